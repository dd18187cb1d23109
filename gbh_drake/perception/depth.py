"""Depth images to 3-D points: back-projection through the pinhole model, then into W."""

from __future__ import annotations

import numpy as np
from pydrake.math import RigidTransform

from gbh_drake.perception.camera import CameraIntrinsics


def valid_depth(depth: np.ndarray) -> np.ndarray:
    """Mask (h, w) of pixels that hold a measurement (finite and positive)."""
    return np.isfinite(depth) & (depth > 0)


def backproject(u: np.ndarray, v: np.ndarray, z: np.ndarray,
                intrinsics: CameraIntrinsics) -> np.ndarray:
    """p_CQ (3, ...), metres, in camera frame C, of pixels at column u, row v with depth z
    (coordinates first: each is a contiguous array). The ray goes through the pixel's centre,
    (u + 0.5, v + 0.5) in Drake's convention (see ``CameraIntrinsics``)."""
    return np.stack([(u + 0.5 - intrinsics.cx) * z / intrinsics.fx,
                     (v + 0.5 - intrinsics.cy) * z / intrinsics.fy, z])


def points_C(depth: np.ndarray, intrinsics: CameraIntrinsics) -> np.ndarray:
    """p_CQ (3, h, w) of every pixel Q of ``depth`` (invalid pixels give 0, nan or inf)."""
    v, u = np.indices(depth.shape, dtype=np.float64)
    return backproject(u, v, depth.astype(np.float64), intrinsics)


def image_window(p_WQ: np.ndarray, intrinsics: CameraIntrinsics, X_WC: RigidTransform
                 ) -> tuple[slice, slice, float, float]:
    """(rows, columns, z_min, z_max): the smallest image window and depth range (m) that hold
    the points p_WQ (n, 3), e.g. a box's corners; the whole image if one is behind the camera."""
    p_CQ = X_WC.inverse().multiply(np.asarray(p_WQ, dtype=float).T).T
    z_min, z_max = p_CQ[:, 2].min(), p_CQ[:, 2].max()
    if z_min <= 0:
        return slice(0, intrinsics.height), slice(0, intrinsics.width), 0.0, z_max
    # Pixel coordinates of the points (pixel u, v is centred at u + 0.5, v + 0.5).
    u = intrinsics.fx * p_CQ[:, 0] / p_CQ[:, 2] + intrinsics.cx - 0.5
    v = intrinsics.fy * p_CQ[:, 1] / p_CQ[:, 2] + intrinsics.cy - 0.5
    u0, u1 = np.clip([np.floor(u.min()), np.ceil(u.max()) + 1], 0, intrinsics.width).astype(int)
    v0, v1 = np.clip([np.floor(v.min()), np.ceil(v.max()) + 1], 0, intrinsics.height).astype(int)
    return slice(v0, v1), slice(u0, u1), z_min, z_max


def valid_points_W(depth: np.ndarray, intrinsics: CameraIntrinsics, X_WC: RigidTransform,
                   window: tuple[slice, slice, float, float] | None = None
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """p_WQ (n, 3) of the valid pixels of ``depth`` seen from camera C at X_WC, with their rows
    v (n,) and columns u (n,) in the image; only those within ``window`` (rows, columns, z_min,
    z_max, as from :func:`image_window`) if given."""
    rows, cols, z_min, z_max = window or (slice(None), slice(None), 0.0, np.inf)
    d = depth[rows, cols]
    v, u = np.nonzero(valid_depth(d) & (d >= z_min) & (d <= z_max))
    v += rows.start or 0
    u += cols.start or 0
    p_CQ = backproject(u.astype(np.float64), v.astype(np.float64),
                       depth[v, u].astype(np.float64), intrinsics)
    # Element-wise, not @: BLAS threads are slower than this for 3x3 on a busy machine.
    R_WC, p_WC = X_WC.rotation().matrix(), X_WC.translation()
    p_WQ = np.stack([R_WC[i, 0] * p_CQ[0] + R_WC[i, 1] * p_CQ[1] + R_WC[i, 2] * p_CQ[2] + p_WC[i]
                     for i in range(3)], axis=-1)
    return p_WQ, v, u
