"""The ``WristLoad`` system: the force the arm's flange exerts on the hand, in W.

Franka's controller estimates the external wrench at the end effector from its joint torques;
here it is the reaction force of the weld between the flange and the hand. Gravity is
compensated on the robot, so while the hand carries nothing the load is about zero, and while an
object hangs on the hook it is about the object's weight, upward: when the object is set down on
the table it drops back toward zero.
"""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import JointIndex
from pydrake.systems.framework import BasicVector, LeafSystem


class WristLoad(LeafSystem):
    """Reads the reaction force of the joint that holds ``body`` (its inboard joint, e.g. the
    weld of the hand to the flange) and outputs it in W.

    .. pydrake_system::

        name: WristLoad
        input_ports:
        - reaction_forces
        - body_poses
        output_ports:
        - load_W

    ``reaction_forces`` and ``body_poses``: the plant's outputs. ``load_W`` (3, N): the force
    on the joint's child body (the hand) from its parent (the flange), in W.
    """

    def __init__(self, plant: MultibodyPlant, body):
        super().__init__()
        (joint,) = [plant.get_joint(JointIndex(i)) for i in range(plant.num_joints())
                    if plant.get_joint(JointIndex(i)).child_body().index() == body.index()]
        self._joint = int(joint.index())
        self._child = int(joint.child_body().index())
        self._X_CJc = joint.frame_on_child().GetFixedPoseInBodyFrame()
        self._forces = self.DeclareAbstractInputPort("reaction_forces",
                                                     AbstractValue.Make([SpatialForce()]))
        self._poses = self.DeclareAbstractInputPort("body_poses",
                                                    AbstractValue.Make([RigidTransform()]))
        self.DeclareVectorOutputPort("load_W", 3, self._calc)

    def _calc(self, context, output: BasicVector) -> None:
        F_CJc_Jc = self._forces.Eval(context)[self._joint]
        R_WJc = self._poses.Eval(context)[self._child].rotation().multiply(
            self._X_CJc.rotation())
        output.SetFromVector(R_WJc.multiply(F_CJc_Jc.translational()))
