"""Where the robot's base frame B and the gripper frame G are in a plant the directives built.

B is the arm's base ``panda::panda_link0``: grasps handed to a real robot are in B. In the
station W = B (the default directives weld ``panda_link0`` to the world at the origin); a
scenario whose directives put the arm elsewhere gets its scan and grasps transformed by
:attr:`RobotFrames.X_WB` when they are written out. ``X_link8_G`` is read from the plant, so a
gripper mounted otherwise is written as mounted; for the station's own mount it equals
:func:`gbh_drake.core.gripper.X_link8_G` (a test checks).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gbh_drake.modeling.names import ARM, GRIPPER

#: The arm's base body (frame B) and flange body, and the gripper frame's name in the SDF.
BASE_BODY, FLANGE_BODY, GRIPPER_FRAME = "panda_link0", "panda_link8", "G"


@dataclass(frozen=True)
class RobotFrames:
    """The robot's frames as a plant has them (4x4 homogeneous matrices, metres)."""

    X_WB: np.ndarray
    """Pose of the arm's base frame B (``panda_link0``) in the world W."""
    X_link8_G: np.ndarray
    """Pose of the gripper frame G in the flange frame ``panda_link8``."""


def robot_frames(plant, context=None) -> RobotFrames:
    """The frames of ``plant`` (a ``MultibodyPlant`` with the arm and the hook gripper, finalized)
    in ``context`` (default: a default context; both are welded, so any context gives them)."""
    context = plant.CreateDefaultContext() if context is None else context
    arm, gripper = plant.GetModelInstanceByName(ARM), plant.GetModelInstanceByName(GRIPPER)
    base = plant.GetBodyByName(BASE_BODY, arm).body_frame()
    flange = plant.GetBodyByName(FLANGE_BODY, arm).body_frame()
    G = plant.GetFrameByName(GRIPPER_FRAME, gripper)
    return RobotFrames(base.CalcPoseInWorld(context).GetAsMatrix4(),
                       G.CalcPose(context, flange).GetAsMatrix4())


def robot_frames_of(directives) -> RobotFrames:
    """:func:`robot_frames` of a plant parsed from ``directives`` (a list of Drake
    ``ModelDirective``, e.g. a scenario's ``station_directives()``)."""
    from pydrake.multibody.parsing import ModelDirectives, ProcessModelDirectives
    from pydrake.multibody.plant import MultibodyPlant

    from gbh_drake.modeling.package_map import make_parser

    plant = MultibodyPlant(0.0)
    ProcessModelDirectives(ModelDirectives(directives=list(directives)), plant,
                           make_parser(plant))
    plant.Finalize()
    return robot_frames(plant)
