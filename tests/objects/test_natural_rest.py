"""Each object of the set declares its natural rest (the ``natural`` protocol) with a one-line
reason, and that rest is one of its stable resting poses; a rest other than the modelled one
turns the object as declared."""

import numpy as np
import pytest
import trimesh

from gbh_drake.objects import list_objects, make_object, sample_resting_pose, stable_poses
from gbh_drake.objects.catalog import natural_rest
from gbh_drake.objects.spec import NaturalRest


def test_every_object_declares_a_natural_rest_with_a_reason():
    for name in list_objects():
        rest = natural_rest(name)
        assert rest is not None, name
        assert rest.reason.strip() and "\n" not in rest.reason and len(rest.reason) < 100, name
    with pytest.raises(KeyError, match="unknown object"):
        natural_rest("no_such_thing")


@pytest.mark.parametrize("name", list_objects())
def test_the_natural_rest_is_a_stable_pose_of_the_object(name):
    spec = make_object(name)
    assert spec.natural_rest == natural_rest(name)
    down = spec.natural_rest.R.T @ np.array([0.0, 0.0, -1.0])  # the face it stands on, in O
    near = stable_poses(spec.mesh).nearest(down)
    assert near.normal_O @ down > np.cos(np.radians(1.0)), name
    assert near.tilt_margin_deg > 10.0, name  # it stands firmly (the least: ball, 14.9 deg)


def test_a_rest_is_checked_and_turns_the_object():
    with pytest.raises(ValueError, match="one-line reason"):
        NaturalRest((0.0, 0.0, 0.0), "")
    with pytest.raises(ValueError, match="3 finite numbers"):
        NaturalRest((0.0, 0.0), "flat")
    box = trimesh.creation.box((0.1, 0.2, 0.3))
    box.apply_translation([0.0, 0.0, 0.15])
    on_side = NaturalRest((90.0, 0.0, 0.0), "on its long side")  # O's y turned up
    X, info = sample_resting_pose(box, np.random.default_rng(0), yaw_range=(0.0, 0.0),
                                  orientation="natural", R_rest=on_side.R)
    np.testing.assert_allclose(X[:3, :3], on_side.R, atol=1e-12)
    assert X[2, 3] == pytest.approx(0.1) and info["stable"]  # the 0.2 m side is now the height
    np.testing.assert_allclose(np.abs(info["normal_O"]), [0.0, 1.0, 0.0], atol=1e-9)
