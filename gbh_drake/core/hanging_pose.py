"""Where an object ends up when it hangs from a hook point: for lift heights and placing.

A hooked object swings until its centre of mass is straight below the point it hangs from. Its
lowest point then drops by more than its resting extent below the hook: a teapot hooked by its
handle tips nose-down. These estimates use what the robot knows (the scanned points and their
centroid), not the object's true mesh. Hooked material thin enough to pass the closed loop (a
wire, a long handle's bar) slides through it to where the object hangs deepest
(:mod:`gbh_drake.core.sliding`): :func:`rest_on_loop` bounds the hang over every point it can
reach.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from gbh_drake.core.collision import closed_loop_interior_G
from gbh_drake.core.geometry import unit
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.sliding import LoopOpening, MaterialGraph, slide_region

spatial = lazy_module("scipy.spatial")


def hanging_rotation(com_W: np.ndarray, hook_W: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Rotation (3, 3) about ``hook_W`` that brings ``com_W`` straight below it (along -``up``):
    the smallest rotation, or a half turn about a horizontal axis when the CoM is straight above."""
    up = unit(np.asarray(up, dtype=float))
    d = np.asarray(com_W, dtype=float) - np.asarray(hook_W, dtype=float)
    if np.linalg.norm(d) < 1e-9:
        return np.eye(3)
    d = d / np.linalg.norm(d)
    target = -up
    axis = np.cross(d, target)
    s, c = np.linalg.norm(axis), float(np.dot(d, target))
    if s < 1e-9:
        if c > 0:
            return np.eye(3)
        horizontal = np.cross(up, [1.0, 0.0, 0.0])
        if np.linalg.norm(horizontal) < 1e-6:
            horizontal = np.cross(up, [0.0, 1.0, 0.0])
        axis, angle = unit(horizontal), np.pi
    else:
        axis, angle = axis / s, np.arctan2(s, c)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def hanging_lowest_height(points_W: np.ndarray, com_W: np.ndarray, hook_W: np.ndarray,
                          up=(0.0, 0.0, 1.0), *, swings: bool = True) -> float:
    """Height (m, along ``up``) of the lowest of ``points_W`` (n, 3) once the object hangs from
    ``hook_W`` with its CoM ``com_W`` below it (``swings``), or held rigidly (not ``swings``)."""
    up = unit(np.asarray(up, dtype=float))
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    if len(p) == 0:
        return 0.0
    if swings:
        R = hanging_rotation(com_W, hook_W, up)
        p = (p - hook_W) @ R.T + hook_W
    return float((p @ up).min())


def lift_for_clearance(points_W: np.ndarray, com_W: np.ndarray, hook_W: np.ndarray,
                       clearance: float, *, swings: bool = True, ground_height: float = 0.0,
                       up=(0.0, 0.0, 1.0)) -> float:
    """How far (m) the hook must rise so that the hanging object's lowest point is ``clearance``
    above the ground plane (at ``ground_height`` along ``up``).

    A hooked object (``swings``) is bounded for the worst case: whatever way it turns as it
    hangs (a scan's centroid is not its centre of mass, and it swings on the way), no point is
    farther below the hook than its farthest scanned point. Held rigidly, it keeps its pose."""
    up = unit(np.asarray(up, dtype=float))
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    if swings and len(p):
        reach = float(np.linalg.norm(p - np.asarray(hook_W, dtype=float), axis=1).max())
        low = float(np.asarray(hook_W, dtype=float) @ up) - reach
    else:
        low = hanging_lowest_height(p, com_W, hook_W, up, swings=swings)
    return float(ground_height + clearance - low)


#: Half thickness (m, along the loop's normal x_G) of the slab around the closed loop whose scan
#: points count as the caged material: the rods are 8 mm thick, a scan's vertices are sparser.
CAGED_SLAB = 0.01
#: Fewer caged points than this within the rods' thickness: the slab is used instead.
MIN_CAGED_POINTS = 3
#: Below this share of ``up`` in the loop's plane the loop lies flat: the material does not come
#: to rest on one of its sides by sliding down in the plane (it hangs from the hook point).
MIN_IN_PLANE = 0.3


@dataclass(frozen=True)
class LoopRest:
    """Where the hooked material comes to rest on the closed loop once the gripper lifts, and how
    the whole object then hangs, all with the gripper at its closed pose (before the lift)."""

    contact_W: np.ndarray
    """The point (W, m) the object hangs from: the first caged material point to meet the loop's
    inner face, moved there (the hook point when nothing is caged)."""
    drop: float
    """How far (m, along -up) the object sinks relative to the gripper until it rests there."""
    support: str
    """The loop's side it rests on: ``bar``, ``palm``, ``straight_rod``, ``l_rod``, or ``""``
    (no caged material, or the loop lies flat: the hook point)."""
    caged: int
    """How many scan points were taken as caged material (within the rods' thickness of the
    loop's plane, or within :data:`CAGED_SLAB` where a sparse scan has fewer than
    :data:`MIN_CAGED_POINTS` there)."""
    lowest: float
    """Height (m, along up) of the lowest point of the object hanging from ``contact_W`` with
    its centre of mass below it (:func:`hanging_rotation`)."""
    lowest_any_turn: float
    """A bound on that lowest point for any way the object turns about ``contact_W`` (the
    farthest scanned point from it straight below it)."""
    slide: float = 0.0
    """How far (m) the material resting on the loop may slide through it (``material`` given:
    :func:`~gbh_drake.core.sliding.slide_region`): ``lowest`` and ``lowest_any_turn`` are then
    the worst over every point of the scan it can slide to, each hanging from the contact."""
    hang_W: np.ndarray | None = None
    """The scan point (W, m, where it was scanned) the object hangs deepest from (the worst
    hang point, ``lowest_any_turn``'s); None without sliding."""
    slide_points: int = 0
    """How many (thinned) scan points the material can slide to, the caged ones included."""


def rest_on_loop(points_W: np.ndarray, com_W: np.ndarray, X_WG: np.ndarray, kind: str,
                 up=(0.0, 0.0, 1.0), *, hook_W: np.ndarray | None = None,
                 slab: float = CAGED_SLAB, material: MaterialGraph | None = None,
                 gripper: HookGripperGeometry = HOOK_GRIPPER) -> LoopRest:
    """How the object of scan points ``points_W`` (n, 3) and centre of mass ``com_W`` comes to
    rest on the closed loop of a grasp of ``kind`` at ``X_WG`` (4, 4: the open gripper's grasp
    pose; the loop is where it is once closed, :func:`~gbh_drake.core.collision.closed_loop_interior_G`).

    When the gripper rises, the material caged in the loop's hole (the points within ``slab``
    of the loop's plane inside its inner faces) sinks along -``up`` relative to the gripper
    until the first of it meets an inner face: for a top-down hook the bar's upper face. The
    object then hangs from that contact with its CoM below it. Without caged material, or with
    the loop lying flat, it hangs from ``hook_W`` (default: the middle of the bar).

    With ``material`` (:func:`~gbh_drake.core.sliding.material_graph` of the same points), the
    caged material may slide through the closed loop along material thin enough to pass it
    (a wire, a long handle's bar, :func:`~gbh_drake.core.sliding.slide_region`): the object
    may then hang from any point it reaches, each brought to the contact, and both lowest
    points are the worst over them (:attr:`LoopRest.slide`)."""
    up = unit(np.asarray(up, dtype=float))
    X = np.asarray(X_WG, dtype=float)
    R, t = X[:3, :3], X[:3, 3]
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    com = np.asarray(com_W, dtype=float)
    box = closed_loop_interior_G(kind)
    c, h = np.asarray(box.center, dtype=float), np.asarray(box.half_extents, dtype=float)
    if hook_W is None:
        hook_W = R @ np.array([0.0, c[1], HOOK_GRIPPER.finger_length]) + t
    hook_W = np.asarray(hook_W, dtype=float)

    p_G = (p - t) @ R
    in_plane = (np.abs(p_G[:, 1] - c[1]) <= h[1]) & (np.abs(p_G[:, 2] - c[2]) <= h[2])
    # The material over the loop's sides (as thick as the rods); a sparse scan may have too few
    # points there: then those within ``slab`` of the loop's plane.
    inside = in_plane & (np.abs(p_G[:, 0] - c[0]) <= h[0])
    if inside.sum() < MIN_CAGED_POINTS:
        inside = in_plane & (np.abs(p_G[:, 0] - c[0]) <= max(slab, h[0]))
    u = R.T @ up  # up in G; the material moves along -u relative to the gripper
    u_plane = np.array([0.0, u[1], u[2]])
    drop, contact, support = 0.0, hook_W, ""
    if inside.any() and np.linalg.norm(u_plane) >= MIN_IN_PLANE:
        q = p_G[inside]
        # Distance along -up until each point leaves the hole through a side (y or z face).
        sides = []
        for axis, low_name, high_name in ((1, "l_rod", "straight_rod"), (2, "palm", "bar")):
            v = -u[axis]
            if abs(v) < 1e-9:
                sides.append((np.full(len(q), np.inf), ""))
                continue
            face = c[axis] + (h[axis] if v > 0 else -h[axis])
            sides.append(((face - q[:, axis]) / v, high_name if v > 0 else low_name))
        s = np.minimum(sides[0][0], sides[1][0])
        i = int(np.argmin(s))
        drop = float(max(s[i], 0.0))
        support = sides[0][1] if sides[0][0][i] <= sides[1][0][i] else sides[1][1]
        contact = p[inside][i] - drop * up
    moved = p - drop * up
    if len(moved) == 0:
        return LoopRest(contact, drop, support, int(inside.sum()), 0.0, 0.0)
    lowest = hanging_lowest_height(moved, com - drop * up, contact, up)
    reach = float(np.linalg.norm(moved - contact, axis=1).max())
    rest = LoopRest(np.asarray(contact, dtype=float), drop, support, int(inside.sum()),
                    lowest, float(contact @ up) - reach)
    if material is None or not inside.any():
        return rest
    return _slid(rest, p, com, np.flatnonzero(inside), material, up, kind, gripper)


#: At most this many of the points the material can slide to are hung from (evenly strided;
#: the farthest from the caged material always).
MAX_HANG_POINTS = 400


def loop_opening(kind: str, gripper: HookGripperGeometry = HOOK_GRIPPER) -> LoopOpening:
    """The closed loop's inner opening (:class:`~gbh_drake.core.sliding.LoopOpening`) of a
    grasp of ``kind``: :func:`~gbh_drake.core.collision.closed_loop_interior_G`'s box."""
    h = np.asarray(closed_loop_interior_G(kind, gripper).half_extents, dtype=float)
    return LoopOpening(width=2.0 * h[1], length=2.0 * h[2], thickness=2.0 * h[0])


def _slid(rest: LoopRest, p: np.ndarray, com: np.ndarray, caged: np.ndarray,
          material: MaterialGraph, up: np.ndarray, kind: str,
          gripper: HookGripperGeometry) -> LoopRest:
    """``rest`` bounded over every point the caged material ``p[caged]`` can slide to: the
    object hung from each of them brought to ``rest.contact_W`` (CoM below it, and any turn),
    the worst kept. The lowest points are those of the scan's convex hull."""
    region = slide_region(material, caged, loop_opening(kind, gripper))
    hang = material.points[region.reachable]
    start = p[caged].mean(axis=0)
    slide = float(np.linalg.norm(hang - start, axis=1).max()) if len(hang) else 0.0
    if len(hang) > MAX_HANG_POINTS:
        far = int(np.argmax(np.linalg.norm(hang - start, axis=1)))
        keep = np.unique(np.r_[np.linspace(0, len(hang) - 1, MAX_HANG_POINTS).astype(int), far])
        hang = hang[keep]
    hull = _hull_points(p)
    contact_up = float(rest.contact_W @ up)
    # Any turn: the farthest hull point from the hang point, straight below the contact.
    reach = np.linalg.norm(hull[None] - hang[:, None], axis=2).max(axis=1)  # (H,)
    any_turn = contact_up - reach
    # The CoM below the hang point: each hang point brought to the contact.
    lowest = np.array([hanging_lowest_height(hull - q + rest.contact_W, com - q + rest.contact_W,
                                             rest.contact_W, up) for q in hang])
    worst = int(np.argmin(any_turn))
    return dataclasses.replace(
        rest, lowest=float(min(rest.lowest, lowest.min())),
        lowest_any_turn=float(min(rest.lowest_any_turn, any_turn.min())), slide=slide,
        hang_W=hang[worst].copy(), slide_points=int(region.reachable.sum()))


def _hull_points(p: np.ndarray) -> np.ndarray:
    """The vertices of the convex hull of ``p`` (n, 3) (where a linear function, such as a
    height after any rigid motion, has its minimum), or ``p`` when it has no hull."""
    try:
        return p[spatial.ConvexHull(p).vertices]
    except Exception:  # degenerate (flat, too few points): all of them
        return p
