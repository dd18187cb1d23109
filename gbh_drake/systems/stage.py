"""A LeafSystem that moves one abstract value through a pure function: the GbH stages' shell."""

from __future__ import annotations

import copy
import weakref

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import LeafSystem

from gbh_drake.core.arguments import argument_problem, require


class LastResult:
    """The last result of a pure computation and the objects it was computed from: ``get`` gives
    it back while the same objects (by identity) are asked for again.

    The objects are held by weak reference where they allow it (a scan's mesh, its free space, a
    Hangability): a dead reference matches nothing, so no later object can pass for one that
    died, and the result is dropped as soon as one of them dies. A Python LeafSystem is never
    freed (pydrake keeps it alive through its own callbacks), so a memo that held its inputs and
    result would keep every trial's scans and GbH results of a worker: 12 GB after a few hundred
    ``gbh+`` trials. Objects that allow no weak reference are held."""

    def __init__(self):
        self._key: tuple | None = None
        self._result = None

    def get(self, key: tuple, compute):
        """The result for ``key``: the last one if ``key`` holds the same objects, else
        ``compute()`` (kept as the last, while ``key``'s objects live)."""
        held = self._key
        if held is None or len(held) != len(key) or any(
                _target(a) is not b for a, b in zip(held, key, strict=True)):
            result = compute()
            self._key, self._result = tuple(self._hold(k) for k in key), result
        return self._result

    def _hold(self, obj):
        try:
            return weakref.ref(obj, self._forget)
        except TypeError:  # no weak reference to this type: hold it
            return _Strong(obj)

    def _forget(self, _ref) -> None:
        self._key, self._result = None, None


class _Strong:
    """A held object, read as a weak reference is: ``ref()``."""

    __slots__ = ("obj",)

    def __init__(self, obj):
        self.obj = obj

    def __call__(self):
        return self.obj


def _target(ref):
    """The object behind a weak reference or a :class:`_Strong` (None once it died)."""
    return ref()


class AbstractStage(LeafSystem):
    """One abstract input port, one abstract output port computed by ``self.compute(value)``.

    Both ports are declared with typed model values (``input_model``, ``output_model``): they
    document the types (:func:`~gbh_drake.systems.ports.build_checked` compares them) and are
    what a context's allocated values hold; the input is required (evaluating the output with
    it unconnected raises Drake's "is not connected"). A value of the wrong type on the input
    fails in :meth:`compute`'s caller with a message naming the system and port. The output is
    cached and depends only on the input (``prerequisites_of_calc`` is the input port's
    ticket), so a stage runs once per new input, not at every simulator step.

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


def params_argument(system: LeafSystem, name: str, value, kind: type):
    """``value``, or ``kind()`` for None; a ``TypeError`` naming ``system``'s argument ``name``
    for another type (a wrong one would surface only when the stage computes, as a result:
    "unusable mesh")."""
    if value is None:
        return kind()
    article = "an" if kind.__name__[0] in "AEIOU" else "a"
    return require(type(system).__name__, name, value, kind, f"{article} {kind.__name__} or None")


def seed_argument(system: LeafSystem, name: str, seed) -> int:
    """``seed`` as an int; a ``TypeError`` naming ``system``'s argument ``name`` unless it is an
    integer in [0, 2^64) (the samplers' seeds)."""
    if not (isinstance(seed, int | np.integer) and not isinstance(seed, bool)
            and 0 <= seed < 2**64):
        raise TypeError(argument_problem(type(system).__name__, name, "an integer in [0, 2^64)",
                                         seed))
    return int(seed)


class CopiedShallowly:
    """A base for abstract-state records that updates replace, member by member, instead of
    mutating: Drake copies abstract state at every update, and a deep copy of what they hold
    (plans, trajectories) would be wasted work."""

    def __deepcopy__(self, memo):
        return copy.copy(self)
