"""How a pinched object turns in the hand: it pivots about the pinch axis (issue 42).

Two pads hold an object against turning about the line through them (the closing axis y_G
through the contacts) only by their torsional friction, which a lever arm of a few centimetres
overcomes: a pinched object swings about that axis until its centre of mass is straight below
it, as a hooked one swings about its hook point (:mod:`gbh_drake.core.hanging_pose`). A tall
bottle pinched below its centre of mass turns over and drags; a mug set down by a regrasp
ends where the swing, not the hand's turn, puts it. So the planner treats a pinch like a hook,
with an axis instead of a point:

* :func:`pinch_swing`: the turn about the axis that brings the CoM below it (its equilibrium)
  and the object's lowest point there, and a bound for any turn about the axis (the scan's
  centroid is not the true CoM, and it swings on the way): every point at its distance from
  the axis straight below it (where the axis is vertical, the points keep their heights);
* :func:`swing_angles` and :func:`swing_drops`: the equilibrium turn of many pinches at once
  and how far the CoM falls in it, for ranking them: a pinch above the centre of mass lets it
  fall least (none), one below it the most (:data:`DROP_STEP`).

Frames: W, z up by default (``up``); metres, radians unless a name says degrees.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gbh_drake.core.geometry import unit

#: m: pinches are ranked by how far the object's centre of mass falls as it swings about the
#: pinch axis, rounded to steps of this: a scan's centroid stands in for the centre of mass, and
#: a hollow object's (a mug's) lies up to about a centimetre from it, so drops within a
#: centimetre are alike (a pinch a few millimetres beside the CoM's vertical is as good as one
#: straight above it).
DROP_STEP = 0.01
#: m: a centre of mass this close to the axis (or an axis this close to vertical, as a sine)
#: exerts no turning torque worth a swing.
_ON_AXIS = 1e-6


@dataclass(frozen=True)
class PinchSwing:
    """How a pinched object turns about the pinch axis. W frame, metres, radians."""

    point_W: np.ndarray
    """(3,) a point on the axis (the pads' midpoint)."""
    axis_W: np.ndarray
    """(3,) the axis (unit: the closing axis y_G)."""
    swing: float
    """The turn about ``axis_W`` (right-handed) that brings the CoM straight below the axis
    (0: already there, on the axis, or the axis vertical)."""
    lowest: float
    """Height (along up) of the lowest point once the object has swung there."""
    lowest_any_turn: float
    """A bound on the lowest point for any turn about the axis."""
    com_W: np.ndarray
    """(3,) where the centre of mass is once the object has swung (below the axis)."""


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    a = unit(np.asarray(axis, dtype=float))
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K


def swing_angles(points_W: np.ndarray, axes_W: np.ndarray, com_W: np.ndarray,
                 up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """(m,) rad, in [-pi, pi]: for pinch axes through ``points_W`` (m, 3) along ``axes_W``
    (m, 3, unit), the turn about each axis that brings ``com_W`` (3,) straight below it (0 where
    the CoM lies on the axis or the axis is vertical)."""
    o = np.asarray(points_W, dtype=float).reshape(-1, 3)
    a = np.asarray(axes_W, dtype=float).reshape(-1, 3)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    up = unit(np.asarray(up, dtype=float))
    v = np.asarray(com_W, dtype=float) - o
    d = v - np.sum(v * a, axis=1, keepdims=True) * a  # the CoM's lever, perpendicular to a
    g = -up - (a @ -up)[:, None] * a  # gravity's direction perpendicular to a
    sin = np.sum(np.cross(d, g) * a, axis=1)
    cos = np.sum(d * g, axis=1)
    still = (np.linalg.norm(d, axis=1) < _ON_AXIS) | (np.linalg.norm(g, axis=1) < _ON_AXIS)
    return np.where(still, 0.0, np.arctan2(sin, cos))


def swing_drops(points_W: np.ndarray, axes_W: np.ndarray, com_W: np.ndarray,
                up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """(m,) m: how far ``com_W`` falls (along up) as the object swings to rest about each pinch
    axis (through ``points_W`` (m, 3) along ``axes_W`` (m, 3)): its lever about the axis times
    the axis' tilt times (1 - cos) of the swing (:func:`swing_angles`): 0 for a pinch straight
    above the CoM, twice the lever for one straight below it."""
    o = np.asarray(points_W, dtype=float).reshape(-1, 3)
    a = np.asarray(axes_W, dtype=float).reshape(-1, 3)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    up = unit(np.asarray(up, dtype=float))
    v = np.asarray(com_W, dtype=float) - o
    lever = np.linalg.norm(v - np.sum(v * a, axis=1, keepdims=True) * a, axis=1)
    tilt = np.sqrt(np.clip(1.0 - (a @ up) ** 2, 0.0, 1.0))
    return lever * tilt * (1.0 - np.cos(swing_angles(o, a, com_W, up)))


def lowest_any_turn(points_W: np.ndarray, point_W: np.ndarray, axis_W: np.ndarray,
                    up=(0.0, 0.0, 1.0)) -> float:
    """Height (along up) below which none of ``points_W`` (n, 3) goes, however the object turns
    about the axis through ``point_W`` along ``axis_W``: each point at its distance from the
    axis, straight below its foot on the axis (as far as the axis' tilt lets it); +inf
    without points."""
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    if len(p) == 0:
        return float("inf")
    a, up = unit(np.asarray(axis_W, dtype=float)), unit(np.asarray(up, dtype=float))
    v = p - np.asarray(point_W, dtype=float)
    along = v @ a
    foot = np.asarray(point_W, dtype=float) + along[:, None] * a
    rho = np.linalg.norm(v - along[:, None] * a, axis=1)
    tilt = np.sqrt(max(0.0, 1.0 - float(a @ up) ** 2))
    return float((foot @ up - rho * tilt).min())


def pinch_swing(points_W: np.ndarray, com_W: np.ndarray, point_W: np.ndarray,
                axis_W: np.ndarray, up=(0.0, 0.0, 1.0)) -> PinchSwing:
    """How the object of scan points ``points_W`` (n, 3) and centre of mass ``com_W`` turns
    when pinched on the axis through ``point_W`` along ``axis_W`` (module docstring)."""
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    o, a = np.asarray(point_W, dtype=float), unit(np.asarray(axis_W, dtype=float))
    up = unit(np.asarray(up, dtype=float))
    swing = float(swing_angles(o[None], a[None], com_W, up)[0])
    R = _rotation(a, swing)
    moved = (p - o) @ R.T + o
    lowest = float((moved @ up).min()) if len(p) else float("inf")
    com = R @ (np.asarray(com_W, dtype=float) - o) + o
    return PinchSwing(o, a, swing, lowest, lowest_any_turn(p, o, a, up), com)
