"""A collision checker of the robot against its surroundings, for the motion planner.

Drake's ``SceneGraphCollisionChecker`` over a planning model built from the scenario's own
directives (arm, gripper, table, anything added) plus the object welded where it lies. Proximity
queries treat a mesh as its convex hull, so the object is a conservative obstacle: the planner
keeps the robot out of the hull, and the last centimetres into a handle are a straight,
separately checked descent (:mod:`gbh_drake.planning.pick`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import ModelDirectives, ProcessModelDirectives
from pydrake.planning import RobotDiagramBuilder, SceneGraphCollisionChecker

from gbh_drake.modeling.package_map import add_packages


@dataclass
class PlanningModel:
    """The checker and what is needed to build full configurations for it.

    ``q_full(q_arm, q_finger)``: the planning plant's positions (arm 7, fingers 2)."""

    checker: SceneGraphCollisionChecker
    arm_lower: np.ndarray
    arm_upper: np.ndarray
    """Joint position limits of the arm (rad)."""

    @staticmethod
    def q_full(q_arm, q_finger: float) -> np.ndarray:
        return np.concatenate([np.asarray(q_arm, dtype=float), [q_finger, q_finger]])

    def free(self, q_arm, q_finger: float) -> bool:
        return bool(self.checker.CheckConfigCollisionFree(self.q_full(q_arm, q_finger)))

    def edge_free(self, q_a, q_b, q_finger: float) -> bool:
        return bool(self.checker.CheckEdgeCollisionFree(self.q_full(q_a, q_finger),
                                                        self.q_full(q_b, q_finger)))


def make_planning_model(scenario, object_sdf: str | None, X_WO: RigidTransform | None, *,
                        edge_step_size: float = 0.01, padding: float = 0.005) -> PlanningModel:
    """The planning model of ``scenario`` with the object (its SDF, welded at ``X_WO``).

    ``edge_step_size`` (rad) is the spacing of the configurations checked along an edge;
    ``padding`` (m) the clearance kept from the environment (table, object)."""
    builder = RobotDiagramBuilder(time_step=0.0)
    plant, parser = builder.plant(), builder.parser()
    add_packages(parser.package_map())
    ProcessModelDirectives(ModelDirectives(directives=scenario.directives), plant, parser)
    if object_sdf is not None:
        (obj,) = parser.AddModels(object_sdf)
        body = plant.get_body(plant.GetBodyIndices(obj)[0])
        plant.WeldFrames(plant.world_frame(), body.body_frame(), X_WO)
    plant.Finalize()
    arm = plant.GetModelInstanceByName("panda")
    gripper = plant.GetModelInstanceByName("hook_gripper")
    checker = SceneGraphCollisionChecker(
        model=builder.Build(), robot_model_instances=[arm, gripper],
        edge_step_size=edge_step_size, env_collision_padding=padding,
        self_collision_padding=0.0)
    # The closed hook's bar tip rests on the straight rod by design.
    checker.SetCollisionFilteredBetween(
        plant.GetBodyByName("straight_finger", gripper).index(),
        plant.GetBodyByName("l_finger", gripper).index(), True)
    return PlanningModel(checker, plant.GetPositionLowerLimits()[:7],
                         plant.GetPositionUpperLimits()[:7])
