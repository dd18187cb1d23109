"""Field rules declared beside the fields: types, ranges, allowed names, list lengths, fixed
values, paths, and the bounds between fields.

A config dataclass declares each field's rule as field metadata::

    d2: float = ranged(0.0, Range(-0.05, 0.05, unit="m"))

and a field that another field bounds declares that too (:class:`Relation`)::

    min_lift: float = ranged(0.10, Pos(1.0, "m"), relations=(Relation("<=", "max_lift"),))

(a relation between fields of two sections is declared on the section field of the config that
holds both, :func:`section`). What no rule can say goes in a method ``check_relations(self,
at=())`` that raises :class:`FieldError`. :func:`check_fields` checks the fields' types (from
their annotations: a config built in code may hold anything), their rules, their relations and
``check_relations``; the class's own public ``check()`` is :func:`checker`'s, the scenario
loader calls :func:`check_fields` with the section's path, and docs/errors.md's tables are
rendered from the same rules (``Rule.doc``, ``Relation.doc``): one home per range and bound.

Pure Python and numpy (no pydrake): the core and the perception config import it.
"""

import dataclasses
import functools
import math
import operator
import types
import typing
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
    """A field that cannot work: ``path`` (tuple of names and indices) and ``problem``.

    ``other``: for a bound between two fields (:class:`Relation`), the same problem said of the
    other field (``pick.max_lift: must be >= scoop.min_lift``), for a loader that names the
    field the user wrote rather than one left at its default."""

    def __init__(self, path: Path_, problem: str, other: "FieldError | None" = None):
        super().__init__(f"{format_path(path) or '<scenario>'}: {problem}")
        self.path = tuple(path)
        self.problem = problem
        self.other = other

    def __reduce__(self):  # picklable with its parts
        return type(self), (self.path, self.problem, self.other)


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
        if not is_number(value):
            raise FieldError(path, f"expected a number, got {value!r}")
        check_finite_number(path, value)
        if self.integer and not isinstance(value, int | np.integer):
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
        if not is_sequence(value):
            raise FieldError(path, f"expected a list of {self.doc()}, got {shown(value)}")
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


@dataclass(frozen=True)
class FilePath:
    """A file or folder's path, as text: relative to the scenario (or experiment) file's folder
    when written in the file, to the current folder when given in an override (``--set``, the
    API's ``overrides``: the loader makes it absolute)."""

    what: str = "file"

    def doc(self) -> str:
        return (f"a {self.what}'s path; relative: to the file's folder (given by --set or "
                "overrides: to the current folder)")

    def check(self, path: Path_, value) -> None:
        if not isinstance(value, str):
            raise FieldError(path, f"expected a path as text (a str; str(path) of a Path), got "
                                   f"{shown(value)}")
        if "\0" in value:
            raise FieldError(path, "holds a NUL character")


Rule = Range | OneOf | Registered | Items | Fixed | FilePath


# ---- bounds between fields --------------------------------------------------------------------

#: A relation's operator: (comparison, its words, the reverse operator).
_OPS = {"<=": (operator.le, "must be <=", ">="), "<": (operator.lt, "must be <", ">"),
        ">=": (operator.ge, "must be >=", "<="), ">": (operator.gt, "must exceed", "<")}


@dataclass(frozen=True)
class Relation:
    """A bound between two number fields: ``<field> <op> factor x <other>`` (``op``: ``<=``,
    ``<``, ``>=``, ``>``).

    Declared in the metadata of the bounded field (``field`` empty) or, between fields of two
    sections, of the section field of the config that holds both (``field``: the bounded field
    inside that section, e.g. ``min_lift`` on ``Scenario.scoop``). ``other`` and ``when`` are
    dotted paths from the declaring config. ``when``: (path, value): the bound holds only when
    that field has that value (e.g. ``("task", "pick")``). ``why``: what goes wrong otherwise.
    A value that is None (an optional field left out) is not compared."""

    op: str
    other: str
    why: str = ""
    field: str = ""
    factor: float = 1.0
    when: tuple = ()

    def __post_init__(self):
        if self.op not in _OPS:
            raise ValueError(f"Relation.op: one of {', '.join(_OPS)}, got {self.op!r}")

    def _scaled(self, name: str) -> str:
        return name if self.factor == 1 else f"{_num(self.factor)} x {name}"

    def doc(self, at: Path_ = ()) -> str:
        """``<= pick.max_lift (for task pick)`` (paths from ``at``)."""
        when = f" (for {format_path(at + _split(self.when[0]))} {self.when[1]})" \
            if self.when else ""
        return f"{self.op} {self._scaled(format_path(at + _split(self.other)))}{when}"

    def lhs(self, name: str) -> Path_:
        """The bounded field's path from the declaring config (declared on field ``name``)."""
        return (name, *_split(self.field))

    def check(self, obj, name: str, at: Path_ = ()) -> None:
        """Raises :class:`FieldError` when the bound declared on ``obj``'s field ``name`` fails
        (``at``: where ``obj`` is, for the messages)."""
        if self.when and _value_at(obj, _split(self.when[0])) != self.when[1]:
            return
        lhs, rhs = self.lhs(name), _split(self.other)
        a, b = _value_at(obj, lhs), _value_at(obj, rhs)
        if a is None or b is None or not (is_number(a) and is_number(b)):
            return  # left out, or not a number: the type check says so
        compare, words, reverse = _OPS[self.op]
        if compare(a, self.factor * b):
            return
        unit = _unit(obj, lhs)
        why = f": {self.why}" if self.why else ""
        other = FieldError(at + rhs, f"{_OPS[reverse][1]} {format_path(at + lhs)}"
                           f"{'' if self.factor == 1 else f' / {_num(self.factor)}'} "
                           f"({_num(a / self.factor)}{unit}), got {_num(b)}{unit}{why}")
        raise FieldError(at + lhs, f"{words} {self._scaled(format_path(at + rhs))} "
                         f"({_num(self.factor * b)}{unit}), got {_num(a)}{unit}{why}", other)


def _split(dotted: str) -> Path_:
    return tuple(dotted.split(".")) if dotted else ()


def _value_at(obj, path: Path_):
    for name in path:
        obj = getattr(obj, name, None)
    return obj


def _unit(obj, path: Path_) -> str:
    """`` m`` for a field whose range has unit m, else ``""``."""
    for name in path[:-1]:
        obj = getattr(obj, name, None)
    fields = {f.name: f for f in dataclasses.fields(obj)} if dataclasses.is_dataclass(obj) else {}
    rule = rule_of(fields[path[-1]]) if path[-1] in fields else None
    unit = getattr(rule, "unit", "") or getattr(getattr(rule, "each", None), "unit", "")
    return f" {unit}" if unit else ""

# ---- declaring and checking -------------------------------------------------------------------

_RULE = "rule"
_RELATIONS = "relations"


def ranged(default, rule: Rule, *, relations: tuple[Relation, ...] = (), **kwargs):
    """A dataclass field with ``default`` (a callable: its default factory, e.g. for a list),
    its ``rule`` and the bounds other fields set it (``relations``) as metadata."""
    metadata = {_RULE: rule, _RELATIONS: tuple(relations)}
    if callable(default):
        return dataclasses.field(default_factory=default, metadata=metadata, **kwargs)
    return dataclasses.field(default=default, metadata=metadata, **kwargs)


def section(factory, *relations: Relation):
    """A field holding a config (``factory`` makes its default) and the bounds between a field
    of it and a field elsewhere in the declaring config (each :class:`Relation` with ``field``
    set)."""
    return dataclasses.field(default_factory=factory, metadata={_RELATIONS: relations})


def rule_of(f: dataclasses.Field) -> Rule | None:
    """The rule declared on dataclass field ``f``, or None."""
    return f.metadata.get(_RULE)


def relations_of(f: dataclasses.Field) -> tuple[Relation, ...]:
    """The bounds declared on dataclass field ``f``."""
    return f.metadata.get(_RELATIONS, ())


def check_ranges(obj, at: Path_ = ()) -> None:
    """Each field of dataclass ``obj`` against its declared type (:func:`check_type`) and its
    rule (``at``: where ``obj`` is, for the error's path)."""
    hints = _type_hints(type(obj))
    for f in dataclasses.fields(obj):
        value, rule = getattr(obj, f.name), rule_of(f)
        if not isinstance(rule, Items | FilePath):  # (these rules say what they hold)
            check_type(at + (f.name,), value, hints.get(f.name, f.type))
        if rule is not None:
            rule.check(at + (f.name,), value)


def check_bounds(obj, at: Path_ = ()) -> None:
    """The :class:`Relation` bounds declared on the fields of dataclass ``obj``."""
    for f in dataclasses.fields(obj):
        for relation in relations_of(f):
            relation.check(obj, f.name, at)


def check_fields(obj, at: Path_ = ()) -> None:
    """:func:`check_ranges`, :func:`check_bounds`, then ``obj``'s own ``check_relations(at)``
    (if it has one)."""
    check_ranges(obj, at)
    check_bounds(obj, at)
    relations = getattr(obj, "check_relations", None)
    if relations is not None:
        relations(at)


# ---- types ------------------------------------------------------------------------------------


def is_number(value) -> bool:
    """An int or float (numpy's too), not a bool."""
    return isinstance(value, int | float | np.number) and not isinstance(value, bool | np.bool_)


def is_sequence(value) -> bool:
    """A list, a tuple or a 1-d numpy array (what a list field may hold in code)."""
    return isinstance(value, list | tuple) or (isinstance(value, np.ndarray) and value.ndim == 1)


def shown(value) -> str:
    """``0.5 (a float)``: a value and its type, for a message about a value given in code."""
    if isinstance(value, type):
        return f"the class {value.__name__} (not an instance of it)"
    text = " ".join(repr(value).split())
    text = text if len(text) <= 60 else text[:57] + "..."
    return f"{text} ({_a(type(value).__name__)})"


def _a(name: str) -> str:
    """``a float``, ``an ObjectConfig``."""
    return f"{'an' if name[:1].lower() in 'aeiou' else 'a'} {name}"


@functools.cache
def _type_hints(cls) -> dict:
    try:
        return typing.get_type_hints(cls)
    except Exception:  # noqa: BLE001  (a forward reference that does not resolve)
        return {}


_KIND_WORDS = {bool: "true or false", int: "an integer", float: "a number", str: "a string"}


def check_type(path: Path_, value, kind) -> None:
    """Raises :class:`FieldError` when ``value`` is not of the annotated type ``kind``: a
    number type for ``float`` (an int too), an integer for ``int``, a bool, a str, a list (a
    tuple or 1-d array too) of such, None or the type for ``Optional``, an instance of any
    other class (a config of ours, a Drake struct). A config built in code may hold anything;
    a loaded one is typed by the loader already."""
    args = typing.get_args(kind)
    if typing.get_origin(kind) in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return
        options = [a for a in args if a is not type(None)]
        if len(options) == 1:
            check_type(path, value, options[0])
        return  # a union of several: Drake's loader knows its variants
    if kind is float:
        ok = is_number(value)
    elif kind is int:
        ok = isinstance(value, int | np.integer) and not isinstance(value, bool)
    elif kind is bool:
        ok = isinstance(value, bool | np.bool_)
    elif kind is str:
        ok = isinstance(value, str)
    elif typing.get_origin(kind) is list:
        if not is_sequence(value):
            raise FieldError(path, f"expected a list, got {shown(value)}")
        if args and args[0] not in (float, int):  # numbers: the field's rule checks each
            for i, v in enumerate(value):
                check_type(path + (i,), v, args[0])
        return
    elif isinstance(kind, type) and kind.__module__ != "builtins":
        ok = isinstance(value, kind)
        if not ok:
            raise FieldError(path, f"expected {_a(kind.__name__)}, got {shown(value)}")
        return
    else:
        return  # dict, Any...: not checked here
    if not ok:
        raise FieldError(path, f"expected {_KIND_WORDS[kind]}, got {shown(value)}")


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
