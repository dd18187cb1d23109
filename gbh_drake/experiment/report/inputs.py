"""What a report is made of: an experiment folder's rows, read once into the frame
(:mod:`~gbh_drake.experiment.report.columns`), and what its saved experiment says.

Damage that leaves a row without its trial (not JSON, a row without one of the rows' fields,
a key field of the wrong type, a ``protocol`` that is not a name) and a damaged
``experiment.yaml`` (one asking for more trials than an experiment may have) raise
:class:`~gbh_drake.experiment.rows.FolderError` naming the file, the line and the field: the
report cannot go on. Any other field of the wrong type, or a NaN or infinite number, is read as
missing and ``warn`` is told (file, line, field); everything else is reported.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd
import yaml

from gbh_drake.experiment.report.columns import _checked, frame_of
from gbh_drake.experiment.rows import (
    DEFAULT_PROTOCOL,
    FolderError,
    RowStore,
    protocol_of,
    read_jsonl,
    row_key,
    sort_key,
)

#: Files of an experiment folder besides the rows.
EXPERIMENT_FILE = "experiment.yaml"
RUNS_FILE = "runs.jsonl"

Warn = Callable[[str], None] | None


@dataclass
class ReportInput:
    """What a report is made of: the rows (ordered), their frame (:attr:`frame`, built once)
    and what the experiment said."""

    name: str
    objects: list[str]
    methods: list[str]
    trials: int
    paper: dict[str, str]
    """Method -> the paper's Table-1 row shown beside it."""
    rows: list[dict]
    left_out: int = 0
    """Rows in the file that are not trials of the experiment (an older definition)."""
    expected: bool = True
    """``objects``, ``methods`` and ``trials`` come from the experiment (not from the rows)."""
    protocols: list[str] = field(default_factory=lambda: [DEFAULT_PROTOCOL])
    """The experiment's protocols, in its order."""
    source: str = "rows"
    """The rows' file (named in warnings)."""
    lines: list[int] | None = None
    """Each row's line in ``source``."""
    object_set: str = ""
    """The experiment's object set, as its ``experiment.yaml`` names it (relative to the
    folder), or ""."""
    built: pd.DataFrame | None = field(default=None, repr=False, compare=False)
    """The frame, once built (:attr:`frame`)."""

    @property
    def frame(self) -> pd.DataFrame:
        """The rows as one typed frame (:data:`~gbh_drake.experiment.report.columns.COLUMNS`),
        in the rows' order, built on first use."""
        if self.built is None:
            self.read()
        return self.built

    def read(self, warn: Warn = None) -> ReportInput:
        """Builds :attr:`frame`, telling ``warn`` what was read as missing; returns self."""
        self.built = frame_of(self.rows, source=self.source, lines=self.lines, warn=warn)
        return self

    def of_protocol(self, protocol: str) -> ReportInput:
        """The input of one protocol's rows."""
        keep = (self.frame.protocol == protocol).to_numpy()
        return dataclasses.replace(
            self, rows=[r for r, k in zip(self.rows, keep, strict=True) if k], protocols=[protocol],
            lines=None if self.lines is None else
            [n for n, k in zip(self.lines, keep, strict=True) if k],
            built=self.frame[keep].reset_index(drop=True))


def read_input(folder: Path, *, warn: Warn = None) -> ReportInput:
    """The rows of ``folder`` and its saved experiment (when there is one), the frame built. A
    last row cut short by an interrupted write is left out (``warn`` is told); see the module
    docstring for the rest."""
    folder = Path(folder)
    store = RowStore(folder)
    rows = store.load(warn=warn)
    lines = _line_numbers(store.path, len(rows))
    unique = {row_key(r): (r, n) for r, n in zip(rows, lines, strict=True)}  # the last row
    saved = folder / EXPERIMENT_FILE
    if saved.is_file():  # written by the runner (yaml_dump_typed of the Experiment: no tags)
        e = read_saved_experiment(saved)
        objects, trials = list(e.get("objects") or []), int(e.get("trials", 0))
        methods = [m["name"] for m in e.get("methods") or []]
        protocols = list(e.get("protocols") or [DEFAULT_PROTOCOL])
        kept = [v for (o, m, t, p), v in unique.items()
                if o in objects and m in methods and 0 <= t < trials and p in protocols]
        data = ReportInput(e.get("name") or folder.name, objects, methods, trials,
                           {m["name"]: m["paper"] for m in e.get("methods") or []
                            if m.get("paper")}, [], left_out=len(unique) - len(kept),
                           protocols=protocols, object_set=e.get("object_set") or "")
    else:
        kept = list(unique.values())
        protocols = sorted({protocol_of(r) for r, _ in kept} | {DEFAULT_PROTOCOL},
                           key=lambda p: (p != DEFAULT_PROTOCOL, p))
        if len(protocols) > 1 and not any(protocol_of(r) == DEFAULT_PROTOCOL for r, _ in kept):
            protocols.remove(DEFAULT_PROTOCOL)
        data = ReportInput(folder.name, sorted({r["object"] for r, _ in kept}),
                           sorted({r["method"] for r, _ in kept}),
                           1 + max((int(r["trial"]) for r, _ in kept), default=-1), {}, [],
                           expected=False, protocols=protocols)
    order = sort_key(data.objects, data.methods, data.protocols)
    kept.sort(key=lambda v: order(v[0]))
    data.rows, data.lines, data.source = [r for r, _ in kept], [n for _, n in kept], \
        str(store.path)
    return data.read(warn)


def _line_numbers(path: Path, n: int) -> list[int]:
    """The lines of ``path`` that :meth:`RowStore.load` read ``n`` rows from (the non-blank
    lines before the last newline)."""
    try:
        *lines, _ = path.read_bytes().split(b"\n")
    except OSError:
        lines = []
    numbers = [i + 1 for i, line in enumerate(lines) if line.strip()]
    return numbers if len(numbers) == n else list(range(1, n + 1))


def read_saved_experiment(path: Path) -> dict:
    """The fields of a folder's ``experiment.yaml`` that reports read (``name``, ``objects``,
    ``trials``, ``methods`` with their ``name`` and ``paper``, ``protocols``, ``object_set``),
    checked (the trials in all at most the experiment's own bound, ``MAX_TOTAL_TRIALS``); raises
    :class:`~gbh_drake.experiment.rows.FolderError` naming the file, the field and the line."""
    damaged = "the folder's experiment.yaml is damaged (gbh experiment writes it again)"
    try:
        text = path.read_bytes().decode("utf-8")
    except OSError as e:
        raise FolderError(f"{path}: cannot read it ({e.strerror or e})") from None
    except UnicodeDecodeError as e:
        raise FolderError(f"{path}: not UTF-8 text (byte at offset {e.start}); {damaged}") \
            from None
    try:
        e = yaml.safe_load(text)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f"line {mark.line + 1}: " if mark else ""
        raise FolderError(f"{path}: {where}not valid YAML; {damaged}") from None
    if e is None:
        e = {}
    if not isinstance(e, dict):
        raise FolderError(f"{path}: not a mapping of fields; {damaged}")

    def bad(field: str, expected: str, value) -> FolderError:
        return FolderError(f"{path}: {field}: expected {expected}, got {value!r}; {damaged}")

    def names(field: str) -> list:
        value = e.get(field) or []
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise bad(field, "a list of names", value)
        return value

    for key in ("name", "object_set"):
        if e.get(key) is not None and not isinstance(e[key], str):
            raise bad(key, "a string", e[key])
    trials = e.get("trials", 0)
    if not isinstance(trials, int) or isinstance(trials, bool) or trials < 0:
        raise bad("trials", "a whole number", trials)
    methods = e.get("methods") or []
    if not isinstance(methods, list):
        raise bad("methods", "a list", methods)
    for i, m in enumerate(methods):
        if not isinstance(m, dict) or not isinstance(m.get("name"), str):
            raise bad(f"methods[{i}]", "a method with a name", m)
        if m.get("paper") is not None and not isinstance(m["paper"], str):
            raise bad(f"methods[{i}].paper", "a string", m["paper"])
    from gbh_drake.experiment.config import MAX_TOTAL_TRIALS  # (config imports this package)

    sizes = (len(names("objects")), trials, len(methods), len(names("protocols")) or 1)
    total = sizes[0] * sizes[1] * sizes[2] * sizes[3]
    if total > MAX_TOTAL_TRIALS:
        raise FolderError(f"{path}: trials: {sizes[0]} objects x {trials} trials x {sizes[2]} "
                          f"methods x {sizes[3]} protocols are {total} trials; at most "
                          f"{MAX_TOTAL_TRIALS} in one experiment; {damaged}")
    return e


def read_runs(folder: Path, *, warn: Warn = None, repair: bool = False) -> list[dict]:
    """The runs of ``runs.jsonl`` (one JSON object a line; damage as for the rows:
    :func:`~gbh_drake.experiment.rows.read_jsonl`), each field checked: ``started``,
    ``engine`` (text), ``trials`` (an integer), ``wall`` (s), ``interrupted``, ``reused`` (rows
    taken from other folders: an integer, only when there were some); one of the wrong type is
    missing (``warn`` is told, naming the file and line)."""
    path = Path(folder) / RUNS_FILE
    runs = read_jsonl(path, warn=warn, repair=repair,
                      check=lambda v: None if isinstance(v, dict) else
                      f"not a run (a JSON object), got {type(v).__name__}")
    kinds = {"started": "str", "engine": "str", "trials": "int", "wall": "float",
             "interrupted": "bool", "reused": "int"}
    out = []
    for i, run in enumerate(runs):
        checked = dict(run)
        for name, kind in kinds.items():
            value, ok = _checked(kind, run.get(name))
            checked[name] = None if value is None else value
            if not ok and warn is not None:
                warn(f"{path}: run {i + 1}: {name}: expected {kind}, got {run[name]!r}; read "
                     "as missing")
        out.append(checked)
    return out
