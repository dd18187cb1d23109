"""Generated bad inputs that walk every field of the scenario schema.

For every field reachable through mappings (our dataclasses and Drake's config structs): a
non-finite number (nan, inf, -inf) where it takes a number, a value of the wrong type, an
unknown sub-field where it takes a mapping; for every rule (``gbh_drake.scenario.checks.rule_table``): a
value on each side out of its range, a name that is not allowed, a list of the wrong length;
for every bound between fields (``gbh_drake.scenario.checks.relation_table``): a value of the
bounded field beyond its bound.
Each case runs through the real command line: exit code 2, one line naming the file, the
field's exact path and its line, nothing written. Lists of Drake structs (``directives``,
``cameras``) and poses (``schema.Transform``) are walked by hand in tests/input/input_corpus.py.
"""

from __future__ import annotations

import dataclasses
import math
import typing

import numpy as np
import pytest

from gbh_drake.cli import main
from gbh_drake.core.ranges import Fixed, Items, OneOf, Range, format_path
from gbh_drake.scenario import Scenario
from gbh_drake.scenario.checks import relation_table, rule_table
from gbh_drake.yamlfiles.yaml_text import optional_of, struct_fields, union_options

RULES = rule_table()

#: Fields walked by hand (input_corpus.py): lists of Drake structs and poses.
BY_HAND = {("directives",), ("cameras",), ("object", "pose"), ("source_path",)}


def leaves(schema=Scenario, path=()):
    """(path, type) of every field reachable through mappings; structs are also yielded."""
    for name, kind in struct_fields(schema).items():
        sub = path + (name,)
        if sub in BY_HAND:
            continue
        inner = optional_of(kind) or kind
        if struct_fields(inner) is not None and inner is not np.ndarray:
            yield sub, inner
            yield from leaves(inner, sub)
        elif union_options(inner) is None:
            yield sub, inner


def yaml_at(path: tuple, value: str) -> tuple[str, int]:
    """Block YAML setting ``path`` to ``value`` (a YAML scalar or flow text), and its line."""
    lines = [f"{'  ' * i}{part}:" for i, part in enumerate(path[:-1])]
    lines.append(f"{'  ' * (len(path) - 1)}{path[-1]}: {value}")
    return "\n".join(lines) + "\n", len(path)


def _kind_cases():
    cases = []
    for path, kind in leaves():
        key = format_path(path)
        if struct_fields(kind) is not None:
            cases.append((f"{key}:unknown", path + ("zzz",), "{zzz: 1}", "unknown field"))
            cases.append((f"{key}:scalar", path, "3", "expected a mapping"))
        elif kind is float:
            for text in (".nan", ".inf", "-.inf"):
                cases.append((f"{key}:{text}", path, text, "must be a finite number"))
            cases.append((f"{key}:word", path, "twelve", "expected a number, got 'twelve'"))
            cases.append((f"{key}:list", path, "[1, 2]", "expected a number, got a list"))
        elif kind is int:
            cases.append((f"{key}:word", path, "twelve", "expected an integer, got 'twelve'"))
            cases.append((f"{key}:nan", path, ".nan", "expected an integer"))
            cases.append((f"{key}:fraction", path, "2.5", "expected an integer"))
        elif kind is bool:
            cases.append((f"{key}:word", path, "maybe", "expected true or false, got 'maybe'"))
        elif kind is str:
            cases.append((f"{key}:list", path, "[a, b]", "expected a string, got a list"))
            cases.append((f"{key}:mapping", path, "{a: b}", "expected a string, got a mapping"))
        elif typing.get_origin(kind) is list:
            cases.append((f"{key}:string", path, "'123'", "expected a list, got '123'"))
            cases.append((f"{key}:nan", path + (0,), "[.nan, 0, 0, 0, 0, 0, 0]",
                          "must be a finite number"))
        elif kind is np.ndarray:  # an Rgba's components
            cases.append((f"{key}:nan", path, "[.nan, 0, 0, 1]", "Rgba values must be within"))
    return cases


def _fmt(v) -> str:
    if isinstance(v, int) or (float(v).is_integer() and abs(v) < 1e15):
        return str(int(v))
    return repr(float(v))


def _rule_cases():
    cases = []
    for section, rules in RULES.items():
        for name, rule in rules.items():
            path = section + (name,)
            key = format_path(path)
            if isinstance(rule, Range):
                for side, value in _outside(rule):
                    cases.append((f"{key}:{side}", path, _fmt(value), f"must be {rule.text()}"))
            elif isinstance(rule, OneOf):
                cases.append((f"{key}:name", path, "zzz_unknown", "must be one of"))
            elif isinstance(rule, Fixed):
                other = {bool: "false" if rule.value else "true", int: "1", float: "1.5",
                         str: "other"}[type(rule.value)]
                cases.append((f"{key}:fixed", path, other, f"must be {rule.value!r}"))
            elif isinstance(rule, Items):
                if rule.length is not None:
                    short = "[" + ", ".join(["0"] * (rule.length - 1)) + "]"
                    cases.append((f"{key}:length", path, short, f"needs {rule.length}"))
                for side, value in _outside(rule.each):
                    items = [_fmt(value)] + ["1"] * ((rule.length or 1) - 1)
                    cases.append((f"{key}:item_{side}", path + (0,), "[" + ", ".join(items) + "]",
                                  f"must be {rule.each.text()}"))
    return cases


def _outside(rule: Range):
    """A value just below and just above the range, where there is a bound."""
    step = 1 if rule.integer else None
    if rule.lo is not None:
        lo = rule.lo if rule.lo_open and not rule.integer else \
            rule.lo - (step or max(abs(rule.lo) * 0.5, 1e-6))
        yield "low", lo
    if rule.hi is not None:
        hi = rule.hi if rule.hi_open and not rule.integer else \
            rule.hi + (step or max(abs(rule.hi) * 0.5, 1e-6))
        yield "high", hi


def _relation_cases():
    """For each bound, the bounded field alone set beyond the other field's default (1.5 times
    past it, or to the end of its own range when that is nearer)."""
    defaults, cases = Scenario(), []
    for at, name, relation in relation_table():
        lhs, rhs = at + relation.lhs(name), at + tuple(relation.other.split("."))
        bound = relation.factor * _value(defaults, rhs)
        value = bound * 1.5 if relation.op in ("<=", "<") else bound / 1.5
        rule = RULES[lhs[:-1]][lhs[-1]]
        value = min(max(value, rule.lo if rule.lo is not None else value),
                    rule.hi if rule.hi is not None else value)
        value = round(value) if rule.integer else value
        cases.append((f"{format_path(lhs)}:{relation.op}{format_path(rhs)}", lhs, _fmt(value),
                      "must "))
    return cases


def _value(obj, path):
    for part in path:
        obj = getattr(obj, part)
    return obj


KIND_CASES = _kind_cases()
RULE_CASES = _rule_cases()
RELATION_CASES = _relation_cases()
#: A field whose out-of-range value another check meets first (documented here).
RULE_EXCEPTIONS = {
    # scan.first_look_scale high also leaves first-look images under 8 pixels (same field).
}


def _run(tmp_path, capsys, path, value):
    text, line = yaml_at(path if not isinstance(path[-1], int) else path[:-1], value)
    # A pick needs max_time > settle_time: keep it so for settle_time cases.
    if path[0] == "settle_time":
        text += "max_time: 600\n"
    scenario = tmp_path / "bad.yaml"
    scenario.write_text(text)
    code = main(["run", str(scenario)])
    out, err = capsys.readouterr()
    return code, out, err, scenario, line


@pytest.mark.parametrize(("case_id", "path", "value", "expect"), KIND_CASES,
                         ids=[c[0] for c in KIND_CASES])
def test_every_field_kind(case_id, path, value, expect, tmp_path, capsys):
    code, out, err, scenario, line = _run(tmp_path, capsys, path, value)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "Traceback" not in err
    field = format_path(path)
    prefix = f"gbh: invalid scenario: {scenario}: "
    assert err.startswith(prefix), err
    where = err[len(prefix):]
    # The field, or for a struct's bad sub-value Drake's own struct (e.g. an Rgba) is named.
    assert where.startswith(f"{field} (line {line}): ") or \
        where.startswith(f"{format_path(path[:-1])}"), where
    assert expect in where, where
    assert not (tmp_path / "output").exists()


@pytest.mark.parametrize(("case_id", "path", "value", "expect"), RULE_CASES,
                         ids=[c[0] for c in RULE_CASES])
def test_every_rule(case_id, path, value, expect, tmp_path, capsys):
    code, out, err, scenario, line = _run(tmp_path, capsys, path, value)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    field = format_path(path)
    assert err.startswith(f"gbh: invalid scenario: {scenario}: {field} (line {line}): "), err
    assert expect in err, err
    assert not (tmp_path / "output").exists()


@pytest.mark.parametrize(("case_id", "path", "value", "expect"), RELATION_CASES,
                         ids=[c[0] for c in RELATION_CASES])
def test_every_bound(case_id, path, value, expect, tmp_path, capsys):
    """The field written is the one named, at its line (the first bound it breaks, which may be
    another of its bounds than this case's)."""
    code, out, err, scenario, line = _run(tmp_path, capsys, path, value)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    field = format_path(path)
    assert err.startswith(f"gbh: invalid scenario: {scenario}: {field} (line {line}): must "), err
    assert not (tmp_path / "output").exists()


def test_every_field_is_walked():
    """The generated cases reach every leaf of the schema (but those walked by hand)."""
    walked = {c[1][:-1] if isinstance(c[1][-1], int) or c[1][-1] == "zzz" else c[1]
              for c in KIND_CASES}
    for path, _ in leaves():
        assert path in walked, path
    assert len(KIND_CASES) > 300 and len(RULE_CASES) > 250 and len(RELATION_CASES) >= 29


def test_every_number_has_a_rule_or_is_finite_only():
    """Each numeric field of our own dataclasses has a range rule, or is listed here as a
    field where any finite value is meaningful."""
    finite_only = {
        ("object", "random_pose", "x"), ("object", "random_pose", "y"),
        ("antipodal", "weight_direction"),
    }
    ours = [(p, k) for p, k in leaves() if k in (int, float) or typing.get_origin(k) is list]
    drake_structs = {("plant_config",), ("simulator_config",), ("visualization",)}
    missing = []
    for path, _ in ours:
        if path[:1] in drake_structs and path[-1] not in RULES.get(path[:1], {}):
            continue  # Drake's own fields: finite, and Drake's checks (ranges where listed)
        if len(path) >= 2 and "color" in path[-2]:
            continue
        if path[-1] not in RULES.get(path[:-1], {}) and path not in finite_only:
            missing.append(format_path(path))
    assert missing == []


def test_nan_everywhere_is_refused_by_the_walk():
    """check_finite reaches numbers inside Drake structs, distributions and lists."""
    from pydrake.common import schema

    from gbh_drake.core.ranges import FieldError
    from gbh_drake.scenario.checks import check_finite

    s = Scenario()
    s.object.pose.translation = schema.UniformVector[3](min=[0, 0, 0], max=[0, math.nan, 0])
    with pytest.raises(FieldError) as info:
        check_finite(s)
    assert info.value.path == ("object", "pose", "translation", "max", 1)
    s = Scenario()
    s.directives[3].add_weld.X_PC.translation = np.array([0.0, math.inf, 0.0])
    with pytest.raises(FieldError) as info:
        check_finite(s)
    assert info.value.path == ("directives", 3, "add_weld", "X_PC", "translation", 1)
    s = Scenario()
    s.robot.hand.speed = 10**400
    with pytest.raises(FieldError):
        check_finite(s)


def test_walk_covers_dataclass_fields():
    for path, kind in leaves():
        if dataclasses.is_dataclass(kind):
            assert struct_fields(kind), path
