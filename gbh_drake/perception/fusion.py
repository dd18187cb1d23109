"""TSDF fusion (Curless and Levoy 1996, as the paper's TSDF Fusion) of depth images into a mesh.

Uses Open3D's ``ScalableTSDFVolume`` (sparse voxel blocks: memory follows the observed surface,
not the workspace); it works in the pinned Open3D 0.19. Only the pixels of the segmented object
and of the table around it are fused (``masked_depths``): rays ending on the table near the object
carve free space around it (on mug_classic, 10 views: 0.58 mm accuracy and 0.994 coverage with
the table, 0.79 and 0.964 without); the table is then cut away (``cap.cut_at_height``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from pydrake.math import RigidTransform

from gbh_drake.core.lazy import lazy_module
from gbh_drake.perception.camera import CameraIntrinsics
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.crop import CropBox
from gbh_drake.perception.depth import image_window

trimesh = lazy_module("trimesh")


@dataclass
class ViewPoints:
    """The valid pixels of several depth images whose points lie in a box, as points in W."""

    p_WQ: np.ndarray
    """(n, 3) float32, m, in W."""
    view: np.ndarray
    """(n,) index of the image each point comes from (non-decreasing)."""
    v: np.ndarray
    """(n,) row of its pixel."""
    u: np.ndarray
    """(n,) column of its pixel."""

    def at_border(self, intrinsics: CameraIntrinsics, keep: np.ndarray, border: int = 1
                  ) -> np.ndarray:
        """Sorted indices of the views in which a point of ``keep`` (n,) bool lies within
        ``border`` pixels of the image's edge."""
        u, v = self.u[keep], self.v[keep]
        edge = ((u < border) | (u >= intrinsics.width - border)
                | (v < border) | (v >= intrinsics.height - border))
        return np.unique(self.view[keep][edge])


def view_points(depths: Sequence[np.ndarray], intrinsics: CameraIntrinsics,
                X_WCs: Sequence[RigidTransform], box: CropBox, stride: int = 1) -> ViewPoints:
    """The points in W of the valid pixels of ``depths`` (h, w) float32 (m), seen from cameras
    at X_WC, that lie inside ``box`` (only the image window that can see the box is read; with
    ``stride`` > 1 only every stride-th row and column of it). Single precision (about 0.1 um
    at 1 m): this runs over every pixel near the object."""
    parts = []
    lower = np.asarray(box.lower_W, dtype=np.float32)
    upper = np.asarray(box.upper_W, dtype=np.float32)
    for i, (depth, X_WC) in enumerate(zip(depths, X_WCs, strict=True)):
        rows, cols, z_min, z_max = image_window(box.corners(), intrinsics, X_WC)
        d = depth[rows, cols][::stride, ::stride]
        with np.errstate(invalid="ignore"):
            v, u = np.nonzero((d > max(z_min, 0.0)) & (d <= z_max))  # no 0, inf or nan
        z = d[v, u].astype(np.float32)
        v = v * stride + (rows.start or 0)
        u = u * stride + (cols.start or 0)
        # Through the pixel's centre (u + 0.5, v + 0.5): see ``CameraIntrinsics``.
        cx, cy = intrinsics.open3d_principal_point()
        x = (u.astype(np.float32) - np.float32(cx)) * (z / np.float32(intrinsics.fx))
        y = (v.astype(np.float32) - np.float32(cy)) * (z / np.float32(intrinsics.fy))
        R = X_WC.rotation().matrix().astype(np.float32)
        t = X_WC.translation().astype(np.float32)
        p = [R[k, 0] * x + R[k, 1] * y + R[k, 2] * z + t[k] for k in range(3)]
        inside = ((p[0] >= lower[0]) & (p[0] <= upper[0]) & (p[1] >= lower[1])
                  & (p[1] <= upper[1]) & (p[2] >= lower[2]) & (p[2] <= upper[2]))
        p_WQ = np.empty((np.count_nonzero(inside), 3), dtype=np.float32)
        for k in range(3):
            p_WQ[:, k] = p[k][inside]
        parts.append((p_WQ, np.full(len(p_WQ), i, np.int32), v[inside], u[inside]))
    if not parts:
        return ViewPoints(np.zeros((0, 3), np.float32),
                          *(np.zeros(0, np.int64) for _ in range(3)))
    return ViewPoints(*(np.concatenate(column) for column in zip(*parts, strict=True)))


def masked_depths(depths: Sequence[np.ndarray], points: ViewPoints, keep: np.ndarray
                  ) -> list[np.ndarray]:
    """Copies of ``depths`` holding only the pixels of ``points`` selected by ``keep`` (n,)
    bool; every other pixel is 0 (no measurement)."""
    masked = [np.zeros(d.shape, dtype=np.float32) for d in depths]
    bounds = np.searchsorted(points.view, np.arange(len(depths) + 1))  # points are by view
    for i, (depth, out) in enumerate(zip(depths, masked, strict=True)):
        mine = slice(bounds[i], bounds[i + 1])
        v, u = points.v[mine][keep[mine]], points.u[mine][keep[mine]]
        out[v, u] = depth[v, u]
    return masked


def integrate(depths: Sequence[np.ndarray], intrinsics: CameraIntrinsics,
              X_WCs: Sequence[RigidTransform], config: ScanConfig) -> trimesh.Trimesh:
    """The TSDF of the depth images (m; 0 = no measurement) from cameras at X_WC, as a mesh
    in W (marching cubes, not cleaned)."""
    from gbh_drake.core.o3d import open3d
    o3d = open3d()  # lazy: see gbh_drake.core.o3d
    volume = o3d.pipelines.integration.ScalableTSDFVolume(
        voxel_length=config.voxel_size, sdf_trunc=config.sdf_trunc,
        color_type=o3d.pipelines.integration.TSDFVolumeColorType.NoColor)
    K = o3d.camera.PinholeCameraIntrinsic(intrinsics.width, intrinsics.height, intrinsics.fx,
                                          intrinsics.fy, *intrinsics.open3d_principal_point())
    color = o3d.geometry.Image(np.zeros((intrinsics.height, intrinsics.width, 3), np.uint8))
    for depth, X_WC in zip(depths, X_WCs, strict=True):
        rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
            color, o3d.geometry.Image(np.ascontiguousarray(depth, dtype=np.float32)),
            depth_scale=1.0, depth_trunc=config.depth_max, convert_rgb_to_intensity=False)
        volume.integrate(rgbd, K, X_WC.inverse().GetAsMatrix4())  # extrinsic: X_CW
    mesh = volume.extract_triangle_mesh()
    return trimesh.Trimesh(np.asarray(mesh.vertices), np.asarray(mesh.triangles))
