"""Import a triangle mesh from a file, repair what can be repaired, refuse what cannot.

:func:`load_mesh_file` reads obj/stl/ply/glb/gltf/off with trimesh, merges a scene's geometries
(with their transforms) into one mesh, scales it, and repairs: merges duplicate vertices, drops
degenerate and duplicate faces and unreferenced vertices, fills small (triangle/quad) holes and
makes winding and normals consistent and outward. It raises :class:`MeshImportError` (the message
names the file) for a missing or empty file, something that is not a mesh, non-finite vertices,
or zero/negative volume. A mesh that stays non-watertight is accepted: the reason is appended to
``mesh.metadata["gbh_warnings"]`` (a list of str) and logged. Drake can use such a mesh as a rigid
hydroelastic geometry; its mass properties then come from the voxel fill of
:func:`gbh_drake.objects.mass.mass_properties`.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import trimesh

log = logging.getLogger(__name__)

SUPPORTED_SUFFIXES = (".obj", ".stl", ".ply", ".glb", ".gltf", ".off")
#: Volumes (m^3) at or below this count as zero (a 1 mm cube is 1e-9 m^3).
MIN_VOLUME = 1e-12


class MeshImportError(ValueError):
    """A mesh file that cannot be used; the message names the file and the reason."""


def load_mesh_file(path, scale: float = 1.0) -> trimesh.Trimesh:
    """Load, merge, scale and repair the mesh in ``path`` (see the module docstring).

    ``scale`` multiplies the file's coordinates (e.g. 0.001 for millimetres). Returns a
    trimesh in the file's frame, metres.
    """
    path = Path(path)

    def fail(reason: str) -> MeshImportError:
        return MeshImportError(f"{path}: {reason}")

    if not path.is_file():
        raise fail("file not found")
    if path.stat().st_size == 0:
        raise fail("file is empty")
    suffix = path.suffix.lower()
    if suffix not in SUPPORTED_SUFFIXES:
        raise fail(f"unsupported format {suffix!r} (supported: {', '.join(SUPPORTED_SUFFIXES)})")
    try:
        loaded = trimesh.load(str(path), force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types for garbage input
        raise fail(f"not a mesh or unparseable ({type(exc).__name__}: {exc})") from exc
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise fail("not a mesh: no triangles found")
    vertices = np.asarray(loaded.vertices, dtype=np.float64)
    if not np.all(np.isfinite(vertices)):
        raise fail("non-finite vertex coordinates (nan or inf)")
    if not (np.isfinite(scale) and scale > 0):
        raise fail(f"scale must be positive and finite, got {scale}")
    mesh = trimesh.Trimesh(vertices * scale, np.asarray(loaded.faces), process=False)
    with np.errstate(invalid="ignore", divide="ignore"):  # flat meshes: 0/0 in trimesh
        warnings = _repair(mesh)
        if len(mesh.faces) == 0:
            raise fail("no faces left after removing degenerate ones")
        _check_volume(mesh, fail)
    if warnings:
        for w in warnings:
            log.warning("%s: %s", path, w)
    mesh.metadata["gbh_warnings"] = warnings
    mesh.metadata["source_path"] = str(path)
    return mesh


def _repair(mesh: trimesh.Trimesh) -> list[str]:
    """Repair in place; returns warnings about what could not be repaired."""
    mesh.merge_vertices()
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.update_faces(mesh.unique_faces())
    mesh.remove_unreferenced_vertices()
    if not mesh.is_watertight:
        trimesh.repair.fill_holes(mesh)
    trimesh.repair.fix_normals(mesh)
    warnings = []
    if not mesh.is_watertight:
        n_open = len(trimesh.repair.broken_faces(mesh))
        warnings.append(
            f"not watertight ({n_open} faces on open or non-manifold edges, "
            f"{mesh.body_count} bodies): mass properties use a voxel fill"
        )
    elif not mesh.is_winding_consistent:
        warnings.append("inconsistent winding that could not be fixed")
    return warnings


def _check_volume(mesh: trimesh.Trimesh, fail) -> None:
    """Refuse flat or inside-out meshes."""
    if mesh.is_watertight:
        if mesh.volume <= MIN_VOLUME:
            raise fail(f"zero or negative volume ({mesh.volume:.3g} m^3)")
        return
    try:
        hull_volume = mesh.convex_hull.volume
    except Exception:  # qhull fails on flat or degenerate input
        hull_volume = 0.0
    if hull_volume <= MIN_VOLUME:
        raise fail(f"zero volume: the mesh is flat (convex hull {hull_volume:.3g} m^3)")
