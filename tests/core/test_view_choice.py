"""The next-best-view score of candidate holes (``core.view_choice.hole_view_scores``) on a
ring whose hole is known: a camera that looks through the hole scores, one that sees it
edge-on, from behind an occluder or through material does not."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from gbh_shapes import make_ring

from gbh_drake.core.hangability import detect_hangable_structures
from gbh_drake.core.object_model import prepare_object
from gbh_drake.core.view_choice import hole_view_scores, material_view_scores


def _ring_model(params, extra: trimesh.Trimesh | None = None):
    """The test ring (axis along z_W, centred at the origin) and its structures, with
    ``extra`` geometry added to the model after the structures are found (an occluder)."""
    ring = make_ring()
    model = prepare_object(ring, params)
    structures = detect_hangable_structures(model, params)
    assert structures and abs(structures[0].v[2]) > 0.99
    if extra is not None:
        model = prepare_object(trimesh.util.concatenate([ring, extra]), params)
    return model, structures


def test_a_view_through_the_hole_scores_and_an_edge_on_view_does_not(params):
    model, structures = _ring_model(params)
    cams = np.array([[0.0, 0.0, 0.5],  # along the axis: through the hole
                     [0.35, 0.0, 0.35],  # 45 deg off the axis
                     [0.5, 0.0, 0.0],  # edge-on: 90 deg off the axis
                     [0.0, 0.47, 0.171]])  # 70 deg off the axis
    scores = hole_view_scores(model, structures, cams, max_angle_deg=60.0)
    assert scores[0] > scores[1] > 0.0
    assert scores[2] == 0.0 and scores[3] == 0.0
    # A wider angle admits the 70 deg view; none admits the edge-on one.
    wide = hole_view_scores(model, structures, cams, max_angle_deg=85.0)
    assert wide[3] > 0.0 and wide[2] == 0.0


def test_an_occluded_view_does_not_score(params):
    """A plate between the camera and the ring blocks the line of sight to c."""
    plate = trimesh.creation.box((0.2, 0.2, 0.004),
                                 trimesh.transformations.translation_matrix((0, 0, 0.2)))
    model, structures = _ring_model(params, plate)
    above, below = np.array([[0.0, 0.0, 0.5]]), np.array([[0.0, 0.0, -0.5]])
    assert hole_view_scores(model, structures, above)[0] == 0.0  # blocked before c
    assert hole_view_scores(model, structures, below)[0] == 0.0  # blocked beyond c
    free_model, _ = _ring_model(params)
    assert hole_view_scores(free_model, structures, below)[0] > 0.0


def test_no_structures_no_score(params):
    model, _ = _ring_model(params)
    np.testing.assert_array_equal(hole_view_scores(model, [], np.ones((3, 3))), np.zeros(3))


# --- The material round the holes (``material_view_scores``) ---------------------------------


def test_the_material_score_is_the_seen_share_of_the_material_round_the_hole(params):
    """With nothing in the way, the ring's material round its hole is seen from above as from
    below (the ring is symmetric), each camera sees part of it and never all of it; a plate
    above the ring hides all of it from a camera above and none from one below."""
    model, structures = _ring_model(params)
    above, below = np.array([[0.0, 0.0, 0.5]]), np.array([[0.0, 0.0, -0.5]])
    up, down = (material_view_scores(model, structures, cam) for cam in (above, below))
    assert 0.0 < up[0] < sum(s.m for s in structures)
    assert up[0] == pytest.approx(down[0], abs=0.05)
    plate = trimesh.creation.box((0.2, 0.2, 0.004),
                                 trimesh.transformations.translation_matrix((0, 0, 0.2)))
    blocked, _ = _ring_model(params, plate)
    assert material_view_scores(blocked, structures, above)[0] == 0.0
    assert material_view_scores(blocked, structures, below)[0] == pytest.approx(down[0], abs=0.05)


def test_the_material_score_prefers_the_side_the_handle_is_on(params, mug):
    """The mug's handle (at +x): a camera on the handle's side sees its material, one on the
    far side sees it through the cup's body only where it looks past it."""
    model = prepare_object(mug, params)
    structures = [s for s in detect_hangable_structures(model, params) if s.c[0] > 0.04]
    assert structures
    cams = np.array([[0.5, 0.0, 0.3], [-0.5, 0.0, 0.3]])
    near, far = material_view_scores(model, structures, cams)
    assert near > 2.0 * far


def test_no_structures_no_material_score(params):
    model, _ = _ring_model(params)
    np.testing.assert_array_equal(material_view_scores(model, [], np.ones((3, 3))), np.zeros(3))
