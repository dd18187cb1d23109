"""Inverse kinematics of the arm for a desired gripper pose X_WG (Drake's InverseKinematics + SNOPT)."""

from __future__ import annotations

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.inverse_kinematics import InverseKinematics
from pydrake.solvers import Solve


def solve_gripper_ik(
    plant,
    plant_context,
    arm,
    G_frame,
    X_WG: RigidTransform,
    q_seed_arm: np.ndarray,
    *,
    position_tolerance: float = 1e-3,
    angle_tolerance: float = 1e-2,
) -> np.ndarray | None:
    """Arm joint positions (7,) that put frame ``G_frame`` at ``X_WG``, or None if IK fails.

    All other positions of the plant (fingers, the object) are held at their values in
    ``plant_context``. Tolerances: metres and radians. Joint limits are respected."""
    ik = InverseKinematics(plant, plant_context, with_joint_limits=True)
    q = ik.q()
    prog = ik.get_mutable_prog()
    p = X_WG.translation()
    ik.AddPositionConstraint(G_frame, np.zeros(3), plant.world_frame(),
                             p - position_tolerance, p + position_tolerance)
    ik.AddOrientationConstraint(G_frame, RotationMatrix(), plant.world_frame(), X_WG.rotation(),
                                angle_tolerance)
    q_all = plant.GetPositions(plant_context).copy()
    arm_mask = np.zeros(plant.num_positions(), dtype=bool)
    arm_mask[_arm_position_indices(plant, arm)] = True
    q_all[arm_mask] = q_seed_arm
    others = np.flatnonzero(~arm_mask)
    if len(others):
        prog.AddBoundingBoxConstraint(q_all[others], q_all[others], q[others])
    prog.AddQuadraticErrorCost(np.eye(int(arm_mask.sum())) * 1e-2, q_seed_arm, q[arm_mask])
    result = Solve(prog, q_all)
    if not result.is_success():
        return None
    return result.GetSolution(q)[arm_mask]


def _arm_position_indices(plant, arm) -> np.ndarray:
    indices = []
    for j in plant.GetJointIndices(arm):
        joint = plant.get_joint(j)
        indices.extend(range(joint.position_start(), joint.position_start() + joint.num_positions()))
    return np.asarray(indices, dtype=int)
