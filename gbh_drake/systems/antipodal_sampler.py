"""The ``AntipodalGraspSampler`` system: a scan in, antipodal grasps for two straight rods out."""

from __future__ import annotations

import dataclasses

from gbh_drake.core.antipodal import AntipodalParams, sample_antipodal_grasps
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.results import GbhInputError
from gbh_drake.perception.scan import ScanResult
from gbh_drake.systems.scanner import no_scan
from gbh_drake.systems.stage import AbstractStage, params_argument, seed_argument

trimesh = lazy_module("trimesh")


class AntipodalGraspSampler(AbstractStage):
    """The learning-free antipodal baseline (:mod:`gbh_drake.core.antipodal`): grasps for the
    hook gripper with its bar folded onto the L rod, i.e. two straight rods of the same length
    (the paper's fairness rule for its baseline), best first.

    .. pydrake_system::

        name: AntipodalGraspSampler
        input_ports:
        - mesh_W
        output_ports:
        - antipodal_grasps

    ``mesh_W``: a :class:`~gbh_drake.perception.scan.ScanResult` or a ``trimesh.Trimesh`` in W.
    ``antipodal_grasps``: ``list[AntipodalGrasp]`` (``X_WG``, ``kind = "antipodal"``, ``score``),
    empty for an empty scan or an unusable mesh.
    """

    def __init__(self, params: AntipodalParams | None = None, *, seed: int = 0,
                 ground_clearance: float | None = None):
        """``seed``: the sampler's seed; ``ground_clearance`` (m): overrides the params' one
        (the scenario passes GbH's, so both methods keep the same clearance)."""
        super().__init__("mesh_W", no_scan("no input yet"), "antipodal_grasps", [],
                         accepts=(ScanResult, trimesh.Trimesh))
        params = params_argument(self, "params", params, AntipodalParams)
        if ground_clearance is not None:
            params = dataclasses.replace(params, ground_clearance=ground_clearance)
        self.params = params
        self._seed = seed_argument(self, "seed", seed)

    def memo_key(self, value) -> tuple:
        return (value.mesh_W,) if isinstance(value, ScanResult) else (value,)

    def compute(self, value):
        if isinstance(value, ScanResult):
            if value.empty:
                return []
            value = value.mesh_W
        try:
            return sample_antipodal_grasps(value, self.params, self._seed)
        except GbhInputError:
            return []
