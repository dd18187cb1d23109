"""A pick: approach above the grasp, descend, close the hook, lift, carry and hold.

Waypoints are solved by IK on straight gripper offsets along the approach direction; the arm
moves between them with joint-space cubic segments (collision-free paths between arbitrary poses
are the planner's job, not this module's).
"""

from dataclasses import dataclass, field

import numpy as np
from pydrake.math import RigidTransform

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.planning.ik import solve_gripper_ik
from gbh_drake.planning.trajectories import MotionScript


@dataclass
class PickParams:
    """How a chosen grasp is executed. Distances in metres, durations in seconds. (No
    ``from __future__ import annotations`` in this module: yaml_load_typed needs real types.)"""

    approach_distance: float = 0.10
    """Pre-grasp offset back along the approach direction (+z_G reversed)."""
    lift_height: float = 0.15
    """Height the gripper rises (world +z) after closing."""
    carry_offset: list[float] = field(default_factory=lambda: [0.0, 0.2, 0.0])
    """Displacement (W) of the carry after the lift, e.g. to a drop-off spot; zeros: no carry."""
    settle_time: float = 0.3
    """Time the robot waits at home before moving (0: start at once)."""
    hold_time: float = 1.0
    """Time the object is held still at the end (does it stay caged?)."""


def pick_script(station, plant_context, X_WG: RigidTransform,
                params: PickParams | None = None) -> MotionScript | None:
    """The motion that picks with the gripper at ``X_WG``; None when a waypoint has no IK.

    ``plant_context`` gives the state IK holds fixed (the object where it lies)."""
    params = params or PickParams()
    plant = station.plant
    G = plant.GetFrameByName("G", station.gripper)
    approach_W = X_WG.rotation().col(2)  # +z_G: from the palm toward the fingertips
    X_pre = RigidTransform(X_WG.rotation(), X_WG.translation() - params.approach_distance * approach_W)
    X_lift = RigidTransform(X_WG.rotation(), X_WG.translation() + [0.0, 0.0, params.lift_height])
    X_carry = RigidTransform(X_WG.rotation(), X_lift.translation() + np.asarray(params.carry_offset))
    q = station.q_home
    waypoints = []
    for X in (X_pre, X_WG, X_lift, X_carry):
        q = solve_gripper_ik(plant, plant_context, station.arm, G, X, q)
        if q is None:
            return None
        waypoints.append(q)
    q_pre, q_grasp, q_lift, q_carry = waypoints
    script = MotionScript().start(station.q_home, HOOK_GRIPPER.q_open)
    if params.settle_time > 0:
        script.hold(params.settle_time, "settle")
    script.move_arm(q_pre, "approach").move_arm(q_grasp, "descend")
    script.move_fingers(HOOK_GRIPPER.q_closed, "close")
    script.move_arm(q_lift, "lift")
    if np.any(params.carry_offset):
        script.move_arm(q_carry, "carry")
    return script.hold(params.hold_time, "hold")
