"""The ``RegraspPlanner`` system: where to set an object down so that GbH can hook it (beyond
the paper, :mod:`gbh_drake.core.regrasp`)."""

from __future__ import annotations

import dataclasses

import numpy as np

from gbh_drake.core.params import AntipodalParams, GbhParams, RegraspParams
from gbh_drake.core.regrasp import choose_regrasp_pose, pinches_for_pose
from gbh_drake.systems.hangability_detector import Hangability
from gbh_drake.systems.stage import AbstractStage, params_argument, seed_argument


class RegraspPlanner(AbstractStage):
    """The resting poses of the scanned object in which GbH ranks a hook grasp, best first.

    .. pydrake_system::

        name: RegraspPlanner
        input_ports:
        - hanging_structures
        output_ports:
        - regrasp_poses

    ``hanging_structures``: the detector's
    :class:`~gbh_drake.systems.hangability_detector.Hangability` (the scan's prepared mesh, its
    centre of mass and structures). ``regrasp_poses``: ``list[RegraspPose]``
    (:func:`~gbh_drake.core.regrasp.choose_regrasp_pose`: the object's stable resting
    orientations, :func:`~gbh_drake.objects.stability.stable_poses` of the scanned mesh about
    its centre of mass, each set down where the object lies, GbH run on it; at most
    ``max_poses``), each with the pinches that hold it from above there
    (:func:`~gbh_drake.core.regrasp.pinches_for_pose`); empty when GbH found no structure
    (nothing to hook in any pose). Cached:
    computed once per new input, and only when evaluated (a PickAndCarry asks only when no
    hook grasp could be planned).
    """

    def __init__(self, params: GbhParams | None = None, regrasp: RegraspParams | None = None,
                 *, seed: int = 0, antipodal: AntipodalParams | None = None,
                 pinch_seed: int = 0):
        """``params``: GbH's (the pipeline run on each pose; its ``ground_clearance`` the
        pinches' too); ``regrasp``: which poses count; ``seed``: the surface sampler's;
        ``antipodal``, ``pinch_seed``: the antipodal sampler's (the pinches)."""
        super().__init__("hanging_structures", Hangability(), "regrasp_poses", [])
        self.params = params_argument(self, "params", params, GbhParams)
        self.regrasp = params_argument(self, "regrasp", regrasp, RegraspParams)
        self.seed = seed_argument(self, "seed", seed)
        self.antipodal = dataclasses.replace(
            params_argument(self, "antipodal", antipodal, AntipodalParams),
            ground_clearance=self.params.ground_clearance)
        self.pinch_seed = seed_argument(self, "pinch_seed", pinch_seed)

    def compute(self, value: Hangability):
        if value.object is None or not value.structures:
            return []
        from gbh_drake.objects.stability import stable_poses

        mesh = value.object.mesh
        rests = stable_poses(mesh, value.object.com).poses
        xy = 0.5 * (np.asarray(mesh.bounds[0][:2]) + np.asarray(mesh.bounds[1][:2]))
        poses = choose_regrasp_pose(
            mesh, [(p.R, p.probability) for p in rests], self.params, xy, seed=self.seed,
            min_turn_deg=self.regrasp.min_turn_deg, min_probability=self.regrasp.min_probability,
            max_poses=self.regrasp.max_poses)
        for pose in poses:
            pose.pinches = pinches_for_pose(mesh, pose, self.antipodal, seed=self.pinch_seed,
                                            clearance=self.params.ground_clearance)
        return poses
