"""The ``ShapeCompleter`` system: a scan in, the scan completed by shape completion out."""

from __future__ import annotations

from gbh_drake.core.params import CompletionParams
from gbh_drake.perception.completion import complete_scan
from gbh_drake.perception.scan import ScanResult
from gbh_drake.systems.scanner import no_scan
from gbh_drake.systems.stage import AbstractStage, params_argument, seed_argument


class ShapeCompleter(AbstractStage):
    """Completes the unseen side of a scan (:mod:`gbh_drake.core.completion`).

    .. pydrake_system::

        name: ShapeCompleter
        input_ports:
        - mesh_W
        output_ports:
        - completed_mesh_W

    ``mesh_W``: the Scanner's :class:`~gbh_drake.perception.scan.ScanResult`.
    ``completed_mesh_W``: the same scan with the completed surface added to its mesh and, as its
    free space, the cameras' and the completion's likely-free space
    (:func:`~gbh_drake.perception.completion.complete_scan`); an empty scan passes as it is.
    Feed it to the ``HangabilityDetector``; plan the pick on the scan as taken.
    """

    def __init__(self, params: CompletionParams | None = None, *, seed: int = 0):
        """``seed``: which of the scan's vertices fit the axis (the scenario derives it)."""
        super().__init__("mesh_W", no_scan("no input yet"), "completed_mesh_W",
                         no_scan("no input yet"))
        self.params = params_argument(self, "params", params, CompletionParams)
        self.seed = seed_argument(self, "seed", seed)

    def memo_key(self, value) -> tuple:
        return (value.mesh_W, value.free_space)

    def compute(self, value: ScanResult) -> ScanResult:
        return complete_scan(value, self.params, self.seed)
