"""The report's one table: the rows read once into a pandas DataFrame, a trial per row, typed.

:data:`COLUMNS` lists every column (name, pandas dtype, meaning, where in a row it comes from);
:func:`frame_of` builds the frame. A field a row does not have (an older row) is the column's
missing value (``<NA>``); a field of the wrong type, or a number that is NaN or infinite, is
missing too and ``warn`` is told once per row and field, naming the file, the line and the
field (the first :data:`WARNINGS_PER_FIELD` rows of a field; then how many more). The
sections never read a row themselves.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import pandas as pd

from gbh_drake.core.resting import resting_pose
from gbh_drake.experiment.rows import DEFAULT_PROTOCOL
from gbh_drake.experiment.taxonomy import cause_of

#: pandas dtypes of the columns.
STR, INT, FLOAT, BOOL, OBJ = "string", "Int64", "Float64", "boolean", "object"


@dataclass(frozen=True)
class Column:
    """One column of the frame."""

    name: str
    dtype: str
    meaning: str
    path: tuple[str, ...] | None
    """Keys of the value in a row (``("record", "verdict", "sank_at")``); None: derived from
    other columns."""
    kind: str = ""
    """What the row must hold there: ``str``, ``int``, ``float``, ``bool``, ``names`` (a list of
    strings), ``counts`` (a mapping of names to integers), ``list`` (its length is kept),
    ``dict``, ``pose`` (6 numbers); "" derived."""
    csv: bool = True
    """Written to ``trials.csv``."""


def _row(name, dtype, kind, meaning, *path, csv=True) -> Column:
    return Column(name, dtype, meaning, tuple(path) or (name,), kind, csv)


def _derived(name, dtype, meaning, csv=True) -> Column:
    return Column(name, dtype, meaning, None, "", csv)


#: The start pose's components (m, rad) as columns ``pose_x`` ... ``pose_yaw``.
POSE_AXES = ("x", "y", "z", "roll", "pitch", "yaw")
#: The stage times of a row shown in the report (wall s): columns ``time_<stage>``.
STAGES = ("build", "scan", "grasps", "plan", "simulate", "total")
#: Record fields copied into trials.csv.
RECORD_FIELDS = ("n_structures", "n_candidates", "n_ranked", "true_parts", "true_part_found",
                 "grasped_true_part", "best_score", "lift", "sim_time")
#: The start of the plan note that says the unseen space raised the lift (planning/pick.py).
UNSEEN_LIFT_NOTE = "the lift allows for unseen space"
#: The phases in which a lifted object that comes back down while held decides success.
CARRIED_PHASES = ("lift", "carry", "hold")
#: The cause of a failed row whose outcome the taxonomy does not know.
UNKNOWN_CAUSE = "unknown"
#: Warnings printed per field before they are counted instead.
WARNINGS_PER_FIELD = 3

_RECORD_KINDS = {"n_structures": ("int", INT), "n_candidates": ("int", INT), "n_ranked": ("int", INT),
                 "true_parts": ("int", INT), "true_part_found": ("bool", BOOL),
                 "grasped_true_part": ("bool", BOOL), "best_score": ("float", FLOAT),
                 "lift": ("float", FLOAT), "sim_time": ("float", FLOAT)}

#: The row's other plain fields, (dtype, kind, meaning): in trials.csv in this (alphabetical) order.
_ROW_REST = {
    "commit": (STR, "str", "the code's commit"),
    "experiment": (STR, "str", "the experiment's name when the row was written"),
    "fallback": (BOOL, "bool", "the executed grasp was the fallback's"),
    "grasp_method": (STR, "str", "the scenario's grasp_method (gbh, antipodal, gbh_plus, ...)"),
    "reason": (STR, "str", "the verdict's reason, in words"),
    "replay": (STR, "str", "the replay's path in the folder, or empty"),
    "scenario_digest": (STR, "str", "digest of the trial's scenario"),
    "viewpoints": (INT, "int", "camera viewpoints of the scan"),
    "worker": (STR, "str", "host:pid of the worker"),
}

#: Every column, in the order of ``trials.csv`` (columns with ``csv=False`` are the frame's
#: alone). Times in s, lengths in m.
COLUMNS: tuple[Column, ...] = (
    _row("object", STR, "str", "the object's name"),
    _row("is_control", BOOL, "bool", "the row says the object has nothing to hang by"),
    _row("method", STR, "str", "the experiment's method name (gbh-10, antipodal, ...)"),
    _row("trial", INT, "int", "trial index of (object, method, protocol)"),
    _row("protocol", STR, "str", "how the object was set down (stable, natural); stable when the "
                               "row has none"),
    _row("seed", INT, "int", "the trial's seed"),
    _row("outcome", STR, "str", "the verdict's outcome (success, not_lifted, ...)"),
    _row("success", BOOL, "bool", "picked and carried"),
    _row("held_by", STR, "str", "cage or pinch (a success), else empty"),
    _derived("cause", STR, "the failure's cause class (taxonomy.py); empty for a success"),
    _row("grasp_kind", STR, "str", "the executed grasp's kind (parallel, vertical, scoop, "
                                 "antipodal), empty without one"),
    _row("grasp_rank", INT, "int", "the executed grasp's rank in its list; -1 without one"),
    _row("grasp_score", FLOAT, "float", "the executed grasp's score"),
    _derived("resting_pose", STR, "upright, on its side, upside down (the start pose's tilt); "
                                "empty without a pose"),
    *(_row(name, dtype, kind, meaning) for name, (dtype, kind, meaning) in _ROW_REST.items()),
    _row("refusals", OBJ, "counts", "grasps refused: {reason:stage: count} (trials.csv: "
                                  "'key xN')"),
    *(_row(f"pose_{a}", FLOAT, "", f"the start pose's {a} (m or rad)", "pose") for a in POSE_AXES),
    *(_row(name, dtype, kind, f"the record's {name}", "record", name)
      for name, (kind, dtype) in _RECORD_KINDS.items()),
    _row("released_on_table", BOOL, "bool", "free on the table at the end (not part of success)",
         "record", "verdict", "released_on_table"),
    *(_row(f"time_{s}", FLOAT, "float", f"wall s of the {s} stage", "stage_times", s)
      for s in STAGES),
    _row("table_touch_while_carried", BOOL, "bool", "the lifted object touched the table during "
         "the lift or carry", "record", "verdict", "table_touch_while_carried"),
    _row("sank_phase", STR, "str", "phase in which the lifted object came back below half the "
         "lifted height while a gripper body touched it; empty if it did not",
         "record", "verdict", "sank_phase"),
    _row("sank_at", FLOAT, "float", "s: when it did", "record", "verdict", "sank_at"),
    _row("min_clearance_after_lift", FLOAT, "float", "m: the object's lowest point above the table "
         "after it was lifted, while held (rows that have it)",
         "record", "verdict", "min_clearance_after_lift"),
    _row("min_clearance_phase", STR, "str", "the phase of min_clearance_after_lift",
         "record", "verdict", "min_clearance_phase"),
    _derived("borderline_success", BOOL, "a success whose lifted object came back down while "
                                      "held (sank_phase lift, carry or hold) or touched the "
                                      "table while carried"),
    _row("gbh_preset", STR, "str", "GbH rules: '' ours, 'paper'", "record", "gbh_preset",
         csv=False),
    _row("grasp_source", STR, "str", "the executed grasp's source (grasps, scoop_grasps, "
         "tall_scoop_grasps, fallback_grasps)", "record", "grasp_source", csv=False),
    _row("regrasps", INT, "list", "set-downs in a new pose before the pick", "record", "regrasps",
         csv=False),
    _row("attempts", INT, "list", "lifts that came away empty (each followed by a retry)",
         "record", "attempts", csv=False),
    _row("lift_raised", BOOL, "names", "the plan raised the lift for unseen space",
         "record", "plan_notes", csv=False),
    _row("set_down", BOOL, "dict", "the trial went on to set the object down (a 'lower' phase; "
         "rows without phases: true)", "record", "phases", csv=False),
    _row("scan_warnings", OBJ, "names", "the scan's warnings (tuple; the cause reads them)",
         "record", "scan_warnings", csv=False),
    _row("rejected_by", OBJ, "counts", "candidates each GbH collision rule removed",
         "record", "rejected_by", csv=False),
    _row("record_refusals", OBJ, "counts", "the record's refusals (for rows without their own)",
         "record", "refusals", csv=False),
    _row("reach_true", STR, "str", "the reach search on the true mesh", "reach", "true",
         csv=False),
    _row("reach_scan", STR, "str", "the reach search on the trial's scan", "reach", "scan",
         csv=False),
    _derived("reach_class", STR, "a no-grasp trial's reach class (REACH_CLASSES)", csv=False),
    _derived("held_how", STR, "how a success was taken (HELD_HOW)", csv=False),
    _derived("dragged", BOOL, "the reason says dragged (held, touching the table at the place)",
             csv=False),
    _row("object_tags", OBJ, "names", "the object set's tags of the object (frozenset; new rows)",
         csv=False),
)

BY_NAME = {c.name: c for c in COLUMNS}

#: A no-grasp trial's reach, from its row's ``reach`` field (gbh_drake/experiment/reach.py).
REACH_CLASSES = ("out of reach", "candidate set missed", "lost in the scan", "undecided",
                 "not analysed")
#: The ways a success came (:func:`held_how_of`).
HELD_HOW = ("hook", "scoop", "tall scoop", "regrasp, hook", "regrasp, scoop",
            "regrasp, tall scoop", "regrasp, fallback pinch", "fallback pinch", "pinch")

_KIND_WORDS = {"str": "a string", "int": "an integer", "float": "a finite number",
               "bool": "true or false", "names": "a list of strings",
               "counts": "a mapping of names to integers", "list": "a list",
               "dict": "a mapping", "pose": "6 finite numbers (x, y, z, roll, pitch, yaw)"}


def _number(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def _checked(kind: str, v):
    """(value, ok) of a row's value ``v`` read as ``kind`` (None is missing, and fine)."""
    if v is None:
        return None, True
    if kind == "str":
        return (v, True) if isinstance(v, str) else (None, False)
    if kind == "int":
        ok = _number(v) and float(v).is_integer()
        return (int(v), True) if ok else (None, False)
    if kind == "float":
        return (float(v), True) if _number(v) else (None, False)
    if kind == "bool":
        return (v, True) if isinstance(v, bool) else (None, False)
    if kind == "names":
        ok = isinstance(v, list) and all(isinstance(x, str) for x in v)
        return (tuple(v), True) if ok else (None, False)
    if kind == "counts":
        ok = isinstance(v, dict) and all(isinstance(n, int) and not isinstance(n, bool)
                                         for n in v.values())
        return ({str(k): n for k, n in v.items()}, True) if ok else (None, False)
    if kind == "list":
        return (len(v), True) if isinstance(v, list) else (None, False)
    if kind == "dict":
        return (v, True) if isinstance(v, dict) else (None, False)
    if kind == "pose":
        if v == []:  # a row of a trial that never got a pose (an error)
            return None, True
        ok = isinstance(v, list) and len(v) == 6 and all(_number(x) for x in v)
        return (tuple(float(x) for x in v), True) if ok else (None, False)
    raise ValueError(f"no kind {kind!r}")


class Problems:
    """The warnings of one reading: per field, the first :data:`WARNINGS_PER_FIELD` told to
    ``warn`` at once, the rest counted and told by :meth:`close`."""

    def __init__(self, source: str, warn: Callable[[str], None] | None):
        self.source, self.warn = source, warn
        self.more: dict[str, int] = {}

    def __call__(self, where: str, field: str, problem: str) -> None:
        told = self.more.setdefault(field, -WARNINGS_PER_FIELD)
        self.more[field] = told + 1
        if told < 0 and self.warn is not None:
            self.warn(f"{self.source}: {where}: {field}: {problem}")

    def close(self) -> None:
        for field, n in self.more.items():
            if n > 0 and self.warn is not None:
                self.warn(f"{self.source}: {n} more rows with a bad {field} (each read as "
                          "missing)")


def _value(row: dict, path: tuple[str, ...], kind: str, where: str, problems: Problems):
    value = row
    for key in path:
        if not isinstance(value, dict):  # (a container that is no mapping: told once)
            return None
        value = value.get(key)
    out, ok = _checked(kind, value)
    if not ok:
        shown = repr(value)
        shown = shown if len(shown) <= 60 else shown[:57] + "..."
        problems(where, ".".join(path), f"expected {_KIND_WORDS[kind]}, got {shown}; read as "
                                        "missing")
    return out


def _containers(row: dict, where: str, problems: Problems) -> None:
    """Tells a ``record``, its ``verdict``, ``reach`` or ``stage_times`` that is no mapping."""
    for path in (("record",), ("record", "verdict"), ("reach",), ("stage_times",)):
        value = row
        for key in path:
            value = value.get(key) if isinstance(value, dict) else None
        if value is not None and not isinstance(value, dict):
            problems(where, ".".join(path), f"expected a mapping, got {type(value).__name__}; "
                                            "its fields read as missing")


def clean(row: dict, where: str = "row", problems: Problems | None = None) -> dict:
    """The frame's values of one ``row`` (a parsed line; see :data:`COLUMNS`), each checked;
    ``where`` names it in a warning (``line 12``)."""
    problems = problems or Problems("rows", None)
    _containers(row, where, problems)
    v: dict = {}
    for c in COLUMNS:
        if c.path is None or c.name.startswith("pose_"):
            continue
        v[c.name] = _value(row, c.path, c.kind, where, problems)
    pose = _value(row, ("pose",), "pose", where, problems)
    for i, axis in enumerate(POSE_AXES):
        v[f"pose_{axis}"] = None if pose is None else pose[i]
    v["protocol"] = v["protocol"] if isinstance(v["protocol"], str) and v["protocol"] \
        else DEFAULT_PROTOCOL
    v["object_tags"] = None if v["object_tags"] is None else frozenset(v["object_tags"])
    notes = v["lift_raised"]
    v["lift_raised"] = notes is not None and any(n.startswith(UNSEEN_LIFT_NOTE) for n in notes)
    phases = v["set_down"]
    v["set_down"] = phases is None or not phases or "lower" in phases
    v["resting_pose"] = "" if pose is None else resting_pose(list(pose))
    v["reach_class"] = reach_class_of(v["reach_true"], v["reach_scan"])
    v["held_how"] = held_how_of(v)
    v["dragged"] = "dragged" in _text(v["reason"])
    v["cause"] = _cause(v, where, problems)
    v["borderline_success"] = v["success"] is True and (
        _text(v["sank_phase"]) in CARRIED_PHASES or v["table_touch_while_carried"] is True)
    v["extra"] = {k: x for k, x in row.items() if k not in BY_NAME and k not in _NESTED
                  and (x is None or isinstance(x, str | int | float | bool))}
    return v


#: Row fields that hold others (read through their columns) or are left out (``traceback``).
_NESTED = ("pose", "record", "stage_times", "reach", "traceback")


def _text(value) -> str:
    return "" if value is None else value


def reach_class_of(true, scan) -> str:
    """The reach class (:data:`REACH_CLASSES`) of a ``no_grasp_found`` row from its reach on
    the true mesh and on the scan: *out of reach*, no hook pose of the gripper passes on the
    true mesh; *candidate set missed*, one passes on the true mesh and on the trial's scan;
    *lost in the scan*, on the true mesh only; *undecided*, a search did not finish; *not
    analysed*, no ``reach`` field (a method without GbH, an older row)."""
    if true == "out of reach":
        return "out of reach"
    if true == "reachable":
        return "candidate set missed" if scan == "reachable" else \
            "undecided" if scan == "undecided" else "lost in the scan"
    return "undecided" if true == "undecided" else "not analysed"


def held_how_of(v: dict) -> str:
    """How a success's object was taken (:data:`HELD_HOW`), from a row's values: ``hook`` (a
    GbH grasp as it lay), ``scoop``, ``tall scoop``, ``regrasp, hook`` / ``regrasp, scoop`` /
    ``regrasp, tall scoop`` / ``regrasp, fallback pinch`` (after setting it down anew),
    ``fallback pinch``, ``pinch``."""
    source = v["grasp_source"] or (
        "fallback_grasps" if v["fallback"] is True else "grasps")
    how = {"grasps": "hook" if _text(v["grasp_kind"]) != "antipodal" else "pinch",
           "scoop_grasps": "scoop", "tall_scoop_grasps": "tall scoop",
           "fallback_grasps": "fallback pinch"}.get(source, source)
    regrasped = v["regrasps"] is not None and v["regrasps"] > 0
    return f"regrasp, {how}" if regrasped else how


def _cause(v: dict, where: str, problems: Problems) -> str:
    """The cause class (taxonomy.cause_of) of a row's checked values; :data:`UNKNOWN_CAUSE` for
    an outcome the taxonomy does not know (told)."""
    checked = {"success": v["success"] is True, "outcome": _text(v["outcome"]),
               "reach": {"true": v["reach_true"], "scan": v["reach_scan"]},
               "refusals": v["refusals"] or {},
               "record": {"scan_warnings": list(v["scan_warnings"] or ()),
                          "rejected_by": v["rejected_by"] or {},
                          "refusals": v["record_refusals"] or {}}}
    try:
        return cause_of(checked)
    except ValueError:
        problems(where, "outcome", f"no cause class for the outcome {v['outcome']!r}; cause "
                                   f"{UNKNOWN_CAUSE!r}")
        return UNKNOWN_CAUSE


def frame_of(rows: Sequence[dict], *, source: str = "rows", lines: Sequence[int] | None = None,
             warn: Callable[[str], None] | None = None) -> pd.DataFrame:
    """The frame of ``rows`` (:data:`COLUMNS`, in order, typed; then any other scalar field the
    rows carry, as written); ``lines`` their line numbers in ``source`` (for the warnings,
    told to ``warn``)."""
    problems = Problems(source, warn)
    values = [clean(r, f"line {lines[i]}" if lines else f"row {i + 1}", problems)
              for i, r in enumerate(rows)]
    problems.close()
    extra = list(dict.fromkeys(k for v in values for k in v["extra"]))
    frame = pd.DataFrame([{**{c.name: v[c.name] for c in COLUMNS},
                           **{k: v["extra"].get(k) for k in extra}} for v in values],
                         columns=[c.name for c in COLUMNS] + extra)
    return frame.astype({c.name: c.dtype for c in COLUMNS})
