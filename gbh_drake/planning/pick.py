"""A pick: transfer to the approach pose, descend, close the hook, lift, carry and hold.

Waypoints are solved by IK on straight gripper offsets along the approach direction; the arm
moves between them with joint-space cubic segments. With a :class:`PickPlanning` the motion is
also collision-checked: the transfer from home to the approach pose is planned by RRT-Connect
around the table and the object (its convex hull, so the approach pose backs off along the
approach axis until it is clear of it), and the short straight segments after it (descend,
close, lift, carry) are checked against the table and the robot itself.
"""

from dataclasses import dataclass, field

import numpy as np
from pydrake.math import RigidTransform

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.planning.collision import PlanningModel
from gbh_drake.planning.ik import solve_gripper_ik
from gbh_drake.planning.rrt import plan_rrt_connect
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
    plan_paths: bool = True
    """Plan the transfer by RRT-Connect and collision-check every segment (False: IK only,
    straight joint-space moves)."""
    max_approach_distance: float = 0.25
    """With planning: the approach pose backs off in 5 cm steps up to this distance until the
    gripper is clear of the object's convex hull."""

    def check(self) -> None:
        """Raises ``ValueError`` naming the first field that cannot work."""
        problems = [
            ("approach_distance", self.approach_distance >= 0, "must be >= 0"),
            ("lift_height", self.lift_height > 0, "must be positive"),
            ("carry_offset", len(self.carry_offset) == 3, "needs 3 coordinates (m)"),
            ("hold_time", self.hold_time > 0, "must be positive"),
            ("max_approach_distance", self.max_approach_distance >= self.approach_distance,
             "must be >= approach_distance"),
        ]
        for name, ok, message in problems:
            if not ok:
                raise ValueError(f"{name}: {message}")


@dataclass
class PickPlanning:
    """Collision models for planning a pick: ``with_object`` (table, robot and the object's
    convex hull, for the transfer) and ``without_object`` (table and robot, for the segments that
    go into the handle and carry the object; run.py builds it without padding, since the grasp
    itself may reach down to the table top); ``seed`` seeds RRT-Connect."""

    with_object: PlanningModel
    without_object: PlanningModel
    seed: int = 0


def pick_script(station, plant_context, X_WG: RigidTransform,
                params: PickParams | None = None, *,
                keep_straight_rod: bool = False, wait: float = 0.0,
                planning: PickPlanning | None = None) -> MotionScript | None:
    """The motion that picks with the open gripper at ``X_WG``; None when a waypoint has no IK
    or, with ``planning``, when no collision-free motion was found.

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

    def ik(p, q_seed):
        return solve_gripper_ik(plant, plant_context, station.arm, G, RigidTransform(R, p), q_seed)

    # The grasp and what follows it: IK, then (with planning) the segments' collision checks.
    waypoints, q = {}, station.q_home
    for label, p in (("descend", X_WG.translation()), ("close", p_closed), ("lift", p_lift),
                     ("carry", p_lift + np.asarray(params.carry_offset))):
        q = ik(p, q)
        if q is None:
            return None
        waypoints[label] = q
    if planning is not None and not _segments_free(planning.without_object, waypoints):
        return None

    # The approach pose (backed off until clear of the object) and the transfer to it.
    transfer = None
    distances = np.arange(params.approach_distance, params.max_approach_distance + 1e-9, 0.05)
    for distance in distances if planning is not None else distances[:1]:
        q_approach = ik(X_WG.translation() - distance * approach_W, waypoints["descend"])
        if q_approach is None:
            continue
        if planning is None:
            transfer = [station.q_home, q_approach]
            break
        if not planning.without_object.edge_free(q_approach, waypoints["descend"],
                                                 HOOK_GRIPPER.q_open):
            continue
        transfer = plan_rrt_connect(planning.with_object, station.q_home, q_approach,
                                    HOOK_GRIPPER.q_open, seed=planning.seed)
        if transfer is not None:
            break
    if transfer is None:
        return None

    script = MotionScript().start(station.q_home, HOOK_GRIPPER.q_open)
    if wait > 0:
        script.hold(wait, "settle")
    for q_via in transfer[1:-1]:
        script.move_arm(q_via, "transfer")
    script.move_arm(transfer[-1], "approach").move_arm(waypoints["descend"], "descend")
    script.move(waypoints["close"], HOOK_GRIPPER.q_closed, "close", duration=0.6)
    script.move_arm(waypoints["lift"], "lift")
    if np.any(params.carry_offset):
        script.move_arm(waypoints["carry"], "carry")
    return script.hold(params.hold_time, "hold")


def _segments_free(model: PlanningModel, waypoints: dict) -> bool:
    """Descend (open), close (open and closed ends), lift and carry (closed) clear of the table
    and of the robot itself."""
    q_o, q_c = HOOK_GRIPPER.q_open, HOOK_GRIPPER.q_closed
    return (model.edge_free(waypoints["descend"], waypoints["close"], q_o)
            and model.free(waypoints["close"], q_c)
            and model.edge_free(waypoints["close"], waypoints["lift"], q_c)
            and model.edge_free(waypoints["lift"], waypoints["carry"], q_c))
