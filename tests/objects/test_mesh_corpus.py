"""A corpus of bad (and borderline) mesh files: each gets exactly the outcome written next to it.

Refusals raise MeshImportError "<file>: <reason>" with no third-party exception chained (so no
foreign traceback is printed); acceptances return a mesh with exactly the listed warnings.
"""

import logging
import re
import traceback

import numpy as np
import pytest
import trimesh

from gbh_drake.objects import MeshImportError, load_mesh_file, mesh_io

TETRA = "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def _bytes(seed: int, n: int) -> bytes:
    return np.random.default_rng(seed).bytes(n)


def _box_bytes(file_type: str, size=(0.05, 0.08, 0.1)) -> bytes:
    return trimesh.creation.box(size).export(file_type=file_type)


def _ply_with_unused_nan() -> str:
    verts = ["0 0 0", "0.1 0 0", "0 0.1 0", "0 0 0.1", "nan nan nan"]
    faces = ["3 0 2 1", "3 0 1 3", "3 0 3 2", "3 1 2 3"]
    header = ("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
              "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
              "end_header\n")
    return header + "\n".join(verts + faces) + "\n"


def _open_cup_obj() -> bytes:
    cup = trimesh.creation.cylinder(radius=0.04, height=0.1, sections=32)
    top = cup.face_normals[:, 2] > 0.9
    return trimesh.Trimesh(cup.vertices, cup.faces[~top]).export(file_type="obj").encode()


# name -> (file content, expected): ("error", reason regex) or ("ok", warning regexes, checks)
REFUSED = {
    "empty.obj": (b"", "file is empty$"),
    "shopping_list.obj": ("milk\neggs\n", "not a mesh: no triangles found$"),
    "random.stl": (_bytes(1, 1000), "not a mesh: no triangles found$"),
    "random_header.stl": (_bytes(2, 80) + np.uint32(1000).tobytes() + _bytes(3, 150),
                          "not a mesh: no triangles found$"),
    "random.obj": (_bytes(4, 1000), "not a mesh: no triangles found$"),
    "random.ply": (_bytes(5, 1000), r"not a mesh or unparseable \(ValueError: Not a ply file"),
    "random.glb": (_bytes(6, 1000), r"not a mesh or unparseable \(ValueError: incorrect header"),
    "random.off": (_bytes(7, 1000), r"not a mesh or unparseable \(ValueError"),
    "error_page.stl": ("<html><body>404 Not Found</body></html>",
                       "not a mesh: no triangles found$"),
    "truncated.stl": (_box_bytes("stl")[:300], "not a mesh: no triangles found$"),
    "missing_buffer.gltf": ('{"asset": {"version": "2.0"}, "buffers": '
                            '[{"uri": "missing.bin", "byteLength": 100}]}',
                            r"not a mesh or unparseable \(FileNotFoundError"),
    "lines_only.obj": ("v 0 0 0\nv 1 0 0\nl 1 2\n", "not a mesh: no triangles found$"),
    "points_only.ply": ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                        "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
                        "not a mesh: no triangles found$"),
    "index_out_of_range.obj": ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n",
                               r"not a mesh or unparseable \(IndexError"),
    "index_zero.obj": ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
                       "no faces left after removing degenerate ones$"),
    "single_triangle.obj": ("v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 3\n",
                            r"zero volume: the mesh is flat \(convex hull 0 m\^3\)$"),
    "double_sided_triangle.obj": ("v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 3\nf 1 3 2\n",
                                  "zero volume: the mesh is flat"),
    "collinear.obj": ("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 3 2\n",
                      "no faces left after removing degenerate ones$"),
    "repeated_vertex.obj": ("v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n",
                            "no faces left after removing degenerate ones$"),
    "flat_square.obj": ("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n",
                        "zero volume: the mesh is flat"),
    "nan_used.obj": (TETRA.replace("v 0 0 0.1", "v nan 0 0.1"),
                     r"non-finite vertex coordinates \(nan or inf\) on 1 vertices used by faces$"),
    "inf_used.obj": (TETRA.replace("v 0.1 0 0", "v inf 0 0"),
                     r"non-finite vertex coordinates \(nan or inf\) on 1 vertices used by faces$"),
    "astronomical.obj": (TETRA.replace("0.1", "1e30"),
                         r"coordinates reach 1e\+30 m after scale 1 \(limit 10000 m\): not an "
                         r"object; check the file's unit and scale$"),
    "mesh.dae": ("<COLLADA/>", r"unsupported format '\.dae' \(supported: \.obj, \.stl"),
    "no_suffix": (TETRA, r"unsupported format '' \(supported"),
}

ACCEPTED = {
    # name: (content, scale, warnings (regex, in order), checks on the mesh)
    "box.stl": (_box_bytes("stl"), 1.0, [], {"watertight": True, "faces": 12}),
    "box_ascii.stl": (_box_bytes("stl_ascii"), 1.0, [],
                      {"watertight": True, "faces": 12}),
    "box.ply": (_box_bytes("ply"), 1.0, [], {"watertight": True, "faces": 12}),
    "box.off": (_box_bytes("off"), 1.0, [], {"watertight": True, "faces": 12}),
    "box.glb": (_box_bytes("glb"), 1.0, [], {"watertight": True, "faces": 12}),
    "tetra_unused_nan.ply": (_ply_with_unused_nan(), 1.0, [], {"watertight": True, "faces": 4}),
    "tetra_utf16.obj": (TETRA.encode("utf-16"), 1.0, [], {"watertight": True, "faces": 4}),
    "tetra_missing_mtl.obj": ("mtllib nowhere.mtl\nusemtl red\n" + TETRA, 1.0, [],
                              {"watertight": True, "faces": 4}),
    "box_missing_face.obj": (trimesh.Trimesh(trimesh.creation.box((0.1, 0.1, 0.1)).vertices,
                                             trimesh.creation.box((0.1, 0.1, 0.1)).faces[:-1])
                             .export(file_type="obj").encode(), 1.0, [],
                             {"watertight": True, "faces": 12}),
    "open_cup.obj": (_open_cup_obj(), 1.0,
                     [r"^not watertight \(\d+ faces on open or non-manifold edges, 1 body\): "
                      r"mass properties use a voxel fill$"], {"watertight": False}),
    "box_mm.stl": (_box_bytes("stl", size=(50.0, 80.0, 100.0)), 1.0,
                   [r"^largest extent 100 m is implausible for a hand-held object \(1 cm - 1 m\):"
                    r" looks like millimetres: give scale: 0.001 \(then 10 cm\)$"],
                   {"watertight": True}),
    "box_cm.stl": (_box_bytes("stl", size=(5.0, 8.0, 10.0)), 1.0,
                   [r"looks like centimetres: give scale: 0.01 \(then 10 cm\)$"], {}),
    "box_cm_scaled_twice.stl": (_box_bytes("stl", size=(5.0, 8.0, 10.0)), 0.0001,
                                [r"^largest extent 1 mm is implausible .*: looks 100x too small: "
                                 r"give scale: 0.01 \(then 10 cm\)$"], {}),
    "box_metres_ok.stl": (_box_bytes("stl"), 1.0, [], {}),
}


def _write(tmp_path, name, content):
    path = tmp_path / name
    if isinstance(content, str):
        path.write_text(content)
    else:
        path.write_bytes(content)
    return path


def _assert_refused(path, reason, **kw):
    with pytest.raises(MeshImportError) as info:
        load_mesh_file(path, **kw)
    err = info.value
    message = str(err)
    assert message.startswith(f"{path}: "), message
    assert len(message.splitlines()) == 1
    assert re.search(reason, message[len(str(path)) + 2:]), message
    # No third-party traceback: nothing chained or shown as context, our frames only.
    assert err.__cause__ is None
    assert err.__context__ is None or err.__suppress_context__
    printed = "".join(traceback.format_exception(err))
    assert "site-packages" not in printed, printed


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_refused(tmp_path, name, caplog):
    caplog.set_level(logging.DEBUG)
    content, reason = REFUSED[name]
    _assert_refused(_write(tmp_path, name, content), reason)
    # Not even a debug log line carries a third-party traceback.
    assert not [r for r in caplog.records if r.exc_info], caplog.text


@pytest.mark.parametrize("name", sorted(ACCEPTED))
def test_accepted(tmp_path, name, caplog):
    content, scale, expected, checks = ACCEPTED[name]
    path = _write(tmp_path, name, content)
    mesh = load_mesh_file(path, scale=scale)
    warnings = mesh.metadata["gbh_warnings"]
    assert len(warnings) == len(expected), warnings
    for w, pattern in zip(warnings, expected, strict=True):
        assert re.search(pattern, w), w
    if "watertight" in checks:
        assert mesh.is_watertight == checks["watertight"]
    if "faces" in checks:
        assert len(mesh.faces) == checks["faces"]
    assert np.all(np.isfinite(mesh.vertices))
    assert mesh.metadata["source_path"] == str(path)
    logged = [r.getMessage() for r in caplog.records if r.name == mesh_io.__name__]
    assert logged == [f"{path}: {w}" for w in warnings]  # logged with the file's name


def test_missing_file(tmp_path):
    _assert_refused(tmp_path / "nope.obj", "file not found$")


def test_directory(tmp_path):
    (tmp_path / "folder.obj").mkdir()
    _assert_refused(tmp_path / "folder.obj", "is a directory, not a mesh file$")


@pytest.mark.parametrize("scale, reason", [
    (0.0, "scale must be positive and finite, got 0.0$"),
    (-1.0, "scale must be positive and finite, got -1.0$"),
    (float("nan"), "scale must be positive and finite, got nan$"),
    (float("inf"), "scale must be positive and finite, got inf$"),
    ("mm", "scale must be a positive number, got 'mm'$"),
    (None, "scale must be a positive number, got None$"),
])
def test_bad_scale(tmp_path, scale, reason):
    path = _write(tmp_path, "tetra.obj", TETRA)
    _assert_refused(path, reason, scale=scale)


def test_numpy_scale_is_fine(tmp_path):
    path = _write(tmp_path, "tetra.obj", TETRA)
    assert load_mesh_file(path, scale=np.int64(2)).extents.max() == pytest.approx(0.2)


def test_file_size_limit(tmp_path, monkeypatch):
    path = _write(tmp_path, "big.obj", TETRA)
    monkeypatch.setattr(mesh_io, "MAX_FILE_BYTES", 50)
    _assert_refused(path, r"file too large \(70 bytes; limit 50 bytes\): decimate it first")


def test_file_size_limit_checked_before_reading(tmp_path):
    path = tmp_path / "sparse.stl"
    with open(path, "wb") as f:  # a sparse file: no disk used, nothing read
        f.truncate(mesh_io.MAX_FILE_BYTES + 1)
    _assert_refused(path, r"file too large \(512 MiB; limit 512 MiB\)")


def test_face_limit(tmp_path, monkeypatch):
    path = _write(tmp_path, "sphere.stl", trimesh.creation.icosphere(2, 0.05).export(
        file_type="stl"))
    monkeypatch.setattr(mesh_io, "MAX_FACES", 100)
    _assert_refused(path, r"320 triangles \(limit 100\): decimate it first")


def test_huge_mesh_is_decimated_with_a_warning(tmp_path, monkeypatch):
    sphere = trimesh.creation.icosphere(4, 0.05)  # 5120 faces
    path = _write(tmp_path, "sphere.stl", sphere.export(file_type="stl"))
    monkeypatch.setattr(mesh_io, "DECIMATE_ABOVE", 1000)
    mesh = load_mesh_file(path)
    assert len(mesh.faces) <= 1000
    (warning,) = mesh.metadata["gbh_warnings"]
    assert warning.startswith(f"5120 triangles (limit 1000): decimated to {len(mesh.faces)} in ")
    assert mesh.is_watertight
    assert mesh.volume == pytest.approx(sphere.volume, rel=0.02)


def test_constants_are_documented():
    assert mesh_io.DECIMATE_ABOVE == 200_000 and mesh_io.MAX_FACES == 2_000_000
    for name in ("DECIMATE_ABOVE", "MAX_FACES", "MAX_FILE_BYTES", "MAX_COORDINATE"):
        assert name in mesh_io.__doc__
