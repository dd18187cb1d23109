"""Where the robot goes for one grasp, in B: the pre-grasp, the grasp, the closed loop and the
lift, each as the gripper frame G and as the flange ``panda_link8``; the jaw's opening.

The same rules as the simulation's planner (``planning.pick.plan_pick``), without IK (your
robot plans its own motion): the pre-grasp is ``approach_distance`` back along -z_G (the
planner backs off further, up to ``max_approach_distance``, when that pose is not clear of the
object's hull); a vertical grasp closes about its straight rod, so the hand moves by the
fingers' travel along +y_G as they close (a parallel grasp closes in place); the lift raises
the closed gripper along the table's normal until the hanging object, hooked where its
material comes to rest on the loop and turned any way about it, clears the table by
``lift_clearance`` (and the unseen space next to a scan too), within ``min_lift`` and
``max_lift`` (``core.hanging_pose``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from gbh_drake.core.grasp_synthesis import closed_gripper
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.hanging_pose import rest_on_loop
from gbh_drake.core.results import GraspKind


@dataclass
class Waypoints:
    """Poses (4, 4) in B of the gripper frame G at each step of one grasp, and the lift."""

    pre_grasp: np.ndarray
    grasp: np.ndarray
    closed: np.ndarray
    lift: np.ndarray
    lift_height: float
    """m: how far the closed gripper rises along the table's normal."""
    q_open: float
    q_closed: float
    """m: each finger's joint position, open and closed (Franka's width is twice it)."""


def grasp_waypoints(X_BG: np.ndarray, kind: str, points_B: np.ndarray, table, pick, *,
                    unseen_B: np.ndarray | None = None,
                    gripper: HookGripperGeometry = HOOK_GRIPPER) -> Waypoints:
    """The waypoints of the hook grasp ``kind`` with the open gripper at ``X_BG`` (4, 4) on the
    object of scan points ``points_B`` (n, 3; their centroid stands for the centre of mass, as
    in the planner), above ``table`` (a ``TablePlane``), by the rules of ``pick`` (a
    ``PickConfig``); ``unseen_B`` (m, 3): unseen cells next to the scan (a lift keeps them
    clear too)."""
    X_BG = np.asarray(X_BG, dtype=float)
    R, p = X_BG[:3, :3], X_BG[:3, 3]
    approach = R[:, 2]
    up = np.asarray(table.normal_W, dtype=float)
    closed, q_closed = closed_gripper(X_BG, kind, gripper)
    lift = lift_height(closed, X_BG, kind, points_B, table, pick, unseen_B, gripper)
    return Waypoints(_pose(R, p - pick.approach_distance * approach), X_BG.copy(), closed,
                     _pose(R, closed[:3, 3] + lift * up), lift, gripper.q_open, q_closed)


def lift_height(X_closed: np.ndarray, X_BG: np.ndarray, kind: str, points_B: np.ndarray, table,
                pick, unseen_B: np.ndarray | None = None,
                gripper: HookGripperGeometry = HOOK_GRIPPER) -> float:
    """m: the lift of the closed gripper (see the module docstring)."""
    from gbh_drake.planning.pick import unseen_lift

    points = np.asarray(points_B, dtype=float).reshape(-1, 3)
    if len(points) == 0 or not GraspKind(kind).hooks:
        return float(pick.min_lift)
    up = np.asarray(table.normal_W, dtype=float)
    hook_B = X_closed[:3, 3] + gripper.finger_length * X_closed[:3, 2]
    rest = rest_on_loop(points, points.mean(axis=0), X_BG, kind, up, hook_W=hook_B)
    need = pick.lift_clearance + table.height - rest.lowest_any_turn
    if unseen_B is not None and len(unseen_B):
        # unseen_lift measures heights from z = 0 along z: here from the table along its normal.
        down = table.height * up
        rest_on_table = dataclasses.replace(rest, contact_W=rest.contact_W - down)
        need = max(need, unseen_lift(np.asarray(unseen_B) - down, rest_on_table,
                                     pick.lift_clearance))
    return float(np.clip(need, pick.min_lift, pick.max_lift))


def _pose(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    X = np.eye(4)
    X[:3, :3], X[:3, 3] = R, p
    return X
