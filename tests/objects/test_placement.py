"""Resting placement: any mesh, any origin and orientation, into frame O resting on z = 0."""

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from mesh_shapes import filled_mug, random_rotation

from gbh_drake.objects import lift_to_table, lowest_point_z, make_object, rest_on_table
from gbh_drake.objects.mass import mass_properties_detailed

MUG = filled_mug()  # base on z = 0, cup axis = z, handle on +x


def _yaw(theta):
    return trimesh.transformations.rotation_matrix(theta, (0, 0, 1))


def test_mesh_centred_at_its_middle_rests_on_the_table():
    """The reported problem: a mesh whose origin is its middle started half inside the table."""
    centred = MUG.copy()
    centred.apply_translation(-centred.bounds.mean(axis=0))
    assert centred.bounds[0, 2] < -0.04
    placed = rest_on_table(centred)
    assert placed.mesh.bounds[0, 2] == 0.0
    # Centred on its footprint, the cup's base: the cup axis is O's z axis again.
    np.testing.assert_allclose(placed.mesh.bounds[:, :2], MUG.bounds[:, :2], atol=1e-9)
    np.testing.assert_allclose(placed.to_O(centred.vertices), placed.mesh.vertices, atol=1e-12)
    assert placed.stable and placed.warnings == []
    assert placed.tilt_margin_deg > 20


@settings(max_examples=30, deadline=None)
@given(offset=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3),
       yaw=st.floats(-np.pi, np.pi))
def test_any_origin_and_yaw_keeps_z_up(offset, yaw):
    mesh_F = MUG.copy()
    mesh_F.apply_transform(_yaw(yaw))
    mesh_F.apply_translation(offset)
    com_F = mass_properties_detailed(mesh_F, 1.0).com
    placed = rest_on_table(mesh_F, com=com_F)
    np.testing.assert_allclose(placed.X_OF[:3, :3], np.eye(3), atol=1e-12)  # "keep"
    assert placed.mesh.vertices[:, 2].min() == pytest.approx(0.0, abs=1e-12)
    # The footprint is the cup's base disc, centred on the axis.
    np.testing.assert_allclose(placed.footprint_O.mean(axis=0), 0.0, atol=2e-3)
    np.testing.assert_allclose(placed.to_O(com_F), placed.com_O, atol=1e-12)
    assert placed.stable


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_any_orientation_is_turned_onto_a_stable_face(seed):
    rng = np.random.default_rng(seed)
    box_O = trimesh.creation.box((0.05, 0.08, 0.12))
    T = np.eye(4)
    T[:3, :3] = random_rotation(rng)
    T[:3, 3] = rng.uniform(-0.5, 0.5, 3)
    mesh_F = box_O.copy()
    mesh_F.apply_transform(T)
    placed = rest_on_table(mesh_F, com=T[:3, 3], orientation="nearest_stable")
    assert placed.mesh.vertices[:, 2].min() == pytest.approx(0.0, abs=1e-12)
    assert placed.stable and placed.warnings == []
    # A face down: the box's extents are its sides again (axis aligned up to a yaw).
    assert placed.mesh.extents[2] == pytest.approx(
        min((0.05, 0.08, 0.12), key=lambda s: abs(s - placed.mesh.extents[2])), abs=1e-9)
    np.testing.assert_allclose(placed.com_O[:2], 0.0, atol=1e-9)  # footprint centre = com here
    R = placed.X_OF[:3, :3]
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)


def test_ground_truth_moves_with_the_transform():
    spec = make_object("mug_classic")
    (handle,) = spec.hangable_parts
    T = _yaw(0.7)
    T[:3, 3] = (0.3, -0.2, -0.05)  # a file whose origin is elsewhere (and yawed)
    mesh_F = spec.mesh.copy()
    mesh_F.apply_transform(T)
    center_F = T[:3, :3] @ handle.center_O + T[:3, 3]
    axis_F = T[:3, :3] @ handle.axis_O
    placed = rest_on_table(mesh_F)
    center_O = placed.to_O(center_F)
    axis_O = placed.X_OF[:3, :3] @ axis_F
    # Same height, same distance from the cup's axis, same angle to the axis as designed.
    assert center_O[2] == pytest.approx(handle.center_O[2], abs=1e-9)
    assert np.linalg.norm(center_O[:2]) == pytest.approx(np.linalg.norm(handle.center_O[:2]),
                                                         abs=1e-3)
    np.testing.assert_allclose(axis_O, _yaw(0.7)[:3, :3] @ handle.axis_O, atol=1e-12)


def test_scanned_pan_whose_bottom_dips_below_its_origin():
    """The reported problem: a scanned pan rested 3 mm inside the table."""
    pan = make_object("frying_pan").mesh.copy()
    rng = np.random.default_rng(0)
    noisy = pan.vertices + rng.normal(0.0, 0.0005, pan.vertices.shape)
    noisy[np.argmin(noisy[:, 2]), 2] = -0.003
    scan = trimesh.Trimesh(noisy, pan.faces, process=False)
    placed = rest_on_table(scan, orientation="nearest_stable")
    assert placed.mesh.vertices[:, 2].min() == 0.0
    tilt = np.degrees(np.arccos(placed.X_OF[2, 2]))
    assert tilt < 3.0  # levelled onto its base, not turned over
    assert placed.stable


def test_tilted_mesh_warns_and_can_be_levelled():
    box = trimesh.creation.box((0.05, 0.05, 0.2))
    box.apply_transform(trimesh.transformations.rotation_matrix(np.radians(30), (1, 0, 0)))
    kept = rest_on_table(box)
    assert not kept.stable and kept.tilt_margin_deg < 0
    (warning,) = kept.warnings
    assert warning.startswith("not stable as given (z up): it will tip over when released, ")
    assert "orientation: nearest_stable" in warning
    assert kept.settle_deg == pytest.approx(30.0, abs=0.01)
    levelled = rest_on_table(box, orientation="nearest_stable")
    assert levelled.stable and levelled.warnings == []
    assert levelled.pose is not None
    np.testing.assert_allclose(levelled.mesh.extents, (0.05, 0.05, 0.2), atol=1e-9)


def test_slightly_tilted_mesh_settles():
    box = trimesh.creation.box((0.1, 0.1, 0.05))
    box.apply_transform(trimesh.transformations.rotation_matrix(np.radians(2.0), (1, 0, 0)))
    kept = rest_on_table(box)
    (warning,) = kept.warnings
    assert warning.startswith("rests 2.0 deg off its nearest stable face (z up as given)")
    assert kept.mesh.vertices[:, 2].min() == 0.0


def test_center_options():
    com = mass_properties_detailed(MUG, 1.0).com
    by_com = rest_on_table(MUG, center="com")
    np.testing.assert_allclose(by_com.com_O[:2], 0.0, atol=1e-12)
    assert com[0] > 0.001  # the handle pulls the com off the cup's axis
    by_box = rest_on_table(MUG, center="bbox")
    lo, hi = by_box.mesh.bounds
    np.testing.assert_allclose((lo + hi)[:2], 0.0, atol=1e-12)
    with pytest.raises(ValueError, match="center"):
        rest_on_table(MUG, center="middle")
    with pytest.raises(ValueError, match="orientation"):
        rest_on_table(MUG, orientation="upside_down")


def test_most_probable_orientation_lays_the_mug_on_its_side():
    placed = rest_on_table(make_object("mug_classic").mesh, orientation="most_probable")
    assert abs(placed.pose.normal_O[2]) < 0.2
    assert placed.mesh.vertices[:, 2].min() == pytest.approx(0.0, abs=1e-12)
    assert placed.mesh.extents[2] < 0.1  # lying


def test_point_contact_is_not_stable():
    octahedron = trimesh.Trimesh(np.vstack([np.eye(3), -np.eye(3)]) * 0.05,
                                 [[0, 1, 2], [1, 3, 2], [3, 4, 2], [4, 0, 2],
                                  [1, 0, 5], [3, 1, 5], [4, 3, 5], [0, 4, 5]])
    octahedron.fix_normals()
    placed = rest_on_table(octahedron)
    assert len(placed.footprint_O) == 1  # on its tip
    np.testing.assert_allclose(placed.footprint_O[0], 0.0, atol=1e-12)
    assert placed.tilt_margin_deg == 0.0 and not placed.stable
    assert placed.warnings[0].startswith("not stable as given")
    assert placed.settle_deg == pytest.approx(np.degrees(np.arccos(1 / np.sqrt(3))), abs=0.01)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), z=st.floats(-0.1, 0.5))
def test_lift_to_table_puts_the_lowest_point_at_the_height(seed, z):
    rng = np.random.default_rng(seed)
    X = np.eye(4)
    X[:3, :3] = random_rotation(rng)
    X[:3, 3] = rng.uniform(-1, 1, 3)
    lifted = lift_to_table(MUG, X, z_table=z)
    assert lowest_point_z(MUG, lifted) == pytest.approx(z, abs=1e-12)
    np.testing.assert_array_equal(lifted[:3], np.vstack([X[:2], lifted[2:3]])[:3])
    np.testing.assert_array_equal(lifted[:3, :3], X[:3, :3])
