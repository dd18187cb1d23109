"""A LeafSystem that moves one abstract value through a pure function: the GbH stages' shell."""

from __future__ import annotations

import copy

from pydrake.common.value import AbstractValue
from pydrake.systems.framework import LeafSystem


class LastResult:
    """The last result of a pure computation and the objects it was computed from: ``get`` gives
    it back while the same objects (by identity) are asked for again. The objects are held, so no
    other object can take their identity."""

    def __init__(self):
        self._key: tuple | None = None
        self._result = None

    def get(self, key: tuple, compute):
        """The result for ``key``: the last one if ``key`` holds the same objects, else
        ``compute()`` (kept as the last)."""
        if self._key is None or len(self._key) != len(key) or any(
                a is not b for a, b in zip(self._key, key, strict=True)):
            self._result, self._key = compute(), key
        return self._result


class AbstractStage(LeafSystem):
    """One abstract input port, one abstract output port computed by ``self.compute(value)``.

    Both ports are declared with typed model values (``input_model``, ``output_model``): a
    default that documents the type and is what an unconnected or not-yet-computed port holds.
    A value of the wrong type on the input fails in :meth:`compute`'s caller with a message
    naming the system and port. The output is cached and depends only on the input
    (``prerequisites_of_calc`` is the input port's ticket), so a stage runs once per new input,
    not at every simulator step.

    Drake re-validates that input more often than it changes: every unrestricted update in the
    diagram (the plant's step, the Scanner's stillness watch) marks the updated systems' state,
    hence the Scanner's scan, as changed, and a later ``Eval`` (the GraspVisualizer's, the
    trial's record) recalculated GbH on the same scan, three times per trial. So each stage also
    keeps its last result with the objects it was computed from (:meth:`memo_key`, compared by
    identity, held so that no other object can take their identity): the same input objects give
    the same result object, without computing. ``compute`` is a pure function of its input, so
    this holds in any context."""

    def __init__(self, input_name: str, input_model, output_name: str, output_model,
                 accepts: tuple[type, ...] = ()):
        """``accepts``: the types the input may hold (default: the model's type)."""
        super().__init__()
        self._accepts = accepts or (type(input_model),)
        self.input_types = {input_name: self._accepts}
        """The types the input accepts (read by :func:`gbh_drake.systems.ports.check_connections`)."""
        self._input = self.DeclareAbstractInputPort(input_name, AbstractValue.Make(input_model))
        self._last = LastResult()
        self.DeclareAbstractOutputPort(
            output_name, lambda: AbstractValue.Make(output_model), self._calc,
            prerequisites_of_calc={self._input.ticket()},
        )

    def compute(self, value):  # pragma: no cover - overridden
        raise NotImplementedError

    def memo_key(self, value) -> tuple:
        """The objects whose identity decides ``compute(value)``: ``value`` itself by default
        (an upstream stage hands on the same result object while its own input is unchanged);
        a scan's consumers name the parts of it they read, which Drake's copies of the
        Scanner's state share."""
        return (value,)

    def _calc(self, context, output) -> None:
        value = self._input.Eval(context)
        if not isinstance(value, self._accepts):
            names = " or ".join(t.__name__ for t in self._accepts)
            raise TypeError(f"{self.get_name() or type(self).__name__}: input "
                            f"{self._input.get_name()!r} expects {names}, got "
                            f"{type(value).__name__}")
        output.set_value(self._last.get(self.memo_key(value), lambda: self.compute(value)))


class CopiedShallowly:
    """A base for abstract-state records that updates replace, member by member, instead of
    mutating: Drake copies abstract state at every update, and a deep copy of what they hold
    (plans, trajectories) would be wasted work."""

    def __deepcopy__(self, memo):
        return copy.copy(self)
