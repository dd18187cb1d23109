"""The robot's planning model: a collision checker and inverse kinematics over the fixed scene.

A ``RobotDiagram`` built from the scenario's own directives (arm, gripper, table and anything a
user added; :func:`parse_robot`, by the station's own populate function
:func:`gbh_drake.modeling.package_map.add_fixed_models`) plus obstacles the robot perceived
(e.g. the scanned object's convex hull, added to the checker on the world frame). A trial
parses its directives once and gives each model it needs (near the grasp, for the transfer
around the scan, at table level for a scoop) its own copy of that ``RobotDiagram``. It holds
no free body: inverse kinematics is solved on this plant, so the free object's quaternion (unit
only to ~1e-5 after a simulation) is never a decision variable that the unit-quaternion
constraint could contradict. Collision checks are Drake's
``SceneGraphCollisionChecker``; proximity treats meshes as their convex hulls.

Configurations of the planning plant are the arm's seven joints plus the hand: both fingers'
positions q (m, half the opening) and the bar's angle (rad), see :class:`HandPose`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from pydrake.common import MemoryFile
from pydrake.geometry import Convex, InMemoryMesh
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.inverse_kinematics import InverseKinematics
from pydrake.multibody.parsing import ModelDirective
from pydrake.planning import (
    RobotCollisionType,
    RobotDiagram,
    RobotDiagramBuilder,
    SceneGraphCollisionChecker,
)
from pydrake.solvers import Solve

from gbh_drake.core.lazy import lazy_module
from gbh_drake.modeling.names import ARM, GRIPPER
from gbh_drake.modeling.package_map import add_fixed_models

trimesh = lazy_module("trimesh")


@dataclass(frozen=True)
class HandPose:
    """The hand's joints: each finger's position ``q`` (m) and the bar's angle (rad)."""

    q: float
    bar: float = 0.0

    def positions(self) -> np.ndarray:
        return np.array([self.q, self.q, self.bar])


def parse_robot(directives: Sequence[ModelDirective]) -> RobotDiagram:
    """The fixed models of ``directives`` (arm, gripper, table, a user's) as a finalized
    ``RobotDiagram`` without free bodies: parse once per trial, then give each
    :class:`PlanningModel` a copy."""
    builder = RobotDiagramBuilder(time_step=0.0)
    add_fixed_models(builder.parser(), directives)
    builder.plant().Finalize()
    return builder.Build()


class PlanningModel:
    """Collision checks and IK of the robot among fixed obstacles (see the module docstring)."""

    def __init__(self, robot: Sequence[ModelDirective] | RobotDiagram, *,
                 obstacles: Sequence[trimesh.Trimesh] = (), padding: float = 0.005,
                 edge_step_size: float = 0.01, ignore_models: Sequence[str] = ()):
        """``robot``: the directives of the fixed models, or a ``RobotDiagram`` of them
        (:func:`parse_robot`; this model works on a copy); ``obstacles``: meshes in W added as
        convex obstacles; ``padding`` (m): clearance kept between the robot and the
        environment; ``edge_step_size`` (rad): spacing of the configurations checked along an
        edge; ``ignore_models``: model instances (by name) the robot may touch (a scoop's model
        ignores the table it slides on)."""
        model = robot.Clone() if isinstance(robot, RobotDiagram) else parse_robot(robot)
        plant = model.plant()
        self.padding = float(padding)
        """m: the clearance kept between the robot and the environment."""
        self.plant = plant
        self.arm = plant.GetModelInstanceByName(ARM)
        self.gripper = plant.GetModelInstanceByName(GRIPPER)
        self.G = plant.GetFrameByName("G", self.gripper)
        self.checker = SceneGraphCollisionChecker(
            model=model, robot_model_instances=[self.arm, self.gripper],
            edge_step_size=edge_step_size, env_collision_padding=padding,
            self_collision_padding=0.0)
        for i, mesh in enumerate(obstacles):
            self.checker.AddCollisionShapeToFrame(
                "obstacles", plant.world_frame(), _convex(mesh, f"obstacle_{i}"), RigidTransform())
        # The closed hook's bar tip rests on the straight rod by design.
        straight = plant.GetBodyByName("straight_finger", self.gripper).index()
        for name in ("l_finger", "bar"):
            self.checker.SetCollisionFilteredBetween(
                straight, plant.GetBodyByName(name, self.gripper).index(), True)
        robot_bodies = [*plant.GetBodyIndices(self.arm), *plant.GetBodyIndices(self.gripper)]
        for name in ignore_models:
            for other in plant.GetBodyIndices(plant.GetModelInstanceByName(name)):
                for body in robot_bodies:
                    self.checker.SetCollisionFilteredBetween(body, other, True)
        self._arm_dofs = _position_indices(plant, self.arm)
        self._hand_dofs = _position_indices(plant, self.gripper)
        self.arm_lower = plant.GetPositionLowerLimits()[self._arm_dofs]
        self.arm_upper = plant.GetPositionUpperLimits()[self._arm_dofs]
        self._context = plant.CreateDefaultContext()

    def q_full(self, q_arm, hand: HandPose) -> np.ndarray:
        """The planning plant's positions for arm joints ``q_arm`` (7,) and ``hand``."""
        q = np.zeros(self.plant.num_positions())
        q[self._arm_dofs] = q_arm
        q[self._hand_dofs] = hand.positions()
        return q

    def free(self, q_arm, hand: HandPose) -> bool:
        return bool(self.checker.CheckConfigCollisionFree(self.q_full(q_arm, hand)))

    def edge_free(self, q_a, q_b, hand: HandPose, hand_b: HandPose | None = None) -> bool:
        """Whether the straight move from arm joints ``q_a`` to ``q_b`` is collision-free, the
        hand at ``hand`` throughout, or moving from ``hand`` to ``hand_b`` with the arm (the
        checker interpolates all joints together)."""
        return bool(self.checker.CheckEdgeCollisionFree(
            self.q_full(q_a, hand), self.q_full(q_b, hand if hand_b is None else hand_b)))

    def X_WG(self, q_arm, hand: HandPose) -> RigidTransform:
        """Forward kinematics: the gripper frame G in W."""
        self.plant.SetPositions(self._context, self.q_full(q_arm, hand))
        return self.G.CalcPoseInWorld(self._context)

    def ik(self, X_WG: RigidTransform, q_seed, hand: HandPose, *, restarts: int = 0,
           position_tolerance: float = 1e-3, angle_tolerance: float = 1e-2) -> np.ndarray | None:
        """Arm joint positions (7,) that put G at ``X_WG`` within the tolerances (m, rad) with
        the hand at ``hand``, near ``q_seed``, within the joint limits; None when infeasible.

        SNOPT is local: when it fails from ``q_seed`` it is restarted from up to ``restarts``
        other guesses (the middle of the joint ranges, then configurations drawn from a
        generator seeded by the target pose, so the answer does not depend on call order).
        A solution in which the robot meets itself (the IK knows no collisions: a vertical
        grasp far from the base folds link 5 into the hand) is no solution: the pose is
        reachable, so the guesses go on, up to :data:`FOLDED_GUESSES` in all, for a
        configuration that does not (the IK of a pose no guess reaches stops at ``restarts``)."""
        q_seed = np.asarray(q_seed, dtype=float)
        q = self._ik_from(X_WG, q_seed, hand, position_tolerance, angle_tolerance)
        if q is not None and not self.self_colliding(q, hand):
            return q
        if restarts <= 0:
            return None
        folded = q is not None
        rng = np.random.default_rng(
            np.frombuffer(np.round(X_WG.GetAsMatrix34(), 6).tobytes(), dtype=np.uint32))
        guess, tried = 0.5 * (self.arm_lower + self.arm_upper), 0
        while tried < (max(restarts, FOLDED_GUESSES) if folded else restarts):
            q = self._ik_from(X_WG, q_seed, hand, position_tolerance, angle_tolerance, guess)
            tried += 1
            if q is not None and not self.self_colliding(q, hand):
                return q
            folded |= q is not None
            guess = rng.uniform(self.arm_lower, self.arm_upper)
        return None

    def self_colliding(self, q_arm, hand: HandPose) -> bool:
        """Whether the robot (arm and gripper) meets itself at arm joints ``q_arm`` and
        ``hand`` (the checker's filters apply: the closed hook's bar on its straight rod is
        by design)."""
        kinds = self.checker.ClassifyBodyCollisions(self.q_full(q_arm, hand))
        return any(k in _SELF for k in kinds)

    def _ik_from(self, X_WG: RigidTransform, q_seed, hand: HandPose, position_tolerance: float,
                 angle_tolerance: float, guess=None) -> np.ndarray | None:
        """One SNOPT solve from ``guess`` (default ``q_seed``), with a cost pulling toward
        ``q_seed``."""
        self.plant.SetPositions(self._context, self.q_full(q_seed, hand))
        ik = InverseKinematics(self.plant, self._context, with_joint_limits=True)
        q = ik.q()
        prog = ik.get_mutable_prog()
        p = X_WG.translation()
        ik.AddPositionConstraint(self.G, np.zeros(3), self.plant.world_frame(),
                                 p - position_tolerance, p + position_tolerance)
        ik.AddOrientationConstraint(self.G, RotationMatrix(), self.plant.world_frame(),
                                    X_WG.rotation(), angle_tolerance)
        hand_q = hand.positions()
        prog.AddBoundingBoxConstraint(hand_q, hand_q, q[self._hand_dofs])
        prog.AddQuadraticErrorCost(1e-2 * np.eye(len(self._arm_dofs)), q_seed, q[self._arm_dofs])
        result = Solve(prog, self.q_full(q_seed if guess is None else guess, hand))
        if not result.is_success():
            return None
        return result.GetSolution(q)[self._arm_dofs]


#: Guesses the IK tries (:meth:`PlanningModel.ik`) once a solution met the robot itself: on
#: the own set's headphones lying flat (stable trial 1), 3 found a free configuration for 4 of
#: the 12 best grasps, 10 for 10 of them (each guess a few milliseconds).
FOLDED_GUESSES = 10
#: The checker's collision kinds in which a robot body meets another of the robot's.
_SELF = (RobotCollisionType.kSelfCollision, RobotCollisionType.kEnvironmentAndSelfCollision)


def _convex(mesh: trimesh.Trimesh, name: str) -> Convex:
    """A Drake ``Convex`` shape (the hull of ``mesh``), in memory."""
    hull = mesh.convex_hull
    text = trimesh.exchange.obj.export_obj(hull, include_normals=False, include_texture=False)
    return Convex(InMemoryMesh(mesh_file=MemoryFile(text, ".obj", name)))


def _position_indices(plant, instance) -> np.ndarray:
    indices = []
    for j in plant.GetJointIndices(instance):
        joint = plant.get_joint(j)
        indices.extend(range(joint.position_start(), joint.position_start() + joint.num_positions()))
    return np.asarray(indices, dtype=int)
