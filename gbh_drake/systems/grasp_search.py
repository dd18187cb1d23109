"""The ``GraspSearchReport`` system: why a grasp method offered no grasp, for the monitor.

A method's grasp source may come up empty for different reasons: the scan holds no object, GbH
found nothing hangable, or no candidate passed the rules. The monitor decides the trial's outcome
from what it is told here (:class:`~gbh_drake.messages.GraspSearch`); nothing
re-judges it afterwards. :func:`explain_no_grasp` is the pure rule.
"""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.systems.framework import LeafSystem

from gbh_drake.core.params import GbhParams
from gbh_drake.core.rejections import count_rejections, no_grasp_message
from gbh_drake.core.scoop import ScoopResult
from gbh_drake.messages import GraspSearch, Outcome
from gbh_drake.perception.scan import ScanResult
from gbh_drake.systems.hangability_detector import Hangability
from gbh_drake.systems.scanner import no_scan
from gbh_drake.systems.stage import params_argument


def explain_no_grasp(scan: ScanResult, hangability: Hangability | None = None,
                     candidates: list | None = None, *, fallback: bool = False,
                     sampler: str = "the antipodal sampler",
                     params: GbhParams | None = None,
                     scoops: ScoopResult | None = None) -> GraspSearch:
    """Why a method offered no grasp on ``scan``: ``hangability`` and ``candidates`` (counted
    :class:`~gbh_drake.core.results.GraspCandidate`) are GbH's (None: a method without GbH,
    whose grasps came from ``sampler``); ``fallback``: an antipodal fallback was tried too and
    found nothing either; ``params``: GbH's (the rules' thresholds; default GbhParams());
    ``scoops``: the scoop's result, when the method scoops (its reason is added). The reason
    counts the candidates each collision rule removed and says how near the closest came
    (:func:`~gbh_drake.core.rejections.count_rejections`)."""
    if scan.empty:
        return GraspSearch(Outcome.EMPTY_SCAN, scan.message)
    if hangability is None:
        return GraspSearch(Outcome.NO_GRASP_FOUND, f"{sampler} found no grasp on the scan")
    also = f"; the scoop: {scoops.reason()}" if scoops is not None and scoops.reason() else ""
    also += "; the antipodal fallback found no grasp either" if fallback else ""
    if not hangability.structures:
        return GraspSearch(Outcome.NO_HANGABLE_STRUCTURE,
                           (hangability.message or "no hangable structure found") + also)
    candidates = list(candidates or [])
    rejections = count_rejections(candidates, params or GbhParams())
    return GraspSearch(Outcome.NO_GRASP_FOUND, no_grasp_message(
        len(candidates), len(hangability.structures), rejections) + also, rejections.removed)


class GraspSearchReport(LeafSystem):
    """Says why a method has no grasp to offer (:func:`explain_no_grasp`).

    .. pydrake_system::

        name: GraspSearchReport
        input_ports:
        - scan
        - hanging_structures (GbH methods)
        - grasp_candidates (GbH methods)
        - scoops (methods that scoop)
        output_ports:
        - grasp_search

    ``scan``: the :class:`~gbh_drake.perception.scan.ScanResult`; ``hanging_structures``: the
    detector's :class:`~gbh_drake.systems.hangability_detector.Hangability`;
    ``grasp_candidates``: the synthesizer's list; ``scoops``: the
    :class:`~gbh_drake.systems.scoop_synthesizer.ScoopSynthesizer`'s result. ``grasp_search``: a
    :class:`~gbh_drake.messages.GraspSearch` (evaluated by the monitor only when the
    machine had no grasp to try). Cached; depends only on its inputs.
    """

    def __init__(self, *, hook: bool = True, fallback: bool = False,
                 sampler: str = "the antipodal sampler", params: GbhParams | None = None,
                 scoop: bool = False):
        """``hook``: the method runs GbH (declares the structure and candidate inputs);
        ``fallback``: an antipodal fallback follows GbH; ``sampler``: what offered the grasps
        of a method without GbH (for the reason's words); ``params``: GbH's (the collision
        rules' thresholds, to count what each removed); ``scoop``: the method scoops
        (declares the ``scoops`` input)."""
        super().__init__()
        self._params = params_argument(self, "params", params, GbhParams)
        self._fallback = bool(fallback)
        self._sampler = sampler
        self._scan = self.DeclareAbstractInputPort("scan", AbstractValue.Make(
            no_scan("no input yet")))
        inputs = [self._scan]
        self._structures = self._candidates = None
        if hook:
            self._structures = self.DeclareAbstractInputPort(
                "hanging_structures", AbstractValue.Make(Hangability()))
            self._candidates = self.DeclareAbstractInputPort("grasp_candidates",
                                                             AbstractValue.Make([]))
            inputs += [self._structures, self._candidates]
        self._scoops = None
        if scoop:
            self._scoops = self.DeclareAbstractInputPort("scoops", AbstractValue.Make(
                ScoopResult()))
            inputs.append(self._scoops)
        self.DeclareAbstractOutputPort(
            "grasp_search", lambda: AbstractValue.Make(GraspSearch()), self._calc,
            prerequisites_of_calc={p.ticket() for p in inputs})

    def _calc(self, context, output) -> None:
        hangability = self._structures.Eval(context) if self._structures else None
        candidates = self._candidates.Eval(context) if self._candidates else None
        scoops = self._scoops.Eval(context) if self._scoops else None
        output.set_value(explain_no_grasp(self._scan.Eval(context), hangability, candidates,
                                          fallback=self._fallback, sampler=self._sampler,
                                          params=self._params, scoops=scoops))
