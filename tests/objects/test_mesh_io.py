"""load_mesh_file: repairs what it can, refuses bad files with the file's name in the message."""

import numpy as np
import pytest
import trimesh

from gbh_drake.objects import MeshImportError, load_mesh_file
from gbh_drake.objects.real import pybullet_mug_path


def _raises_naming(path, match):
    with pytest.raises(MeshImportError, match=match) as info:
        load_mesh_file(path)
    assert str(path) in str(info.value)


def test_missing_file(tmp_path):
    _raises_naming(tmp_path / "nope.obj", "not found")


def test_empty_file(tmp_path):
    path = tmp_path / "empty.obj"
    path.write_bytes(b"")
    _raises_naming(path, "empty")


@pytest.mark.parametrize("suffix", [".obj", ".stl", ".ply", ".off", ".glb"])
def test_text_that_is_not_a_mesh(tmp_path, suffix):
    path = tmp_path / f"notes{suffix}"
    path.write_text("this is a shopping list, not a mesh\nmilk\neggs\n")
    _raises_naming(path, "not a mesh")


def test_unsupported_suffix(tmp_path):
    path = tmp_path / "mesh.dae"
    path.write_text("<COLLADA/>")
    _raises_naming(path, "unsupported")


def test_flat_mesh_has_zero_volume(tmp_path):
    path = tmp_path / "flat.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n")
    _raises_naming(path, "zero volume")


def test_a_body_read_at_a_tiny_scale_is_not_called_flat(tmp_path):
    """A 10 cm box at scale 0.001 (a metres file given as millimetres) is 0.1 mm across and
    1e-12 m^3: it loads, so that the size check can refuse it with the unit hint."""
    path = tmp_path / "box.obj"
    trimesh.creation.box((0.1, 0.1, 0.1)).export(path)
    mesh = load_mesh_file(path, scale=0.001)
    assert mesh.volume == pytest.approx(1e-12)
    flat = tmp_path / "flat.obj"  # still flat at any scale
    flat.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1e-10\n"
                    "f 1 2 3\nf 1 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n")
    with pytest.raises(MeshImportError, match="zero"):
        load_mesh_file(flat, scale=0.001)


def test_non_finite_vertices(tmp_path):
    path = tmp_path / "nan.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n")
    _raises_naming(path, "non-finite")


def test_repairs_inverted_split_box_and_scales(tmp_path):
    box = trimesh.creation.box((10.0, 20.0, 30.0))  # millimetres
    unmerged = trimesh.Trimesh(box.vertices[box.faces].reshape(-1, 3),
                               np.arange(36).reshape(-1, 3)[:, ::-1], process=False)
    degenerate = trimesh.Trimesh(np.vstack([unmerged.vertices, [[0, 0, 0]] * 3]),
                                 np.vstack([unmerged.faces, [[36, 37, 38]]]), process=False)
    path = tmp_path / "box.stl"
    degenerate.export(path)
    mesh = load_mesh_file(path, scale=0.001)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(6e-6)
    assert len(mesh.faces) == 12
    assert mesh.metadata["gbh_warnings"] == []


def test_scene_is_merged(tmp_path):
    a = trimesh.creation.box((0.1, 0.1, 0.1))
    b = trimesh.creation.icosphere(radius=0.05)
    b.apply_translation((0.3, 0, 0))
    path = tmp_path / "two.glb"
    trimesh.Scene([a, b]).export(path)
    mesh = load_mesh_file(path)
    assert mesh.body_count == 2
    assert mesh.bounds[1, 0] == pytest.approx(0.35, abs=1e-6)


def test_open_mesh_is_accepted_with_a_warning():
    mesh = load_mesh_file(pybullet_mug_path())
    assert not mesh.is_watertight
    assert any("not watertight" in w for w in mesh.metadata["gbh_warnings"])


def test_a_meshs_warning_is_logged_once_per_process_and_kept_by_every_load(tmp_path, caplog):
    """An experiment's task list loads a mesh several times: the log says it once, and each
    load still carries the warning (records and listings read it)."""
    import shutil

    path = tmp_path / "mug.obj"  # a path of its own: not logged by another test before
    shutil.copy(pybullet_mug_path(), path)
    caplog.set_level("WARNING", logger="gbh_drake.objects.mesh_io")
    meshes = [load_mesh_file(path) for _ in range(3)]
    logged = [r for r in caplog.records if "not watertight" in r.getMessage()]
    assert len(logged) == 1 and str(path) in logged[0].getMessage()
    assert all(any("not watertight" in w for w in m.metadata["gbh_warnings"]) for m in meshes)


@pytest.mark.parametrize("path", [None, 3, b"/x.obj"])
def test_a_path_that_is_not_a_path_is_named(path):
    from gbh_drake.objects import load_mesh_object

    for load, name in ((load_mesh_file, "load_mesh_file"), (load_mesh_object, "load_mesh_object")):
        with pytest.raises(TypeError, match=rf"^{name}\(\): path: expected a mesh file's path \(a "
                                            r"str or Path\), got "):
            load(path)


@pytest.mark.parametrize("scale", ["1", True, None])
def test_a_scale_that_is_not_a_number_is_refused(tmp_path, scale):
    path = tmp_path / "box.obj"
    trimesh.creation.box((0.05, 0.05, 0.05)).export(path)
    with pytest.raises(MeshImportError, match=f"box.obj: scale must be a positive number, got "
                                              f"{scale!r}"):
        load_mesh_file(path, scale=scale)


@pytest.mark.parametrize("kwargs", [{"density": "600"}, {"mass": "0.3"}])
def test_a_density_or_mass_that_is_not_a_number_is_named(tmp_path, kwargs):
    from gbh_drake.objects import load_mesh_object

    path = tmp_path / "box.obj"
    trimesh.creation.box((0.05, 0.05, 0.05)).export(path)
    (name,) = kwargs
    with pytest.raises(TypeError, match=rf"^mass_properties_for\(\): {name}: expected a number, "
                                        rf"got '{kwargs[name]}' \(a str\)"):
        load_mesh_object(path, **kwargs)
