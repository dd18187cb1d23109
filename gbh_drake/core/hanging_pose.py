"""Where an object ends up when it hangs from a hook point: for lift heights and placing.

A hooked object swings until its centre of mass is straight below the point it hangs from. Its
lowest point then drops by more than its resting extent below the hook: a teapot hooked by its
handle tips nose-down. These estimates use what the robot knows (the scanned points and their
centroid), not the object's true mesh.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.core.geometry import unit


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
