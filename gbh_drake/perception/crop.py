"""Axis-aligned boxes of W: the workspace bound around the scan target, regions of interest.

The workspace box (``CropBox.workspace``) is a generous bound: nothing outside it is scanned, and
the object is segmented inside it (``gbh_drake.perception.segment``), not cut to it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gbh_drake.core.lazy import lazy_module
from gbh_drake.perception.config import ScanConfig

trimesh = lazy_module("trimesh")


@dataclass(frozen=True)
class CropBox:
    """Box [lower_W, upper_W] (m), axes of W."""

    lower_W: tuple[float, float, float]
    upper_W: tuple[float, float, float]

    @staticmethod
    def around(p_WT, config: ScanConfig, z_min: float | None = None) -> CropBox:
        """The config's crop box centred on target p_WT in x and y; floor ``z_min`` (default
        ``config.crop_z_min``)."""
        x, y = np.asarray(p_WT, dtype=float)[:2]
        h = config.crop_half_size_xy
        floor = config.crop_z_min if z_min is None else z_min
        return CropBox((x - h, y - h, floor), (x + h, y + h, config.crop_z_max))

    @staticmethod
    def workspace(p_WT, config: ScanConfig, table_height: float | None = None) -> CropBox:
        """The workspace box: +-``crop_half_size_xy`` around target p_WT in x and y, from a
        little below the table (at height ``table_height`` (m) under T; unbounded if None) to
        ``crop_z_max`` above it."""
        x, y = np.asarray(p_WT, dtype=float)[:2]
        h = config.crop_half_size_xy
        if table_height is None:
            return CropBox((x - h, y - h, -10.0), (x + h, y + h, 10.0))
        floor = table_height - max(0.05, 2.0 * config.sdf_trunc)
        return CropBox((x - h, y - h, floor), (x + h, y + h, table_height + config.crop_z_max))

    def intersect(self, other: CropBox) -> CropBox:
        """The box common to ``self`` and ``other`` (may be empty: lower above upper)."""
        return CropBox(tuple(np.maximum(self.lower_W, other.lower_W).tolist()),
                       tuple(np.minimum(self.upper_W, other.upper_W).tolist()))

    def corners(self) -> np.ndarray:
        """The 8 corners (8, 3) in W (m)."""
        index = np.indices((2, 2, 2)).reshape(3, -1).T
        return np.where(index == 0, self.lower_W, self.upper_W)

    def contains(self, p_WQ: np.ndarray) -> np.ndarray:
        """Mask (...) of the points p_WQ (..., 3) inside the box."""
        inside = np.ones(p_WQ.shape[:-1], dtype=bool)
        for i in range(3):
            inside &= (p_WQ[..., i] >= self.lower_W[i]) & (p_WQ[..., i] <= self.upper_W[i])
        return inside

    def cut(self, mesh: trimesh.Trimesh) -> trimesh.Trimesh:
        """The triangles of ``mesh`` whose centroid is inside the box (the cut is as ragged as
        the triangles, about a voxel for a fused mesh)."""
        if len(mesh.faces) == 0:
            return mesh
        inside = mesh.copy()
        inside.update_faces(self.contains(mesh.triangles_center))
        inside.remove_unreferenced_vertices()
        return inside
