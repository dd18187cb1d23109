"""The ``HangabilityDetector`` system: a mesh in, the hanging structures out (paper Sec. 2.2)."""

from __future__ import annotations

from dataclasses import dataclass, field

from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.object_model import ObjectModel
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import detect_reported
from gbh_drake.core.results import GbhInputError, HangabilityReport, HangingStructure
from gbh_drake.perception.scan import ScanResult
from gbh_drake.systems.scanner import no_scan
from gbh_drake.systems.stage import AbstractStage, params_argument, seed_argument

trimesh = lazy_module("trimesh")


@dataclass
class Hangability:
    """The detector's output: the prepared object (samples, CoM, and the scan's free space when
    the input was a scan; None when the input was unusable), its hanging structures (in W), a
    message when there are none, and what the detector saw and refused on the way (None when it
    did not run)."""

    object: ObjectModel | None = None
    structures: list[HangingStructure] = field(default_factory=list)
    message: str = "no input yet"
    report: HangabilityReport | None = None


class HangabilityDetector(AbstractStage):
    """Finds the structures an object can hang by.

    .. pydrake_system::

        name: HangabilityDetector
        input_ports:
        - mesh_W
        output_ports:
        - hanging_structures

    ``mesh_W``: the Scanner's :class:`~gbh_drake.perception.scan.ScanResult`, or any
    ``trimesh.Trimesh`` in W. ``hanging_structures``: a :class:`Hangability`. "Nothing
    hangable", an empty scan or an unusable mesh are results (empty ``structures`` and a
    ``message``), not exceptions. A scan's ``free_space`` (what the views saw free) goes with
    the prepared object (``Hangability.object.free_space``), so the GraspSynthesizer has it too.
    """

    def __init__(self, params: GbhParams | None = None, *, seed: int = 0):
        """``seed``: the surface sampler's seed (the scenario derives it from its own)."""
        super().__init__("mesh_W", no_scan("no input yet"), "hanging_structures", Hangability(),
                         accepts=(ScanResult, trimesh.Trimesh))
        self.params = params_argument(self, "params", params, GbhParams)
        self.seed = seed_argument(self, "seed", seed)

    def memo_key(self, value) -> tuple:
        if isinstance(value, ScanResult):
            return (value.mesh_W, value.free_space)  # (an empty scan has a mesh of its own)
        return (value,)

    def compute(self, value) -> Hangability:
        if isinstance(value, ScanResult) and value.empty:
            return Hangability(None, [], value.message or "empty scan")
        mesh = value.mesh_W if isinstance(value, ScanResult) else value
        free_space = value.free_space if isinstance(value, ScanResult) else None
        try:
            obj, structures, report = detect_reported(mesh, self.params, self.seed, free_space)
        except GbhInputError as e:
            return Hangability(None, [], f"unusable mesh: {e}")
        return Hangability(obj, structures, "" if structures else "no hangable structure found",
                           report)
