"""A LeafSystem that moves one abstract value through a pure function: the GbH stages' shell."""

from __future__ import annotations

from pydrake.common.value import AbstractValue, Value
from pydrake.systems.framework import LeafSystem


class AbstractStage(LeafSystem):
    """One abstract input port, one abstract output port computed by ``self.compute(value)``.

    The output is cached and depends only on the input (``prerequisites_of_calc`` is the input
    port's ticket), so a stage runs once per new input, not at every simulator step."""

    def __init__(self, input_name: str, output_name: str):
        super().__init__()
        self._input = self.DeclareAbstractInputPort(input_name, AbstractValue.Make(object()))
        self.DeclareAbstractOutputPort(
            output_name, lambda: Value[object](), self._calc,
            prerequisites_of_calc={self._input.ticket()},
        )

    def compute(self, value):  # pragma: no cover - overridden
        raise NotImplementedError

    def _calc(self, context, output) -> None:
        output.set_value(self.compute(self._input.Eval(context)))
