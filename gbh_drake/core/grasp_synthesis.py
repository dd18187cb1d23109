"""Grasp synthesis (paper Sec. 2.3; sign conventions of design.md Sec. 4), all in the mesh frame W.

Frame G is :mod:`gbh_drake.core.gripper`'s: palm centre, +z_G toward the fingertips (approach),
+y_G closing axis from the L rod toward the straight rod; n1 = -z_G, n2 = +y_G. For a contact
point h of a structure (c, v), let u = unit(c - h) (from the material at h toward the hole):

* parallel grasp: the bar (n2 = +y_G) along +v or -v (two groups), the approach +z_G = -n1 along
  u, so the palm is on h's side and palm, rods and bar enclose the material at h; p_M at c;
* vertical grasp: the straight finger (+z_G, p4 -> p2) along +v or -v (v's sign is arbitrary, so
  both), snapped to the ground normal (with the same sign) when within acos(p_theta) of it;
  n2 = +y_G along u, so the straight rod is in the hole and the L rod outside the material;
  p2 at q_m from eqs. 1-3.

Poses are the gripper at the grasp pose, fully open (the pose the arm must reach; the collision
count uses the same opening). Every function is vectorised over the contact points.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.core.geometry import frame_coordinates, poses_from_axes, unit
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import PARALLEL, VERTICAL, GraspCandidate, HangingStructure

_SIGNS = (1.0, -1.0)


def parallel_grasp_poses(
    structure: HangingStructure, gripper: HookGripperGeometry = HOOK_GRIPPER
) -> tuple[np.ndarray, np.ndarray]:
    """Parallel grasps of one structure: poses X_WG (2K, 4, 4) and their contact points (2K, 3).

    Rows are the K hit points with the bar along +v, then the K with the bar along -v.
    """
    c, H = structure.c, structure.H
    p_GM = gripper.keypoints_G()["pM"]
    X, hs = [], []
    for s in _SIGNS:
        y = np.broadcast_to(s * structure.v, H.shape)
        z = unit(c - H)
        X_WG = poses_from_axes(y, z, np.zeros_like(H))
        X_WG[:, :3, 3] = c - X_WG[:, :3, :3] @ p_GM  # p_M at c
        X.append(X_WG)
        hs.append(H)
    return np.concatenate(X), np.concatenate(hs)


def finger_directions(v: np.ndarray, ground_normal: np.ndarray, p_theta: float) -> np.ndarray:
    """(2, 3) straight-finger directions +z_G for a vertical grasp: +v and -v, each replaced by
    +-ground_normal (same side) when |cos(theta)| > p_theta (paper's ground rule)."""
    z = np.stack([s * v for s in _SIGNS])
    cos = z @ ground_normal
    snap = np.abs(cos) > p_theta
    z[snap] = np.sign(cos[snap])[:, None] * ground_normal
    return z


def vertical_grasp_poses(
    structure: HangingStructure,
    points: np.ndarray,
    params: GbhParams,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
) -> tuple[np.ndarray, np.ndarray]:
    """Vertical grasps of one structure: poses X_WG (2K, 4, 4) and contact points (2K, 3).

    ``points`` (N, 3) is the object's point cloud in W. For each h (eqs. 1-3):
    q1 = h + d1 u; Q = the points in the gripper's plane (|x_G| <= slice_half_width) between the
    open rods when the straight rod passes q1, within one finger length of q1 along the finger
    (farther points cannot be caged), plus h itself; q_f = argmax over Q of (q - q1) . z;
    q2 = its projection on the line q1 + t z; q_m = q2 + d2 z; p2 (open gripper) at q_m.
    z is the straight finger's direction, i.e. v or the ground normal after the ground rule.
    """
    c, H = structure.c, structure.H
    g = unit(np.asarray(params.ground_normal, dtype=float))
    lf, q_open = gripper.finger_length, gripper.q_open
    p_G2 = gripper.keypoints_G(q_open)["p2"]
    u = unit(c - H)
    q1 = H + params.d1 * u
    X, hs = [], []
    for z_dir in finger_directions(structure.v, g, params.p_theta):
        z = np.broadcast_to(z_dir, H.shape)
        X_WG = poses_from_axes(u, z, q1)  # frame at q1, axes of the grasp
        x, y, zc = frame_coordinates(X_WG, points)  # points in the frame at q1
        in_Q = np.abs(x) <= params.slice_half_width
        in_Q &= (y <= 0.0) & (y >= -2.0 * q_open) & (np.abs(zc) <= lf)
        height = np.where(in_Q, zc, -np.inf).max(axis=1)
        height = np.maximum(height, -params.d1 * np.sum(u * z, axis=1))  # h itself is in Q
        q_m = q1 + (height + params.d2)[:, None] * z
        X_WG[:, :3, 3] = q_m - X_WG[:, :3, :3] @ p_G2
        X.append(X_WG)
        hs.append(H)
    return np.concatenate(X), np.concatenate(hs)


def synthesize_grasps(
    structures: list[HangingStructure],
    points: np.ndarray,
    params: GbhParams,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
) -> list[GraspCandidate]:
    """All parallel and vertical grasps of ``structures`` (unscored, N_c not yet counted).

    ``points`` (N, 3) is the object's point cloud in W (used by the vertical grasps' Q).
    """
    out: list[GraspCandidate] = []
    for i, s in enumerate(structures):
        if len(s.H) == 0:
            continue
        batches = []
        if params.parallel_grasps:
            batches.append((PARALLEL, *parallel_grasp_poses(s, gripper)))
        if params.vertical_grasps:
            batches.append((VERTICAL, *vertical_grasp_poses(s, points, params, gripper)))
        for kind, X, hs in batches:
            out.extend(GraspCandidate(X[j], kind, i, s, hs[j]) for j in range(len(X)))
    return out
