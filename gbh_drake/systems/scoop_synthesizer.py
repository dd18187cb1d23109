"""The ``ScoopSynthesizer`` system: hanging structures in, scoops of flat material out (beyond
the paper, :mod:`gbh_drake.core.scoop`)."""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.systems.framework import LeafSystem

from gbh_drake.core.gripper import WEDGE_GRIPPER, HookGripperGeometry
from gbh_drake.core.params import GbhParams, ScoopParams
from gbh_drake.core.scoop import ScoopResult, plan_scoops
from gbh_drake.systems.hangability_detector import Hangability
from gbh_drake.systems.stage import LastResult, params_argument


class ScoopSynthesizer(LeafSystem):
    """Scoops (the wedge bar slid under material lying on the table) of the flat structures.

    .. pydrake_system::

        name: ScoopSynthesizer
        input_ports:
        - hanging_structures
        output_ports:
        - scoops
        - scoop_grasps
        - tall_scoop_grasps

    ``hanging_structures``: the detector's
    :class:`~gbh_drake.systems.hangability_detector.Hangability`. ``scoops``: the
    :class:`~gbh_drake.core.scoop.ScoopResult` (every pose, the rules' counts, why none passed);
    ``scoop_grasps``: its ranked scoops (``list[GraspCandidate]`` of kind ``scoop``, best
    first), what a :class:`~gbh_drake.systems.pick_and_carry.PickAndCarry` executes;
    ``tall_scoop_grasps``: the tall scoops (material taller than the wedge, offered apart,
    :attr:`~gbh_drake.core.scoop.ScoopResult.ranked_tall`). Cached;
    computed once per new input object (kept with it, as an
    :class:`~gbh_drake.systems.stage.AbstractStage` does, with a
    :class:`~gbh_drake.systems.stage.LastResult`: Drake re-validates
    the input more often than it changes).
    """

    def __init__(self, params: GbhParams | None = None, scoop: ScoopParams | None = None,
                 gripper: HookGripperGeometry = WEDGE_GRIPPER):
        """``params``: GbH's (the table, N_c, the score); ``scoop``: the scoop's rules;
        ``gripper``: the wedge gripper's geometry."""
        super().__init__()
        self.params = params_argument(self, "params", params, GbhParams)
        self.scoop = params_argument(self, "scoop", scoop, ScoopParams)
        self.gripper = gripper
        self._input = self.DeclareAbstractInputPort("hanging_structures",
                                                    AbstractValue.Make(Hangability()))
        self._last = LastResult()
        self.input_types = {"hanging_structures": (Hangability,)}
        self._result = self.DeclareAbstractOutputPort(
            "scoops", lambda: AbstractValue.Make(ScoopResult()), self._calc_result,
            prerequisites_of_calc={self._input.ticket()})
        self.DeclareAbstractOutputPort(
            "scoop_grasps", lambda: AbstractValue.Make([]),
            lambda context, output: output.set_value(self._result.Eval(context).ranked),
            prerequisites_of_calc={self._result.cache_entry().ticket()})
        self.DeclareAbstractOutputPort(
            "tall_scoop_grasps", lambda: AbstractValue.Make([]),
            lambda context, output: output.set_value(self._result.Eval(context).ranked_tall),
            prerequisites_of_calc={self._result.cache_entry().ticket()})

    def _calc_result(self, context, output) -> None:
        value = self._input.Eval(context)
        output.set_value(self._last.get((value,), lambda: self._plan(value)))

    def _plan(self, value: Hangability) -> ScoopResult:
        if value.object is None or not value.structures:
            return ScoopResult()
        return plan_scoops(value.object, value.structures, self.params, self.scoop,
                           self.gripper)
