"""Mesh clean-up after fusion: drop the small disconnected fragments (noise, stray voxels)."""

from __future__ import annotations

import numpy as np

from gbh_drake.core.lazy import lazy_module

trimesh = lazy_module("trimesh")


def keep_large_components(mesh: trimesh.Trimesh, min_fraction: float) -> trimesh.Trimesh:
    """``mesh`` without the connected parts (sharing edges) whose triangle count is below
    ``min_fraction`` times that of the largest part."""
    if len(mesh.faces) == 0:
        return mesh
    labels = trimesh.graph.connected_component_labels(mesh.face_adjacency,
                                                      node_count=len(mesh.faces))
    counts = np.bincount(labels)
    keep = counts[labels] >= min_fraction * counts.max()
    cleaned = mesh.copy()
    cleaned.update_faces(keep)
    cleaned.remove_unreferenced_vertices()
    return cleaned
