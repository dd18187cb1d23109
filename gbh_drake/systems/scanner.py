"""The ``Scanner`` system: depth views of the scene around a target, fused into the object mesh."""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import QueryObject
from pydrake.systems.framework import LeafSystem

from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import ScanResult, scan_object


class Scanner(LeafSystem):
    """Scans the scene with simulated depth views and outputs the fused mesh in W.

    .. pydrake_system::

        name: Scanner
        input_ports:
        - query_object
        output_ports:
        - mesh_W

    ``query_object`` (``QueryObject``): connect the SceneGraph's query output port.
    ``mesh_W`` (:class:`~gbh_drake.perception.scan.ScanResult`): the object's mesh in W,
    segmented from the table and the robot (a first look finds it near ``p_WT``, then the views
    are aimed at it), its points, the camera poses X_WC, warnings (e.g. the object reaches the
    edge of what the cameras see) and timing; ``empty`` and ``message`` when nothing was seen.

    Two ways to use it. Without ``scan_time`` the output is a function of the input, cached
    until the scene's poses change (evaluate it when you need a scan). With ``scan_time`` (s) the
    Scanner takes one scan at that time, keeps it in its state and outputs it from then on (scan
    first, then act); before that time the output is an empty result that says so.
    """

    def __init__(self, config: ScanConfig, p_WT, *, scan_time: float | None = None,
                 noise_seed: int = 0):
        """``p_WT`` (3,) m: where the object is expected in W (the first look searches around it,
        then the views aim at what it found);
        ``noise_seed``: seed of the depth noise (when ``config.noise``)."""
        super().__init__()
        config.validate()
        self._config = config
        self._p_WT = np.asarray(p_WT, dtype=float).reshape(3)
        self._noise_seed = int(noise_seed)
        self._query = self.DeclareAbstractInputPort("query_object",
                                                    AbstractValue.Make(QueryObject()))
        model = AbstractValue.Make(no_scan("not scanned yet"))
        if scan_time is None:
            self.DeclareAbstractOutputPort("mesh_W", model.Clone, self._calc_scan,
                                           prerequisites_of_calc={self._query.ticket()})
        else:
            self._held = self.DeclareAbstractState(model)
            self.DeclarePeriodicUnrestrictedUpdateEvent(1e9, float(scan_time), self._take_scan)
            self.DeclareStateOutputPort("mesh_W", self._held)

    @property
    def config(self) -> ScanConfig:
        return self._config

    @property
    def p_WT(self) -> np.ndarray:
        return self._p_WT.copy()

    def scan(self, context) -> ScanResult:
        """A scan of the scene as ``context`` has it now."""
        return scan_object(self._query.Eval(context), self._config, self._p_WT,
                           noise_seed=self._noise_seed)

    def _calc_scan(self, context, output) -> None:
        output.set_value(self.scan(context))

    def _take_scan(self, context, state) -> None:
        state.get_mutable_abstract_state(self._held).set_value(self.scan(context))


def no_scan(message: str) -> ScanResult:
    """An empty scan result that says why there is no scan."""
    return ScanResult.empty_result(message)
