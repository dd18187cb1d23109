"""Import a triangle mesh from a file, repair what can be repaired, refuse what cannot.

:func:`load_mesh_file` reads obj/stl/ply/glb/gltf/off with trimesh, merges a scene's geometries
(with their transforms) into one mesh, scales it, and repairs: merges duplicate vertices, drops
degenerate and duplicate faces and unreferenced vertices, fills small (triangle/quad) holes and
makes winding and normals consistent and outward.

Every failure raises :class:`MeshImportError` whose message is ``"<file>: <reason>"``; no
exception of a third-party library escapes (their type and message are quoted in the reason and
the original is kept in ``error.detail``, not chained, so no foreign traceback is printed).
Refused:

* a missing path, a directory, an empty file, a file over :data:`MAX_FILE_BYTES`, an unsupported
  suffix, a ``scale`` that is not positive and finite;
* bytes that do not parse as a mesh or hold no triangles (points, lines only), face indices that
  point at missing vertices, more than :data:`MAX_FACES` triangles;
* non-finite (nan/inf) coordinates on vertices that faces use (unused ones are dropped), or
  coordinates beyond :data:`MAX_COORDINATE` metres after ``scale``;
* nothing left after dropping degenerate faces, zero or negative volume (flat, a single triangle).

Accepted with a warning (appended to ``mesh.metadata["gbh_warnings"]``, a list of str without the
file name, and logged with it):

* more than :data:`DECIMATE_ABOVE` triangles: quadric decimation (Open3D) down to that many
  (about 2 s for 300k triangles, 14 s for 1M, measured here);
* a mesh that stays non-watertight: Drake can use it as a rigid hydroelastic geometry; its mass
  properties then come from the voxel fill of :func:`gbh_drake.objects.mass.mass_properties`;
* a largest extent outside 1 cm - 1 m, with a ``scale`` hint
  (:func:`gbh_drake.objects.plausibility.extent_warnings`).
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
import warnings as pywarnings
from pathlib import Path

import numpy as np
import trimesh
from scipy.spatial import ConvexHull, QhullError

from gbh_drake.core.arguments import require
from gbh_drake.core.ranges import is_number
from gbh_drake.objects.plausibility import extent_warnings

log = logging.getLogger(__name__)
#: (path, warning) pairs already logged by this process (each load still keeps its warnings in
#: ``mesh.metadata["gbh_warnings"]``, which records and listings read).
_LOGGED: set[tuple[str, str]] = set()

SUPPORTED_SUFFIXES = (".obj", ".stl", ".ply", ".glb", ".gltf", ".off")
#: Volumes at or below this fraction of the cube of the mesh's largest extent count as zero (a
#: 10 cm object: 1e-12 m^3; relative, so that a mesh read at the wrong scale, 0.1 mm across, is
#: refused for its size, with the unit hint, not called flat).
MIN_VOLUME_FRACTION = 1e-9
#: Meshes with more triangles are decimated to this many (with a warning).
DECIMATE_ABOVE = 200_000
#: Meshes with more triangles are refused (decimating them would take minutes).
MAX_FACES = 2_000_000
#: Files larger than this (bytes) are refused before they are read (an ASCII STL of 2M
#: triangles is ~500 MB).
MAX_FILE_BYTES = 512 * 2**20
#: Coordinates (m, after ``scale``) beyond this are refused: not an object at any plausible unit.
MAX_COORDINATE = 1.0e4


@contextlib.contextmanager
def quiet_mesh_warnings():
    """Keeps the object set's and the mesh import's warnings out of the log for a while (they
    are said elsewhere: in a run's summary, in ``gbh objects list``); errors still show."""
    objects_log = logging.getLogger("gbh_drake.objects")
    level = objects_log.level
    objects_log.setLevel(logging.ERROR)
    try:
        yield
    finally:
        objects_log.setLevel(level)


class MeshImportError(ValueError):
    """A mesh file that cannot be used; the message names the file and the reason.

    ``detail`` holds the third-party exception behind it, if any (not chained on purpose)."""

    def __init__(self, message: str, detail: BaseException | None = None):
        super().__init__(message)
        self.detail = detail


def load_mesh_file(path, scale: float = 1.0) -> trimesh.Trimesh:
    """Load, merge, scale and repair the mesh in ``path`` (see the module docstring).

    ``scale`` multiplies the file's coordinates (e.g. 0.001 for millimetres). Returns a
    trimesh in the file's frame, metres, with ``metadata["gbh_warnings"]`` (list of str) and
    ``metadata["source_path"]``. Raises :class:`MeshImportError` (TypeError for a ``path`` that
    is not a path).
    """
    require("load_mesh_file", "path", path, (str, os.PathLike), "a mesh file's path (a str or Path)")
    path = Path(path)

    def fail(reason: str, detail: BaseException | None = None) -> MeshImportError:
        return MeshImportError(f"{path}: {reason}", detail)

    _check_file(path, fail)
    if not is_number(scale):  # ('1' or True would pass float())
        raise fail(f"scale must be a positive number, got {scale!r}")
    scale = float(scale)
    if not (np.isfinite(scale) and scale > 0):
        raise fail(f"scale must be positive and finite, got {scale}")
    loaded = _read(path, fail)
    vertices, faces = _validated_arrays(loaded, fail)
    vertices = vertices * float(scale)
    reach = float(np.max(np.abs(vertices)))
    if reach > MAX_COORDINATE:
        raise fail(f"coordinates reach {reach:.3g} m after scale {scale:g} (limit "
                   f"{MAX_COORDINATE:g} m): not an object; check the file's unit and scale")
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    try:
        with np.errstate(all="ignore"), pywarnings.catch_warnings():  # flat meshes: 0/0
            pywarnings.simplefilter("ignore")
            _clean(mesh)
            warnings: list[str] = []
            if len(mesh.faces) == 0:
                raise fail("no faces left after removing degenerate ones")
            if len(mesh.faces) > DECIMATE_ABOVE:
                warnings.append(_decimate(mesh, DECIMATE_ABOVE))
            warnings += _repair(mesh)
            _check_volume(mesh, fail)
    except MeshImportError:
        raise
    except Exception as exc:  # noqa: BLE001  (trimesh/networkx/open3d on odd input)
        raise fail(f"could not be repaired ({type(exc).__name__}: {exc})", exc) from None
    warnings += extent_warnings(mesh, scale=scale)
    for w in warnings:
        if (str(path), w) not in _LOGGED:  # once per process: a task list loads a mesh often
            _LOGGED.add((str(path), w))
            log.warning("%s: %s", path, w)
    mesh.metadata["gbh_warnings"] = warnings
    mesh.metadata["source_path"] = str(path)
    return mesh


def _check_file(path: Path, fail) -> None:
    """Refuse what is not a readable, supported, reasonably sized file, before reading it."""
    if path.is_dir():
        raise fail("is a directory, not a mesh file")
    if not path.is_file():
        raise fail("file not found")
    size = path.stat().st_size
    if size == 0:
        raise fail("file is empty")
    if size > MAX_FILE_BYTES:
        raise fail(f"file too large ({_bytes(size)}; limit {_bytes(MAX_FILE_BYTES)}): "
                   f"decimate it first (e.g. MeshLab, Blender)")
    suffix = path.suffix.lower()
    if suffix not in SUPPORTED_SUFFIXES:
        raise fail(f"unsupported format {suffix!r} (supported: {', '.join(SUPPORTED_SUFFIXES)})")


def _bytes(n: int) -> str:
    return f"{n / 2**20:.0f} MiB" if n >= 2**20 else f"{n} bytes"


def _read(path: Path, fail) -> trimesh.Trimesh:
    """trimesh's loader, with every exception and warning it raises turned into ours."""
    try:
        with pywarnings.catch_warnings(), np.errstate(all="ignore"):
            pywarnings.simplefilter("ignore")
            loaded = trimesh.load(str(path), force="mesh", process=False)
    except Exception as exc:  # noqa: BLE001  (trimesh raises many types for garbage input)
        raise fail(f"not a mesh or unparseable ({type(exc).__name__}: {exc})", exc) from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise fail("not a mesh: no triangles found")
    return loaded


def _validated_arrays(loaded: trimesh.Trimesh, fail) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices (n, 3) float64, faces (m, 3) int64)``, checked; unused non-finite vertices
    dropped."""
    try:
        vertices = np.asarray(loaded.vertices, dtype=np.float64).reshape(-1, 3)
        faces = np.asarray(loaded.faces).reshape(-1, 3)
    except (TypeError, ValueError) as exc:
        raise fail(f"malformed vertex or face data ({type(exc).__name__}: {exc})", exc) from None
    if not np.issubdtype(faces.dtype, np.integer):
        raise fail("malformed face data (indices are not integers)")
    faces = faces.astype(np.int64)
    bad = (faces < 0) | (faces >= len(vertices))
    if bad.any():
        raise fail(f"{int(bad.any(axis=1).sum())} of {len(faces)} faces refer to missing "
                   f"vertices (indices outside 1..{len(vertices)})")
    if len(faces) > MAX_FACES:
        raise fail(f"{len(faces)} triangles (limit {MAX_FACES}): decimate it first "
                   f"(e.g. MeshLab, Blender)")
    finite = np.all(np.isfinite(vertices), axis=1)
    if not finite.all():
        used = np.zeros(len(vertices), dtype=bool)
        used[faces.ravel()] = True
        n_bad = int((used & ~finite).sum())
        if n_bad:
            raise fail(f"non-finite vertex coordinates (nan or inf) on {n_bad} vertices "
                       f"used by faces")
        keep = np.flatnonzero(finite)
        remap = np.full(len(vertices), -1, dtype=np.int64)
        remap[keep] = np.arange(len(keep))
        vertices, faces = vertices[keep], remap[faces]
    return vertices, faces


def _clean(mesh: trimesh.Trimesh) -> None:
    """Merge duplicate vertices; drop degenerate and duplicate faces and unused vertices."""
    mesh.merge_vertices()
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.update_faces(mesh.unique_faces())
    mesh.remove_unreferenced_vertices()


def _decimate(mesh: trimesh.Trimesh, target: int) -> str:
    """Quadric decimation (Open3D) to ``target`` triangles, in place; returns the warning."""
    from gbh_drake.core.simplify import simplified

    n_before, start = len(mesh.faces), time.perf_counter()
    decimated = simplified(mesh, target)
    mesh.vertices, mesh.faces = decimated.vertices, decimated.faces
    _clean(mesh)
    return (f"{n_before} triangles (limit {DECIMATE_ABOVE}): decimated to {len(mesh.faces)} "
            f"in {time.perf_counter() - start:.1f} s")


def _repair(mesh: trimesh.Trimesh) -> list[str]:
    """Repair in place; returns warnings about what could not be repaired."""
    if not mesh.is_watertight:
        trimesh.repair.fill_holes(mesh)
    trimesh.repair.fix_normals(mesh)
    warnings = []
    if not mesh.is_watertight:
        n_open = len(trimesh.repair.broken_faces(mesh))
        warnings.append(
            f"not watertight ({n_open} faces on open or non-manifold edges, "
            f"{mesh.body_count} bod{'y' if mesh.body_count == 1 else 'ies'}): mass "
            "properties use a voxel fill"
        )
    elif not mesh.is_winding_consistent:
        warnings.append("inconsistent winding that could not be fixed")
    return warnings


def _check_volume(mesh: trimesh.Trimesh, fail) -> None:
    """Refuse flat or inside-out meshes (a volume at most :data:`MIN_VOLUME_FRACTION` of the
    largest extent cubed)."""
    min_volume = MIN_VOLUME_FRACTION * float(np.max(mesh.extents)) ** 3
    if mesh.is_watertight:
        if mesh.volume <= min_volume:
            raise fail(f"zero or negative volume ({mesh.volume:.3g} m^3)")
        return
    try:  # scipy directly: trimesh would retry and log qhull's traceback (at debug level)
        hull_volume = float(ConvexHull(np.asarray(mesh.vertices)).volume)
    except (QhullError, ValueError):  # flat or degenerate input
        hull_volume = 0.0
    if hull_volume <= min_volume:
        raise fail(f"zero volume: the mesh is flat (convex hull {hull_volume:.3g} m^3)")
