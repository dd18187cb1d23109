"""Collision checking by point counting (paper Sec. 2.3): N_c = object points inside the gripper.

The solid model is :meth:`HookGripperGeometry.inside_solid_model` (hand, rods and bar boxes in
G). Counting is batched: the G coordinates of every point for a chunk of poses are computed as
(chunk, N) arrays (broadcast multiply-adds, :func:`frame_coordinates`), and the box tests run on
those arrays. :func:`ground_penetration` checks the same solid model against the supporting plane.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.core.geometry import frame_coordinates
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry

#: Points x poses processed per chunk (bounds the temporary (chunk, N) arrays to ~50 MB).
_CHUNK_POINTS = 2_000_000


def count_points_in_gripper(
    points_W: np.ndarray,
    X_WG: np.ndarray,
    q: float | None = None,
    margin: float = 0.0,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
) -> np.ndarray:
    """N_c (M,) int: how many of ``points_W`` (N, 3, metres in W) lie inside the gripper's solid
    model (boxes grown by ``margin`` metres) at each pose ``X_WG`` (M, 4, 4) with finger position
    ``q`` (metres; default fully open)."""
    # float32 halves the memory traffic; its ~1e-7 relative error is far below any tolerance.
    X = np.asarray(X_WG, dtype=np.float32).reshape(-1, 4, 4)
    p = np.asarray(points_W, dtype=np.float32).reshape(-1, 3)
    counts = np.zeros(len(X), dtype=int)
    if len(p) == 0:
        return counts
    step = max(1, _CHUNK_POINTS // len(p))
    for k in range(0, len(X), step):
        x, y, z = frame_coordinates(X[k : k + step], p)
        counts[k : k + step] = gripper.inside_solid_model(x, y, z, q, margin).sum(axis=1)
    return counts


def solid_model_corners_G(q: float | None = None,
                          gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(8 B, 3) corners of the solid model's B boxes in G (metres) at finger position ``q``."""
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    return np.concatenate([np.asarray(b.center) + signs * np.asarray(b.half_extents)
                           for b in gripper.solid_boxes_G(q)])


def ground_penetration(X_WG: np.ndarray, ground_normal: np.ndarray, ground_height: float,
                       gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(M,) metres: how deep the deepest corner of the solid model goes below the plane
    ``ground_normal . p = ground_height`` (W), over the open and the closed gripper at each pose
    X_WG (M, 4, 4). <= 0: the gripper stays clear of the plane. (Boxes are convex and the
    fingers move linearly, so the corners at both openings bound every opening in between.)"""
    X = np.asarray(X_WG, dtype=float).reshape(-1, 4, 4)
    n = np.asarray(ground_normal, dtype=float)
    n = n / np.linalg.norm(n)
    corners = np.concatenate([solid_model_corners_G(gripper.q_open, gripper),
                              solid_model_corners_G(gripper.q_closed, gripper)])
    # Height of each corner along n: n . (R p + t) = (R^T n) . p + n . t
    heights = np.einsum("mij,i,cj->mc", X[:, :3, :3], n, corners) + (X[:, :3, 3] @ n)[:, None]
    return ground_height - heights.min(axis=1)
