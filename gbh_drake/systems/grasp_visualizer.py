"""The ``GraspVisualizer`` system: draws the scan, the hanging structures and the grasps in Meshcat.

In the style of the paper's Figs. 4-5 (:mod:`gbh_drake.viz.gbh_meshcat`): once the pick-and-carry
machine has planned, the scanned mesh, the structures (c, v, rays) and the ranked grasps are
drawn, with the executed one's solid model highlighted; when no candidate passed the collision
rules, the few that came closest (:func:`gbh_drake.core.rejections.closest_rejected`) are drawn
in purple under ``gbh/refused``. It only publishes (no state): what it draws appears in the live
view and in the saved replay.
"""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.geometry import Meshcat
from pydrake.systems.framework import LeafSystem

from gbh_drake.core.params import GbhParams
from gbh_drake.core.rejections import closest_rejected
from gbh_drake.messages import Mode, PickStatus
from gbh_drake.systems.hangability_detector import Hangability
from gbh_drake.systems.scanner import no_scan


class GraspVisualizer(LeafSystem):
    """Draws what GbH saw and chose, once, when the grasps have been planned.

    .. pydrake_system::

        name: GraspVisualizer
        input_ports:
        - scan
        - hanging_structures (optional)
        - grasps
        - pick_status
        - grasp_candidates (optional)

    ``grasp_candidates``: GbH's counted candidates (the synthesizer's), to draw the closest
    refused ones when no grasp passed; ``params``: GbH's (the rules' thresholds).
    """

    def __init__(self, meshcat: Meshcat, *, period: float = 0.1, prefix: str = "gbh",
                 params: GbhParams | None = None, n_refused: int = 3):
        super().__init__()
        self._meshcat = meshcat
        self._prefix = prefix
        self._params = params or GbhParams()
        self._n_refused = int(n_refused)
        self._scan = self.DeclareAbstractInputPort("scan",
                                                   AbstractValue.Make(no_scan("no input yet")))
        self._structures = self.DeclareAbstractInputPort("hanging_structures",
                                                         AbstractValue.Make(Hangability()))
        self._grasps = self.DeclareAbstractInputPort("grasps", AbstractValue.Make([]))
        self._status = self.DeclareAbstractInputPort("pick_status",
                                                     AbstractValue.Make(PickStatus()))
        self._candidates = self.DeclareAbstractInputPort("grasp_candidates",
                                                         AbstractValue.Make([]))
        self._drawn_for: int | None = None
        self.DeclarePeriodicPublishEvent(period, 0.0, self._publish)

    def _publish(self, context) -> None:
        status: PickStatus = self._status.Eval(context)
        if status.mode in (Mode.SETTLE, Mode.PLAN):
            return
        key = id(status.plan) if status.plan is not None else -1
        if self._drawn_for == key:
            return
        from gbh_drake.viz.gbh_meshcat import (
            REFUSED,
            clear,
            draw_grasps,
            draw_object,
            draw_structures,
        )

        self._drawn_for = key
        clear(self._meshcat, self._prefix)
        scan = self._scan.Eval(context)
        if len(scan.mesh_W.faces):
            draw_object(self._meshcat, scan.mesh_W, self._prefix)
        if self._structures.HasValue(context):  # (optional: a method without GbH has none)
            draw_structures(self._meshcat, self._structures.Eval(context).structures,
                            self._prefix)
        grasps = [g for g in self._grasps.Eval(context) if hasattr(g, "structure")]
        if grasps:
            draw_grasps(self._meshcat, grasps, self._prefix)
        elif self._candidates.HasValue(context):
            refused = closest_rejected(self._candidates.Eval(context), self._params,
                                       self._n_refused)
            if refused:
                draw_grasps(self._meshcat, refused, self._prefix, rgba=REFUSED,
                            folder="refused")
