"""The object set: watertight single bodies of the designed genus, placement, mass, sizes."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull, Delaunay

from gbh_drake.objects import list_objects, make_object, mass_properties
from gbh_drake.objects.catalog import _BUILDERS

PROCEDURAL = sorted(_BUILDERS)


def test_set_composition(specs):
    names = list_objects()
    assert names == sorted(names)
    hangable = [n for n in names if not specs[n].is_control]
    controls = [n for n in names if specs[n].is_control]
    assert len(hangable) >= 15
    assert {"box", "ball", "bottle", "can"} <= set(controls)
    assert "pybullet_mug" in hangable
    for n in hangable:
        assert specs[n].hangable_parts, n
    for n in controls:
        assert specs[n].hangable_parts == [], n


def test_unknown_name_lists_known_ones():
    with pytest.raises(KeyError, match="mug_classic"):
        make_object("no_such_object")


@pytest.mark.parametrize("name", PROCEDURAL)
def test_watertight_single_body_of_designed_genus(specs, name):
    mesh = specs[name].mesh
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.body_count == 1
    assert mesh.volume > 0
    assert (2 - mesh.euler_number) // 2 == specs[name].genus


@pytest.mark.parametrize("name", list_objects())
def test_rests_on_table_with_com_over_footprint(specs, name):
    spec = specs[name]
    v = np.asarray(spec.mesh.vertices)
    assert v[:, 2].min() == pytest.approx(0.0, abs=1e-9)
    _, com, _ = mass_properties(spec.mesh, spec.density)
    foot = v[v[:, 2] < 1e-3, :2]
    hull = foot[ConvexHull(foot).vertices]
    # Statically stable: the CoM projects inside the contact patch, away from its edge.
    assert Delaunay(hull).find_simplex(com[:2]) >= 0, name
    lo, hi = foot.min(axis=0), foot.max(axis=0)
    assert np.all(np.abs(0.5 * (lo + hi)) < 0.25 * np.ptp(v[:, :2], axis=0).max() + 1e-3)


@pytest.mark.parametrize("name", list_objects())
def test_realistic_mass_size_and_budget(specs, name):
    spec = specs[name]
    mass, _, inertia = mass_properties(spec.mesh, spec.density)
    assert 0.03 <= mass <= 0.8, (name, mass)
    assert np.all(np.linalg.eigvalsh(inertia) > 0)
    assert 0.04 < spec.mesh.extents.max() < 0.45
    assert len(spec.mesh.faces) < 10_000
    assert len(spec.rgba) == 4 and all(0 <= c <= 1 for c in spec.rgba)
    assert spec.description


def test_parameters_change_the_object():
    small, large = make_object("mug_classic"), make_object("mug_classic", radius=0.045)
    assert large.mesh.extents[1] > small.mesh.extents[1]
    assert large.mesh.is_watertight and large.mesh.body_count == 1


@pytest.mark.parametrize(("name", "params", "message"), [
    (None, {}, "make_object(): name: expected an object's name (gbh objects list), got None "
               "(a NoneType)"),
    (["mug_classic"], {}, "make_object(): name: expected an object's name (gbh objects list), "
                          "got ['mug_classic'] (a list)"),
    ("mug_classic", {"radius": "big"}, "make_object(): radius: expected a finite number (or a "
                                       "list of them), got 'big' (a str)"),
    ("mug_classic", {"radius": float("nan")}, "make_object(): radius: expected a finite number "
                                              "(or a list of them), got nan (a float)"),
    ("box", {"size": (0.07, "0.1", 0.16)}, "make_object(): size: expected a finite number (or a "
                                           "list of them), got (0.07, '0.1', 0.16) (a tuple)"),
    ("mug_classic", {"handle": 0.03}, "make_object(): object 'mug_classic' has no parameter "
                                      "'handle'; its parameters: radius, height, wall, reach, "
                                      "mass"),
])
def test_make_object_names_an_argument_of_the_wrong_type(name, params, message):
    with pytest.raises(TypeError) as info:
        make_object(name, **params)
    assert str(info.value) == message
    with pytest.raises(KeyError, match="unknown object 'mug_clasic'"):  # (a name: as before)
        make_object("mug_clasic")


@pytest.mark.parametrize(("name", "params", "message"), [
    ("mug_classic", {"radius": -0.01}, "make_object(): radius: expected positive (a length in m "
                                       "or a mass in kg), got -0.01 (a float)"),
    ("mug_classic", {"mass": 0}, "make_object(): mass: expected positive (a length in m or a mass "
                                 "in kg), got 0 (an int)"),
    ("box", {"size": [0.1, -0.1, 0.1]}, "make_object(): size: expected positive (a length in m or "
                                        "a mass in kg), got [0.1, -0.1, 0.1] (a list)"),
    ("mug_classic", {"wall": 0.05}, "make_object(): 'mug_classic' with wall=0.05 gives no solid "
                                    "(invalid manifold: Error.InvalidConstruction): a wall as "
                                    "thick as the radius, a hole larger than its part?"),
])
def test_make_object_refuses_parameters_that_make_no_object(name, params, message):
    """A negative radius or mass built a sliver with a density of 31 t/m^3 or below zero, and a
    wall thicker than the radius failed inside manifold3d: each is refused naming the
    parameter; an angle may be negative."""
    with pytest.raises(ValueError) as info:
        make_object(name, **params)
    assert str(info.value) == message
    assert make_object("frying_pan", tilt_deg=-12.0).density > 0
