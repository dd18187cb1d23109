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
    hold_time: float = 1.0
    """Time the object is held still at the end (does it stay caged?)."""

    def check(self) -> None:
        """Raises ``ValueError`` naming the first field that cannot work."""
        problems = [
            ("approach_distance", self.approach_distance >= 0, "must be >= 0"),
            ("lift_height", self.lift_height > 0, "must be positive"),
            ("carry_offset", len(self.carry_offset) == 3, "needs 3 coordinates (m)"),
            ("hold_time", self.hold_time > 0, "must be positive"),
        ]
        for name, ok, message in problems:
            if not ok:
                raise ValueError(f"{name}: {message}")


def pick_script(station, plant_context, X_WG: RigidTransform,
                params: PickParams | None = None, *,
                keep_straight_rod: bool = False, wait: float = 0.0) -> MotionScript | None:
    """The motion that picks with the open gripper at ``X_WG``; None when a waypoint has no IK.

    ``plant_context`` gives the state IK holds fixed (the object where it lies); the robot first
    waits ``wait`` seconds at home (e.g. for the object to settle). The fingers
    close symmetrically about G, which keeps p_M (the bar tip's meeting point) fixed: right for
    parallel grasps, whose p_M is at the hole's centre. With ``keep_straight_rod`` the arm moves
    G along +y_G while the fingers close, by as much as each finger travels, so the straight rod
    stays where the grasp put it and only the L rod sweeps in: right for vertical grasps, whose
    straight rod is placed in the hole beside the material (closing symmetrically would push the
    straight rod into that material)."""
    params = params or PickParams()
    plant = station.plant
    G = plant.GetFrameByName("G", station.gripper)
    R = X_WG.rotation()
    approach_W, closing_W = R.col(2), R.col(1)  # +z_G: palm -> fingertips; +y_G: L -> straight rod
    shift = (HOOK_GRIPPER.q_open - HOOK_GRIPPER.q_closed) if keep_straight_rod else 0.0
    p_closed = X_WG.translation() + shift * closing_W
    p_lift = p_closed + [0.0, 0.0, params.lift_height]
    targets = {
        "approach": X_WG.translation() - params.approach_distance * approach_W,
        "descend": X_WG.translation(),
        "close": p_closed,
        "lift": p_lift,
        "carry": p_lift + np.asarray(params.carry_offset),
    }
    q = station.q_home
    waypoints = {}
    for label, p in targets.items():
        q = solve_gripper_ik(plant, plant_context, station.arm, G, RigidTransform(R, p), q)
        if q is None:
            return None
        waypoints[label] = q
    script = MotionScript().start(station.q_home, HOOK_GRIPPER.q_open)
    if wait > 0:
        script.hold(wait, "settle")
    script.move_arm(waypoints["approach"], "approach").move_arm(waypoints["descend"], "descend")
    script.move(waypoints["close"], HOOK_GRIPPER.q_closed, "close", duration=0.6)
    script.move_arm(waypoints["lift"], "lift")
    if np.any(params.carry_offset):
        script.move_arm(waypoints["carry"], "carry")
    return script.hold(params.hold_time, "hold")
