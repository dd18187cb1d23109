"""The ``GraspSynthesizer`` system: hanging structures in, collision-counted grasps out (Sec. 2.3)."""

from __future__ import annotations

from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import synthesize
from gbh_drake.systems.hangability_detector import Hangability
from gbh_drake.systems.stage import AbstractStage, params_argument


class GraspSynthesizer(AbstractStage):
    """Parallel and vertical hook grasps for every hanging structure, with N_c counted.

    .. pydrake_system::

        name: GraspSynthesizer
        input_ports:
        - hanging_structures
        output_ports:
        - grasp_candidates

    ``hanging_structures``: a :class:`~gbh_drake.systems.hangability_detector.Hangability`.
    ``grasp_candidates``: ``list[GraspCandidate]`` (X_WG of the open gripper, ``n_collisions``
    set, not yet scored). The unknown space of a scan (``Hangability.object.free_space``)
    counts in N_sweep when ``GbhParams.unknown_is_occupied``.
    """

    def __init__(self, params: GbhParams | None = None,
                 gripper: HookGripperGeometry = HOOK_GRIPPER):
        super().__init__("hanging_structures", Hangability(), "grasp_candidates", [])
        self.params = params_argument(self, "params", params, GbhParams)
        self.gripper = gripper

    def compute(self, value: Hangability):
        if value.object is None or not value.structures:
            return []
        return synthesize(value.object, value.structures, self.params, self.gripper)
