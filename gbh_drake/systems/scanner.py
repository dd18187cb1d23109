"""The ``Scanner`` system: depth views of the scene around a target, fused into the object mesh."""

from __future__ import annotations

import numpy as np
from pydrake.common.value import AbstractValue, Value
from pydrake.geometry import QueryObject
from pydrake.systems.framework import LeafSystem

from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import ScanResult, scan_object


class Scanner(LeafSystem):
    """Scans the scene with simulated depth views and outputs the fused mesh in W.

    @system
    name: Scanner
    input_ports:
    - query_object
    output_ports:
    - mesh_W
    @endsystem

    ``query_object`` (abstract ``QueryObject``): connect the SceneGraph's query output port.
    ``mesh_W`` (abstract :class:`~gbh_drake.perception.scan.ScanResult`): the mesh in W, the
    points, the camera poses X_WC and timing; ``empty`` and ``message`` when nothing was seen.

    The scan is expensive (~0.5-1 s for 10 views), so ``mesh_W`` is cached. By default it is
    computed once, at its first evaluation in a context, and kept however the scene moves
    afterwards (scan first, then act). With ``rescan_on_change=True`` it is recomputed whenever
    the query object's inputs (the poses in the scene) change.
    """

    def __init__(self, config: ScanConfig, p_WT, *, rescan_on_change: bool = False):
        """``p_WT`` (3,) m: the scan target in W (near the object's centre, above the table)."""
        super().__init__()
        config.validate()
        self._config = config
        self._p_WT = np.asarray(p_WT, dtype=float).reshape(3)
        self._query_port = self.DeclareAbstractInputPort(
            "query_object", AbstractValue.Make(QueryObject()))
        prerequisites = ({self._query_port.ticket()} if rescan_on_change
                         else {self.nothing_ticket()})
        self.DeclareAbstractOutputPort("mesh_W", lambda: Value[object](), self._calc_mesh_W,
                                       prerequisites_of_calc=prerequisites)

    @property
    def config(self) -> ScanConfig:
        return self._config

    @property
    def p_WT(self) -> np.ndarray:
        return self._p_WT.copy()

    def _calc_mesh_W(self, context, output) -> None:
        query_object = self._query_port.Eval(context)
        result: ScanResult = scan_object(query_object, self._config, self._p_WT)
        output.set_value(result)
