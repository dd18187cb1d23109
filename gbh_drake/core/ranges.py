"""Field rules declared beside the fields: ranges, allowed names, list lengths, fixed values.

A config dataclass declares each field's rule as field metadata::

    d2: float = ranged(0.0, Range(-0.05, 0.05, unit="m"))

and its cross-field rules in a method ``check_relations(self, at=())`` that raises
:class:`FieldError`. :func:`check_fields` checks both; the class's own public ``check()`` is
:func:`checker`'s, the scenario loader calls :func:`check_fields` with the section's path, and
docs/scenario_fields.md's table is rendered from the same rules (``Rule.doc``): one home per range.

Pure Python and numpy (no pydrake): the core and the perception config import it.
"""

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

Path_ = tuple


def format_path(path: Path_) -> str:
    """``("robot", "q_home", 3)`` -> ``robot.q_home[3]``."""
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text


class FieldError(ValueError):
    """A field that cannot work: ``path`` (tuple of names and indices) and ``problem``."""

    def __init__(self, path: Path_, problem: str):
        super().__init__(f"{format_path(path) or '<scenario>'}: {problem}")
        self.path = tuple(path)
        self.problem = problem

    def __reduce__(self):  # picklable with its parts
        return type(self), (self.path, self.problem)


def _num(v) -> str:
    if v is None:
        return ""
    if isinstance(v, int | np.integer) and not isinstance(v, bool):
        return str(int(v))
    if math.isfinite(v) and float(v).is_integer() and abs(v) < 1e12:
        return str(int(v))
    return f"{float(v):g}"


def check_finite_number(path: Path_, value) -> None:
    """Refuses NaN, +-inf and an int too large for a float."""
    try:
        finite = math.isfinite(value)
    except OverflowError:
        finite = False
    if not finite:
        raise FieldError(path, f"must be a finite number, got {value}")


def _note(note: str) -> str:
    return f" ({note})" if note else ""


# ---- the rules --------------------------------------------------------------------------------


@dataclass(frozen=True)
class Range:
    """A closed or open interval of numbers (either bound may be None) with a unit."""

    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""
    note: str = ""
    integer: bool = False
    optional: bool = False
    """Whether the field may also be left out (None: a default decided elsewhere)."""

    def contains(self, v) -> bool:
        if self.lo is not None and (v <= self.lo if self.lo_open else v < self.lo):
            return False
        return not (self.hi is not None and (v >= self.hi if self.hi_open else v > self.hi))

    def text(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        lo, hi = _num(self.lo), _num(self.hi)
        if self.lo is not None and self.hi is not None:
            return (f"{'an integer ' if self.integer else ''}in {'(' if self.lo_open else '['}"
                    f"{lo}, {hi}{')' if self.hi_open else ']'}{unit}")
        if self.lo is not None:
            if self.lo == 0:
                return ("> 0" if self.lo_open else ">= 0") + unit
            return f"{'>' if self.lo_open else '>='} {lo}{unit}"
        if self.hi is not None:
            return f"{'<' if self.hi_open else '<='} {hi}{unit}"
        return "finite"

    def doc(self) -> str:
        return self.text() + (" or omitted" if self.optional else "") + _note(self.note)

    def check(self, path: Path_, value) -> None:
        if value is None and self.optional:
            return
        if isinstance(value, bool) or not isinstance(value, int | float | np.number):
            raise FieldError(path, f"expected a number, got {value!r}")
        check_finite_number(path, value)
        if self.integer and not float(value).is_integer():
            raise FieldError(path, f"expected an integer, got {value!r}")
        if not self.contains(value):
            unit = f" {self.unit}" if self.unit else ""
            raise FieldError(path, f"must be {self.text()}, got {_num(value)}{unit}{_note(self.note)}")


def Int(lo=None, hi=None, note: str = "", optional: bool = False) -> Range:  # noqa: N802
    """A rule constructor: integers in [lo, hi] (``optional``: or None)."""
    return Range(lo, hi, integer=True, note=note, optional=optional)


def Pos(hi=None, unit="", note="", hi_open=False) -> Range:  # noqa: N802
    return Range(0.0, hi, lo_open=True, hi_open=hi_open, unit=unit, note=note)


def NonNeg(hi=None, unit="", note="") -> Range:  # noqa: N802
    return Range(0.0, hi, unit=unit, note=note)


@dataclass(frozen=True)
class OneOf:
    """One of a few allowed values (names)."""

    values: tuple
    note: str = ""

    def doc(self) -> str:
        return "one of " + ", ".join(f"`{v}`" if v else "`''`" for v in self.values) + \
            _note(self.note)

    def check(self, path: Path_, value) -> None:
        if value not in self.values:
            shown = ", ".join(repr(v) if v == "" else str(v) for v in self.values)
            raise FieldError(path, f"must be one of {shown}; got {value!r}{_note(self.note)}")


@dataclass(frozen=True)
class Registered:
    """One of the names of a registry that may grow at run time (``names()`` lists them now)."""

    names: Callable[[], tuple]
    note: str = ""

    def doc(self) -> str:
        return OneOf(tuple(self.names()), self.note).doc()

    def check(self, path: Path_, value) -> None:
        OneOf(tuple(self.names()), self.note).check(path, value)


@dataclass(frozen=True)
class Items:
    """A list of ``length`` items (any length when None), each within ``each`` (a
    :class:`Range`, :class:`OneOf` or :class:`Registered`; None: any), each once when
    ``unique``."""

    length: int | None
    each: "Range | OneOf | Registered | None" = Range()
    what: str = "values"
    unique: bool = False

    def doc(self) -> str:
        if self.each is None or self.each == Range():
            each = ""
        else:
            each = f", each {self.each.text() if isinstance(self.each, Range) else self.each.doc()}"
        return ((f"{self.length} {self.what}" if self.length else self.what) + each +
                (", none twice" if self.unique else ""))

    def check(self, path: Path_, value) -> None:
        if self.length is not None and len(value) != self.length:
            raise FieldError(path, f"needs {self.length} {self.what}, got {len(value)}")
        for i, v in enumerate(value):
            if self.each is not None:
                self.each.check(path + (i,), v)
            if self.unique and list(value).index(v) != i:
                raise FieldError(path + (i,), f"{v!r} is listed twice")


@dataclass(frozen=True)
class Fixed:
    """A field that must keep one value (the run derives or ignores it)."""

    value: object
    why: str

    def doc(self) -> str:
        return f"`{self.value!r}` ({self.why})"

    def check(self, path: Path_, value) -> None:
        if value != self.value:
            raise FieldError(path, f"must be {self.value!r} ({self.why}); got {value!r}")


Rule = Range | OneOf | Registered | Items | Fixed

# ---- declaring and checking -------------------------------------------------------------------

_RULE = "rule"


def ranged(default, rule: Rule, **kwargs):
    """A dataclass field with ``default`` (a callable: its default factory, e.g. for a list)
    and its ``rule`` as metadata."""
    if callable(default):
        return dataclasses.field(default_factory=default, metadata={_RULE: rule}, **kwargs)
    return dataclasses.field(default=default, metadata={_RULE: rule}, **kwargs)


def rule_of(f: dataclasses.Field) -> Rule | None:
    """The rule declared on dataclass field ``f``, or None."""
    return f.metadata.get(_RULE)


def check_ranges(obj, at: Path_ = ()) -> None:
    """Each field of dataclass ``obj`` that declares a rule, against it (``at``: where ``obj``
    is, for the error's path)."""
    for f in dataclasses.fields(obj):
        rule = rule_of(f)
        if rule is not None:
            rule.check(at + (f.name,), getattr(obj, f.name))


def check_fields(obj, at: Path_ = ()) -> None:
    """:func:`check_ranges`, then ``obj``'s own ``check_relations(at)`` (if it has one)."""
    check_ranges(obj, at)
    relations = getattr(obj, "check_relations", None)
    if relations is not None:
        relations(at)


def checker(error: type[Exception] = ValueError):
    """A public ``check`` method from the class's declared rules: raises ``error`` with
    ``<Class>.<field>: <problem>`` for the first field that cannot work."""

    def check(self) -> None:
        """Raises naming the first field whose value cannot work (its declared range, or a
        relation between fields)."""
        try:
            check_fields(self)
        except FieldError as e:
            raise error(f"{type(self).__name__}.{e}") from None

    return check


def sibling(at: Path_, name: str) -> str:
    """How a relation's message names another field of the same config: ``scan.distance``
    inside a scenario (``at`` = ("scan",)), ``distance`` on its own."""
    return format_path(at + (name,))
