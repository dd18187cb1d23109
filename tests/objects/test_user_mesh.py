"""A user's mesh file, end to end: import, mass, resting frame O, warnings."""

import numpy as np
import pytest
import trimesh
from mesh_shapes import filled_mug

from gbh_drake.objects import (
    MeshImportError,
    load_mesh_object,
    mass_properties_for,
    prepare_mesh_object,
    sample_resting_pose,
)
from gbh_drake.objects.user_mesh import DEFAULT_MESH_DENSITY


@pytest.fixture
def mug_file_cm_centred(tmp_path):
    """The reported case: a mug in centimetres whose origin is its middle."""
    mug = filled_mug()
    mug.apply_translation(-mug.bounds.mean(axis=0))
    mug.apply_scale(100.0)
    path = tmp_path / "mug_cm.obj"
    mug.export(path)
    return path


def test_centimetre_file_warns_once_with_the_scale_hint(mug_file_cm_centred):
    obj = load_mesh_object(mug_file_cm_centred)
    extent = [w for w in obj.warnings if "largest extent" in w]
    assert extent == [f"{mug_file_cm_centred}: largest extent 13.3 m is implausible for a "
                      f"hand-held object (1 cm - 1 m): looks like centimetres: give scale: 0.01 "
                      f"(then 13.3 cm)"]
    assert all(w.startswith(f"{mug_file_cm_centred}: ") for w in obj.warnings)
    assert len(obj.warnings) == len(set(obj.warnings))


def test_with_scale_and_mass_it_behaves_like_a_real_mug(mug_file_cm_centred):
    obj = load_mesh_object(mug_file_cm_centred, scale=0.01, mass=0.33)
    assert obj.warnings == []
    assert obj.mesh.vertices[:, 2].min() == 0.0  # on the table, not half inside it
    np.testing.assert_allclose(obj.mesh.bounds[:, :2], filled_mug().bounds[:, :2], atol=1e-6)
    props = obj.mass_properties
    assert props.mass == 0.33 and props.method == "exact"
    # Mass properties in O agree with computing them on the placed mesh.
    direct = mass_properties_for(obj.mesh, mass=0.33)
    np.testing.assert_allclose(props.com, direct.com, atol=1e-9)
    np.testing.assert_allclose(props.inertia, direct.inertia, rtol=1e-6, atol=1e-12)
    X_WO, info = sample_resting_pose(obj.mesh, np.random.default_rng(0), (0.5, 0.6),
                                     (-0.07, 0.07), (-np.pi, np.pi), com=props.com)
    assert np.min(obj.mesh.vertices @ X_WO[2, :3] + X_WO[2, 3]) == pytest.approx(0, abs=1e-12)


def test_default_density_flags_the_solid_filled_mug(mug_file_cm_centred):
    obj = load_mesh_object(mug_file_cm_centred, scale=0.01)
    assert obj.mass_properties.density == DEFAULT_MESH_DENSITY
    (warning,) = obj.warnings
    assert "is solid-filled" in warning and "give mass (kg) directly" in warning


def test_rotated_inertia_matches_a_recomputation():
    box = trimesh.creation.box((0.04, 0.06, 0.15))
    box.apply_transform(trimesh.transformations.rotation_matrix(0.4, (1, 1, 0)))
    box.apply_translation((0.2, 0.1, 0.3))
    obj = prepare_mesh_object(box, source="box", density=500.0, orientation="nearest_stable")
    direct = mass_properties_for(obj.mesh, density=500.0)
    assert obj.mass_properties.mass == pytest.approx(direct.mass)
    np.testing.assert_allclose(obj.mass_properties.com, direct.com, atol=1e-12)
    np.testing.assert_allclose(obj.mass_properties.inertia, direct.inertia, rtol=1e-9,
                               atol=1e-15)
    assert obj.placement.stable
    (warning,) = obj.warnings  # a solid box at a density: the solid-filled rule
    assert warning.startswith("box: the mesh is solid-filled")
    np.testing.assert_allclose(obj.placement.to_O(box.vertices), obj.mesh.vertices, atol=1e-12)


def test_unstable_as_given_is_a_warning_naming_the_source():
    box = trimesh.creation.box((0.04, 0.06, 0.15))
    box.apply_transform(trimesh.transformations.rotation_matrix(0.6, (1, 0, 0)))
    obj = prepare_mesh_object(box, source="tilted.stl", mass=0.2)
    (warning,) = obj.warnings
    assert warning.startswith("tilted.stl: not stable as given (z up): it will tip over")


def test_a_random_stable_pose_does_not_warn_about_the_orientation_as_given(tmp_path):
    """With ``random_pose`` (stable) the object starts on one of its stable resting poses, so
    whether it would stand as given is not worth a warning; with a pose it is."""
    from gbh_drake.modeling.object_asset import load_object_asset
    from gbh_drake.scenario.schema import ObjectConfig, RandomRestingPose

    box = trimesh.creation.box((0.04, 0.06, 0.15))
    box.apply_transform(trimesh.transformations.rotation_matrix(0.6, (1, 0, 0)))
    box.export(tmp_path / "tilted.stl")
    posed = load_object_asset(ObjectConfig(mesh="tilted.stl", mass=0.2), tmp_path)
    assert any("not stable as given" in w for w in posed.warnings)
    drawn = load_object_asset(ObjectConfig(mesh="tilted.stl", mass=0.2,
                                           random_pose=RandomRestingPose()), tmp_path)
    assert not any("stable as given" in w for w in drawn.warnings)
    kept = load_object_asset(ObjectConfig(mesh="tilted.stl", mass=0.2,
                                          random_pose=RandomRestingPose(stable=False)), tmp_path)
    assert any("not stable as given" in w for w in kept.warnings)


def test_mass_and_density_together_are_refused():
    with pytest.raises(ValueError, match="either mass or density"):
        prepare_mesh_object(filled_mug(), source="x", mass=0.3, density=600.0)


def test_bad_file_raises_mesh_import_error(tmp_path):
    path = tmp_path / "nothing.stl"
    path.write_bytes(b"\0" * 200)
    with pytest.raises(MeshImportError, match=str(path)):
        load_mesh_object(path)
