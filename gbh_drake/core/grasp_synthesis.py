"""Grasp synthesis (paper Sec. 2.3; sign conventions of design.md Sec. 4), all in the mesh frame W.

Frame G is :mod:`gbh_drake.core.gripper`'s: palm centre, +z_G toward the fingertips (approach),
+y_G closing axis from the L rod toward the straight rod; n1 = -z_G, n2 = +y_G. For a contact
point h of a structure (c, v), let u = unit(c - h) (from the material at h toward the hole):

* parallel grasp: the bar (n2 = +y_G) along +v or -v (two groups), the approach +z_G = -n1 along
  u, so the palm is on h's side and palm, rods and bar enclose the material at h; c on the bar's
  centre line, with the caged material centred between the rods (see below);
* vertical grasp: the straight finger (+z_G, p4 -> p2) along +v or -v (v's sign is arbitrary, so
  both), snapped to the ground normal (with the same sign) when within acos(p_theta) of it;
  n2 = +y_G along u, so the straight rod is in the hole and the L rod outside the material;
  the bar beyond q_f of eqs. 1-3 (see below).

Poses are the gripper at the grasp pose, fully open (the pose the arm must reach; the collision
count uses the same opening). Every function is vectorised over the contact points.

**Our rods have thickness; the paper's points do not.** The paper's keypoints are points of
rods of no thickness: p2 is the straight finger's tip, p_M the middle of the gap between the
bar's tip p1 and p2, and the gripper closes when p1 meets p2. Ours are the rods' centre lines
(gripper.py): the bar (8 mm square) is centred on z_G = l_f, so its inner face, the side that
faces the palm, is at z_G = l_f - rod_width/2; the loop closes at q_closed, where the bar's tip
meets the straight rod's inner face. Taken literally, the paper's placements put material where
our rods go when they close, and the fingers stop on it (measured on the object set at rest on
a table: 149 of the 150 ranked grasps met material before closing, at 17.2-39.8 mm instead of
q_closed = 17 mm: pinches, not cages), so we read them as "the material inside the closed
loop" and place the rods accordingly:

* vertical: the paper puts p2 on q_m = q_2 + d2 v (q_2: the farthest caged point q_f projected on
  the straight rod's line). With d2 = 0 that puts the bar's centre line on q_f, half the bar in
  the material. We put the bar's *inner face* ``cage_clearance`` beyond q_f and add the paper's
  d2 on top: p2 = q_2 + (rod_width/2 + cage_clearance + d2) z, where z is the straight finger's
  direction (d2 = 0 for 10 views, 0.005 for one view, as in the paper). These grasps close about
  the straight rod (the arm follows the fingers; collision.py), so the straight rod, placed
  d1 = 1 cm from h inside the hole, stays there and the caged material must fit between it and
  the closed L rod: it may reach 2 q_closed - rod_width - (d1 - rod_width/2) = 20 mm from h.
* parallel: the paper puts p_M on c. Parallel grasps close symmetrically about G, so the material
  at h, which crosses the loop's plane at c's y_G, would end up under the closed straight rod
  (p_M's y_G is where the closed bar tip meets it). We put c on the bar's centre line midway
  between the rods, p_C = (p2 + p3)/2 = (0, 0, l_f), which stays put while the fingers close:
  the bar passes through the hole (at the open pose its tip is q_open - l_h = 1 cm short of c's
  plane, and it slides in along the hole's axis while closing) and the material at h lies midway
  between the rods, with q_closed - rod_width/2 = 13 mm on each side when closed. Like the
  vertical grasps' q_f, the caged points then fix the last degree of freedom: the gripper slides
  along the bar (the hole's axis, so the bar stays in the hole) until the material between palm
  and bar is centred between the rods (:func:`parallel_grasp_poses`).

Whether the closing motion really stays clear of the material (and of the table) is checked by
counting points in the volume it sweeps (collision.py), not assumed.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.core.geometry import frame_coordinates, poses_from_axes, unit
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import PARALLEL, VERTICAL, GraspCandidate, GraspKind, HangingStructure

_SIGNS = (1.0, -1.0)


def parallel_grasp_poses(
    structure: HangingStructure,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    points: np.ndarray | None = None,
    params: GbhParams | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Parallel grasps of one structure: poses X_WG (2RK, 4, 4) and contact points (2RK, 3).

    Rows are the K hit points with the bar along +v, then the K with the bar along -v, each
    group once per turn of ``params.approach_rotations_deg`` (R of them; the paper's pose is
    the turn 0: approach along unit(c - h)): the approach turned about the bar, so the palm
    swings round the hole and the bar stays in it. c is put on the bar's centre line midway
    between the rods, :func:`parallel_anchor_G` (module docstring). With ``points`` (N, 3, the
    object's point cloud in W), each pose then slides along the bar (the hole's axis) so that
    the caged material is centred between the rods:
    Q = the points in the gripper's plane (|x_G| <= ``params.slice_half_width``) between the
    palm and the bar's inner face (0 <= z_G <= l_f - rod_width/2) and between the open rods
    (|y_G| <= q_open), plus h; G moves along y_G by the midpoint of Q's extent in y_G, at most
    the closed loop's half width q_closed - rod_width/2. (Every point of that slab is either in
    the closed loop's hole or where a closing rod goes, so centring Q is what keeps the rods off
    it; c is found on a segment from one contact point, not on the material's mid-plane: on the
    headphones' 24 mm band it is 3 mm off, and the 26 mm loop then closes on the band.)
    """
    c, H = structure.c, structure.H
    params = GbhParams() if params is None else params
    p_GC = parallel_anchor_G(gripper)
    X, hs = [], []
    for s in _SIGNS:
        y = np.broadcast_to(s * structure.v, H.shape)
        for angle in params.approach_rotations_deg:
            turn = np.radians(angle)
            z = rotated_about(unit(c - H), y, turn)
            X_WG = poses_from_axes(y, z, np.zeros_like(H))
            X_WG[:, :3, 3] = c - X_WG[:, :3, :3] @ p_GC  # (p2 + p3) / 2 at c
            X.append(X_WG)
            hs.append(c + rotated_about(H - c, y, turn))  # the material the turned loop cages
    X_WG = np.concatenate(X)
    if points is not None and len(points):
        X_WG[:, :3, 3] += _centring_shift(X_WG, points, params, gripper)[:, None] * X_WG[:, :3, 1]
    return X_WG, np.concatenate(hs)


def _centring_shift(X_WG: np.ndarray, points: np.ndarray, params: GbhParams,
                    gripper: HookGripperGeometry) -> np.ndarray:
    """(M,) metres along y_G that centre the caged points Q of each parallel grasp X_WG (M, 4, 4)
    between the rods (see :func:`parallel_grasp_poses`); h, at y_G = 0, is always in Q."""
    r = 0.5 * gripper.rod_width
    x, y, z = frame_coordinates(X_WG.astype(np.float32), np.asarray(points, dtype=np.float32))
    in_Q = np.abs(x) <= params.slice_half_width
    in_Q &= (z >= 0.0) & (z <= gripper.finger_length - r) & (np.abs(y) <= gripper.q_open)
    lo = np.minimum(np.where(in_Q, y, np.inf).min(axis=1), 0.0)
    hi = np.maximum(np.where(in_Q, y, -np.inf).max(axis=1), 0.0)
    limit = gripper.q_closed - r
    target, low = parallel_window_G(gripper)
    return np.clip(0.5 * (lo + hi) - target, low - target, limit - target)


def parallel_window_G(gripper: HookGripperGeometry = HOOK_GRIPPER) -> tuple[float, float]:
    """(centre, lower edge) in y_G of where a parallel grasp keeps the caged material: the
    closed loop's hole, centred on G (0, and its edge -(q_closed - rod_width/2)), for the
    paper's bar. A wedge's nose narrows the way down past the bar's tip to the nose's tip
    (:func:`~gbh_drake.core.collision.nose_descent_boxes_G`): the material must then come
    down between the nose and the straight rod *and* end in the closed hole, so the window is
    from the nose's tip (open) to the straight rod's inner face (closed)."""
    edge = gripper.q_closed - 0.5 * gripper.rod_width
    if gripper.bar_nose <= 0.0:
        return 0.0, -edge
    nose_tip = -gripper.q_open + gripper.bar_length + gripper.bar_nose
    return 0.5 * (nose_tip + edge), nose_tip


def parallel_anchor_G(gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(3,) the point of G that a parallel grasp puts on the hanging position c: the middle of
    the fingertips, (p2 + p3) / 2 = (0, 0, l_f), on the bar's centre line midway between the rods
    at every opening (module docstring: why not the paper's p_M)."""
    p = gripper.keypoints_G()
    return 0.5 * (p["p2"] + p["p3"])


def vertical_tip_offset(params: GbhParams, gripper: HookGripperGeometry = HOOK_GRIPPER) -> float:
    """Metres along the straight finger from q_2 (the farthest caged point's projection) to p2
    (the straight rod's tip on the bar's centre line): the bar's half width, so that its inner
    face clears q_f, plus ``cage_clearance`` plus the paper's d2."""
    return 0.5 * gripper.rod_width + params.cage_clearance + params.d2


def rotated_about(vectors: np.ndarray, axes: np.ndarray, angle: float) -> np.ndarray:
    """``vectors`` (n, 3) turned by ``angle`` (rad, right-handed) about the unit ``axes`` (n, 3)
    (Rodrigues' formula)."""
    if angle == 0.0:
        return np.array(vectors, dtype=float)
    k = unit(np.broadcast_to(axes, np.shape(vectors)))
    v = np.asarray(vectors, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    return v * c + np.cross(k, v) * s + k * np.sum(k * v, axis=1, keepdims=True) * (1.0 - c)


def finger_directions(v: np.ndarray, ground_normal: np.ndarray, p_theta: float,
                      snap_tilt_max_deg: float = 0.0) -> np.ndarray:
    """(2 or more, 3) straight-finger directions +z_G for a vertical grasp: +v and -v, each
    replaced by +-ground_normal (same side) when |cos(theta)| > p_theta (paper's ground rule);
    a direction that is not replaced but lies within ``snap_tilt_max_deg`` of +-ground_normal
    is kept and the ground normal (same side) added after it (beyond the paper: both tried)."""
    z = np.stack([s * v for s in _SIGNS])
    cos = z @ ground_normal
    snap = np.abs(cos) > p_theta
    z[snap] = np.sign(cos[snap])[:, None] * ground_normal
    also = ~snap & (np.abs(cos) > np.cos(np.radians(snap_tilt_max_deg))) & (snap_tilt_max_deg > 0)
    extra = [np.sign(cos[i]) * ground_normal for i in np.flatnonzero(also)]
    return np.concatenate([z, np.reshape(extra, (-1, 3))]) if extra else z


def vertical_grasp_poses(
    structure: HangingStructure,
    points: np.ndarray,
    params: GbhParams,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
) -> tuple[np.ndarray, np.ndarray]:
    """Vertical grasps of one structure: poses X_WG (FRK, 4, 4) and contact points (FRK, 3), for
    the F finger directions of :func:`finger_directions` and the R turns of
    ``params.approach_rotations_deg`` about the straight finger (the L rod and the bar swing
    round the straight rod in the hole; turn 0 is the paper's pose, n2 along unit(c - h)).

    ``points`` (N, 3) is the object's point cloud in W. For each h (eqs. 1-3):
    q1 = h + d1 u (``d1_centred``: d1 no more than |c - h|); Q = the points in the gripper's
    plane (|x_G| <= slice_half_width) between the open rods when the straight rod passes q1,
    within one finger length of q1 along the finger (farther points cannot be caged), plus h
    itself; q_f = argmax over Q of (q - q1) . z;
    q2 = its projection on the line q1 + t z; p2 (open gripper) at q2 + t_2 z with
    t_2 = :func:`vertical_tip_offset` (rod_width/2 + cage_clearance + d2; the paper's q_m is
    t_2 = d2, see the module docstring). z is the straight finger's direction, i.e. v or the
    ground normal after the ground rule.
    """
    c, H = structure.c, structure.H
    g = unit(np.asarray(params.ground_normal, dtype=float))
    lf, q_open = gripper.finger_length, gripper.q_open
    p_G2 = gripper.keypoints_G(q_open)["p2"]
    u = unit(c - H)
    d1 = np.full(len(H), params.d1)
    if params.d1_centred:  # no farther than the hole's centre, at least half a rod from h
        d1 = np.clip(np.linalg.norm(c - H, axis=1), 0.5 * gripper.rod_width, params.d1)
    q1 = H + d1[:, None] * u
    points32 = np.asarray(points, dtype=np.float32)
    X, hs = [], []
    directions = finger_directions(structure.v, g, params.p_theta, params.snap_tilt_max_deg)
    for z_dir, angle in ((d, a) for d in directions for a in params.approach_rotations_deg):
        z = np.broadcast_to(z_dir, H.shape)
        y_dir = u if angle == 0 else \
            rotated_about(u - np.sum(u * z, axis=1, keepdims=True) * z, z, np.radians(angle))
        X_WG = poses_from_axes(y_dir, z, q1)  # frame at q1, axes of the grasp
        # Points in the frame at q1 (float32: half the memory traffic, ~1e-7 relative error).
        x, y, zc = frame_coordinates(X_WG.astype(np.float32), points32)
        in_Q = np.abs(x) <= params.slice_half_width
        in_Q &= (y <= 0.0) & (y >= -2.0 * q_open) & (np.abs(zc) <= lf)
        height = np.where(in_Q, zc, -np.inf).max(axis=1)
        height = np.maximum(height, -d1 * np.sum(u * z, axis=1))  # h itself is in Q
        q_m = q1 + (height + vertical_tip_offset(params, gripper))[:, None] * z
        X_WG[:, :3, 3] = q_m - X_WG[:, :3, :3] @ p_G2
        X.append(X_WG)
        hs.append(q1 + rotated_about(H - q1, z, np.radians(angle)))  # what the turned L rod cages
    return np.concatenate(X), np.concatenate(hs)


def synthesize_grasps(
    structures: list[HangingStructure],
    points: np.ndarray,
    params: GbhParams,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
) -> list[GraspCandidate]:
    """All parallel and vertical grasps of ``structures`` (unscored, N_c not yet counted).

    ``points`` (N, 3) is the object's point cloud in W (used by the grasps' caged points Q).
    """
    out: list[GraspCandidate] = []
    for i, s in enumerate(structures):
        if len(s.H) == 0:
            continue
        batches = []
        if params.parallel_grasps:
            batches.append((PARALLEL, *parallel_grasp_poses(s, gripper, points, params)))
        if params.vertical_grasps:
            batches.append((VERTICAL, *vertical_grasp_poses(s, points, params, gripper)))
        # Rows are groups (bar sign or finger direction) x turns x the K contact points.
        turns = np.repeat(np.asarray(params.approach_rotations_deg, dtype=float), len(s.H))
        for kind, X, hs in batches:
            turn = np.resize(turns, len(X))
            drop = caged_hang_drop(s, hs)
            out.extend(GraspCandidate(X[j], kind, i, s, hs[j], turn_deg=float(turn[j]),
                                      hang_drop=float(drop[j]))
                       for j in range(len(X)))
    return out


def caged_hang_drop(structure: HangingStructure, h: np.ndarray) -> np.ndarray:
    """(n,) metres: the structure's ``hang_drop`` at the hit point nearest each caged point
    ``h`` (n, 3) (a turned grasp cages the material a turn along the rim); zeros when the
    structure has none."""
    drop = np.asarray(structure.hang_drop, dtype=float)
    h = np.asarray(h, dtype=float).reshape(-1, 3)
    if len(drop) != len(structure.H) or len(drop) == 0:
        return np.zeros(len(h))
    nearest = np.argmin(np.linalg.norm(h[:, None] - structure.H[None], axis=2), axis=1)
    return drop[nearest]


def closed_gripper(X_WG: np.ndarray, kind: str, gripper: HookGripperGeometry = HOOK_GRIPPER
                   ) -> tuple[np.ndarray, float]:
    """Where the gripper of the grasp ``kind`` open at X_WG (4, 4) is once closed, and its
    fingers' position (m): a hook closes to the loop's closure, a pinch until the rods touch; a
    vertical grasp (and a scoop) closes about its straight rod, so the hand moves by the
    fingers' travel along +y_G, the others close in place."""
    X_WG = np.asarray(X_WG, dtype=float)
    q_closed = gripper.q_closed if GraspKind(kind).hooks else 0.5 * gripper.rod_width
    shift = gripper.q_open - gripper.q_closed if GraspKind(kind).keeps_straight_rod else 0.0
    return _moved(X_WG, shift * X_WG[:3, 1]), q_closed


def _moved(X: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """A copy of the pose ``X`` (4, 4) translated by ``offset`` (3,)."""
    out = np.array(X, dtype=float)
    out[:3, 3] += offset
    return out
