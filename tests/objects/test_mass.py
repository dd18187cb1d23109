"""mass_properties: exact for closed bodies, a voxel fill otherwise."""

import numpy as np
import pytest
import trimesh

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
