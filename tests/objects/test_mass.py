"""mass_properties: exact for closed bodies, a voxel fill otherwise."""

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

from gbh_drake.objects import make_object, mass_properties
from gbh_drake.objects.mass import mass_properties_detailed


def test_box_is_exact():
    size, density = np.array([0.1, 0.2, 0.3]), 500.0
    box = trimesh.creation.box(size)
    box.apply_translation((1.0, 2.0, 3.0))
    mass, com, inertia = mass_properties(box, density)
    expected_mass = density * size.prod()
    assert mass == pytest.approx(expected_mass)
    np.testing.assert_allclose(com, (1.0, 2.0, 3.0), atol=1e-12)
    a, b, c = size
    expected = expected_mass / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    np.testing.assert_allclose(inertia, expected, rtol=1e-9, atol=1e-12)


def test_box_with_a_small_hole_falls_back_to_voxels_and_stays_close():
    box = trimesh.creation.box((0.1, 0.1, 0.1))
    exact = mass_properties_detailed(box, 1000.0)
    fine = trimesh.Trimesh(*trimesh.remesh.subdivide_to_size(box.vertices, box.faces, 0.002))
    opened = trimesh.Trimesh(fine.vertices, fine.faces[:-1], process=False)
    approx = mass_properties_detailed(opened, 1000.0)
    assert approx.method == "voxel" and exact.method == "exact"
    assert approx.mass == pytest.approx(exact.mass, rel=0.08)
    np.testing.assert_allclose(approx.com, exact.com, atol=2e-3)
    np.testing.assert_allclose(approx.inertia, exact.inertia, rtol=0.15, atol=1e-6)


def test_overlapping_bodies_are_counted_once():
    a = trimesh.creation.box((0.1, 0.1, 0.1))
    b = a.copy()
    b.apply_translation((0.05, 0, 0))
    both = trimesh.util.concatenate([a, b])
    props = mass_properties_detailed(both, 1000.0)
    assert props.method == "voxel"
    assert props.mass == pytest.approx(1000.0 * 0.15 * 0.1 * 0.1, rel=0.08)


def test_pybullet_mug_has_plausible_mass_properties():
    spec = make_object("pybullet_mug")
    mass, com, inertia = mass_properties(spec.mesh, spec.density)
    assert mass == pytest.approx(0.3, rel=0.01)
    lo, hi = spec.mesh.bounds
    assert np.all(com > lo) and np.all(com < hi)
    assert abs(com[0]) < 1e-3 and com[1] > 0  # symmetric in x, handle on +y
    assert np.all(np.linalg.eigvalsh(inertia) > 0)


def test_rejects_bad_density():
    with pytest.raises(ValueError):
        mass_properties(trimesh.creation.box((1, 1, 1)), 0.0)


def test_mass_given_directly_gives_that_mass():
    from gbh_drake.objects import mass_properties_for

    size = np.array([0.1, 0.2, 0.3])
    box = trimesh.creation.box(size)
    box.apply_translation((0.1, 0.0, 0.15))
    props = mass_properties_for(box, mass=0.5)
    assert props.mass == 0.5 and props.method == "exact"
    assert props.density == pytest.approx(0.5 / size.prod())
    np.testing.assert_allclose(props.com, (0.1, 0.0, 0.15), atol=1e-12)
    a, b, c = size
    expected = 0.5 / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    np.testing.assert_allclose(props.inertia, expected, rtol=1e-9, atol=1e-15)
    by_density = mass_properties_for(box, density=props.density)
    assert by_density.mass == pytest.approx(0.5)
    np.testing.assert_allclose(by_density.inertia, props.inertia, rtol=1e-9)


@settings(max_examples=30, deadline=None)
@given(mass=st.floats(1e-3, 10.0))
def test_mass_given_directly_scales_the_inertia(mass):
    from gbh_drake.objects import mass_properties_for

    mesh = make_object("teacup").mesh
    unit = mass_properties_for(mesh, density=1.0)
    props = mass_properties_for(mesh, mass=mass)
    assert props.mass == mass
    np.testing.assert_allclose(props.inertia, unit.inertia * mass / unit.mass, rtol=1e-9)
    np.testing.assert_array_equal(props.com, unit.com)


def test_mass_given_directly_for_an_open_mesh_uses_the_voxel_fill():
    from gbh_drake.objects import mass_properties_for

    props = mass_properties_for(make_object("pybullet_mug").mesh, mass=0.3)
    assert props.method == "voxel" and props.mass == pytest.approx(0.3)
    assert np.all(np.linalg.eigvalsh(props.inertia) > 0)


@pytest.mark.parametrize("kw", [{}, {"density": 1.0, "mass": 1.0}, {"mass": 0.0},
                                {"mass": -1.0}, {"mass": float("nan")}, {"density": 0.0},
                                {"density": float("inf")}])
def test_mass_properties_for_refuses_bad_arguments(kw):
    from gbh_drake.objects import mass_properties_for

    with pytest.raises(ValueError):
        mass_properties_for(trimesh.creation.box((0.1, 0.1, 0.1)), **kw)
