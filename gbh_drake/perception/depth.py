"""Depth images to 3-D points: back-projection through the pinhole model, then into W."""

from __future__ import annotations

import numpy as np
from pydrake.math import RigidTransform

from gbh_drake.perception.camera import CameraIntrinsics


def valid_depth(depth: np.ndarray) -> np.ndarray:
    """Mask (h, w) of pixels that hold a measurement (finite and positive)."""
    return np.isfinite(depth) & (depth > 0)


def points_C(depth: np.ndarray, intrinsics: CameraIntrinsics) -> np.ndarray:
    """p_CQ (h, w, 3), metres, of every pixel Q in camera frame C (invalid pixels give nan/inf)."""
    v, u = np.indices(depth.shape, dtype=np.float64)
    z = depth.astype(np.float64)
    return np.stack([(u - intrinsics.cx) * z / intrinsics.fx,
                     (v - intrinsics.cy) * z / intrinsics.fy, z], axis=-1)


def points_W(depth: np.ndarray, intrinsics: CameraIntrinsics, X_WC: RigidTransform):
    """p_WQ (h, w, 3) of every pixel (invalid ones hold garbage) and the valid mask (h, w)."""
    valid = valid_depth(depth)
    p_CQ = np.where(valid[..., None], points_C(depth, intrinsics), 0.0)
    R_WC = X_WC.rotation().matrix()
    return p_CQ @ R_WC.T + X_WC.translation(), valid
