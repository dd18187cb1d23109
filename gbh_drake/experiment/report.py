"""The experiment's reports, rebuilt from its rows alone.

``summary.md`` holds: the Table-1-style table (objects with hangable parts; Method, Viewpoints,
Total, Success, Fail, Rate and its Wilson 95 % interval, held by cage or pinch) with the paper's
real-robot figures beside it, and under it every pair of methods compared on the same (object,
trial) poses (McNemar's exact test, the difference in rate with a paired-bootstrap 95 %
interval, Holm-adjusted p-values: :mod:`gbh_drake.experiment.stats`); success by resting pose
(upright, on its side, upside down), the controls (objects with nothing to hang) apart, a table
per object (each rate with its interval), the failures by outcome and by cause
(:func:`gbh_drake.experiment.taxonomy.cause_of`), the grasps refused by reason, the executed
grasps by rank, a list of the failed trials with their replays and how to rerun one, and
timings. A rate of zero trials is printed "-".

Beside it, for a researcher to load: ``trials.csv`` (one row per trial: the row's flat fields,
its cause, resting pose, stage times and a few record fields; see :func:`trials_frame`) and
``table1.csv`` (per method: trials, successes, rate, Wilson lo/hi, cage, pinch); the plots
``success.png``/``.svg`` (success per method with Wilson error bars: the totals, then one panel
per object) and ``causes.png``/``.svg`` (the failure causes per method, stacked). Rows are
ordered by object, method and trial as the experiment lists them, never by when they finished,
so the same rows give the same report.

Protocols (``stable``, ``natural``: how the objects were set down): an experiment of the
``stable`` protocol alone gets the report it had before protocols existed (but for the
``protocol`` columns of the CSVs); with another protocol, Table 1 (with its paired comparison),
the resting poses, the per-object tables and the success plot are given once per protocol, and
the tables by method (controls, failures, refusals) have a column per method and protocol
(``gbh-10 (natural)``). A row without a protocol is ``stable``.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd
import yaml

from gbh_drake.core.resting import RESTING_POSES, resting_pose
from gbh_drake.experiment.rows import (
    DEFAULT_PROTOCOL,
    ROWS_FILE,
    FolderError,
    RowStore,
    protocol_of,
    read_jsonl,
    row_key,
    sort_key,
)
from gbh_drake.experiment.stats import holm, mcnemar, wilson
from gbh_drake.experiment.taxonomy import CAUSES, cause_of
from gbh_drake.outputs import write_atomically

#: Files of an experiment folder besides the rows.
EXPERIMENT_FILE = "experiment.yaml"
SUMMARY_FILE = "summary.md"
PLOT_FILE = "success.png"
CAUSES_PLOT_FILE = "causes.png"
TRIALS_CSV = "trials.csv"
TABLE1_CSV = "table1.csv"
RUNS_FILE = "runs.jsonl"

#: The stage times of a row shown in the report (wall seconds).
STAGES = ("build", "scan", "grasps", "plan", "simulate", "total")

#: The paper's Table 1 (real robot, 15 objects x 5 trials): name -> (viewpoints, total, success).
PAPER_TABLE1 = {
    "GraspNet 1 view": (1, 75, 23),
    "GbH 1 view": (1, 75, 54),
    "GbH 10 views": (10, 75, 68),
}

#: What each protocol means, under its Table 1.
PROTOCOL_TEXT = {
    "stable": "Protocol `stable`: each object in one of its stable resting poses, drawn by its "
              "probability, with a random yaw and position.",
    "natural": "Protocol `natural`: each object in the rest a person would set it down in "
               "(declared per object, with its reason, in gbh_drake/objects/catalog.py), with a "
               "random yaw and position; the paper's objects were set down by a person.",
}


@dataclass
class ReportInput:
    """What a report is made of: the rows (ordered) and what the experiment said."""

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


@dataclass
class Tally:
    total: int = 0
    success: int = 0
    cage: int = 0
    pinch: int = 0

    @property
    def fail(self) -> int:
        return self.total - self.success

    def rate(self) -> str:
        return f"{100.0 * self.success / self.total:.1f} %" if self.total else "-"

    def interval(self, digits: int = 1) -> str:
        """The Wilson 95 % interval of the rate, ``[lo, hi] %``; ``-`` without trials."""
        if not self.total:
            return "-"
        lo, hi = wilson(self.success, self.total)
        return f"[{100.0 * lo:.{digits}f}, {100.0 * hi:.{digits}f}] %"

    @classmethod
    def of(cls, rows) -> Tally:
        tally = cls()
        for r in rows:
            tally.add(r)
        return tally

    def add(self, row: dict) -> None:
        self.total += 1
        if row.get("success"):
            self.success += 1
            self.cage += row.get("held_by") == "cage"
            self.pinch += row.get("held_by") == "pinch"


def read_input(folder: Path, *, warn=None) -> ReportInput:
    """The rows of ``folder`` and its saved experiment (when there is one). A last row cut short
    by an interrupted write is left out (``warn`` is told); any other damage raises
    :class:`~gbh_drake.experiment.rows.FolderError` naming the file and line."""
    folder = Path(folder)
    rows = RowStore(folder).load(warn=warn)
    unique = {row_key(r): r for r in rows}  # a trial run twice: its last row
    saved = folder / EXPERIMENT_FILE
    if saved.is_file():  # written by the runner (yaml_dump_typed of the Experiment: no tags)
        e = read_saved_experiment(saved)
        objects, trials = list(e.get("objects", [])), int(e.get("trials", 0))
        methods = [m["name"] for m in e.get("methods", [])]
        protocols = list(e.get("protocols") or [DEFAULT_PROTOCOL])
        wanted = {(o, m, t, p) for o in objects for m in methods for t in range(trials)
                  for p in protocols}
        kept = [r for k, r in unique.items() if k in wanted]
        return ReportInput(e.get("name") or folder.name, objects, methods, trials,
                           {m["name"]: m["paper"] for m in e.get("methods", [])
                            if m.get("paper")},
                           sorted(kept, key=sort_key(objects, methods, protocols)),
                           left_out=len(unique) - len(kept), protocols=protocols)
    objects = sorted({r["object"] for r in unique.values()})
    methods = sorted({r["method"] for r in unique.values()})
    trials = 1 + max((int(r["trial"]) for r in unique.values()), default=-1)
    protocols = sorted({protocol_of(r) for r in unique.values()} | {DEFAULT_PROTOCOL},
                       key=lambda p: (p != DEFAULT_PROTOCOL, p))
    if len(protocols) > 1 and not any(protocol_of(r) == DEFAULT_PROTOCOL
                                      for r in unique.values()):
        protocols.remove(DEFAULT_PROTOCOL)
    return ReportInput(folder.name, objects, methods, trials, {},
                       sorted(unique.values(), key=sort_key(objects, methods, protocols)),
                       expected=False, protocols=protocols)


def read_saved_experiment(path: Path) -> dict:
    """The fields of a folder's ``experiment.yaml`` that reports read (``name``, ``objects``,
    ``trials``, ``methods`` with their ``name`` and ``paper``, ``protocols``), checked; raises
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

    names("objects")
    names("protocols")
    if e.get("name") is not None and not isinstance(e["name"], str):
        raise bad("name", "a string", e["name"])
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
    return e


def write_report(folder: Path, *, warn=None) -> tuple[Path, Path]:
    """Writes ``summary.md``, ``trials.csv``, ``table1.csv`` and the plots (``success`` and
    ``causes``, PNG and SVG) into ``folder`` from its rows; returns the summary and
    ``success.png``. Everything is read (and checked) before anything is written."""
    folder = Path(folder)
    data = read_input(folder, warn=warn)
    runs = read_runs(folder, warn=warn)
    summary = folder / SUMMARY_FILE
    write_atomically(summary, summary_markdown(data, runs=runs))
    write_atomically(folder / TRIALS_CSV, trials_frame(data).to_csv(index=False))
    write_atomically(folder / TABLE1_CSV, table1_frame(data).to_csv(index=False))
    plot = folder / PLOT_FILE
    plot_success(data, plot)
    plot_causes(data, folder / CAUSES_PLOT_FILE)
    return summary, plot


def read_runs(folder: Path, *, warn=None, repair: bool = False) -> list[dict]:
    """The runs of ``runs.jsonl`` (one JSON object a line; damage as for the rows:
    :func:`~gbh_drake.experiment.rows.read_jsonl`)."""
    return read_jsonl(Path(folder) / RUNS_FILE, warn=warn, repair=repair,
                      check=lambda v: None if isinstance(v, dict) else
                      f"not a run (a JSON object), got {type(v).__name__}")


def _per_protocol(data: ReportInput) -> list[tuple[str, ReportInput]]:
    """(heading suffix, the report input of one protocol) for each protocol; a single ``("",
    data)`` for an experiment of the ``stable`` protocol alone (its report as it was before
    protocols existed)."""
    if data.protocols == [DEFAULT_PROTOCOL]:
        return [("", data)]
    return [(f", protocol `{p}`",
             dataclasses.replace(data, rows=[r for r in data.rows if protocol_of(r) == p],
                                 protocols=[p]))
            for p in data.protocols]


def _groups(data: ReportInput) -> list[tuple[str, str, str | None]]:
    """(column label, method, protocol) of the tables by method: each method (protocol None:
    any), or with several protocols each method in each protocol, ``gbh-10 (natural)``."""
    if len(data.protocols) <= 1:
        return [(m, m, None) for m in data.methods]
    return [(f"{m} ({p})", m, p) for p in data.protocols for m in data.methods]


def _of(row: dict, method: str, protocol: str | None) -> bool:
    return row["method"] == method and (protocol is None or protocol_of(row) == protocol)


def _hangable(data: ReportInput) -> list[dict]:
    return [r for r in data.rows if not r.get("is_control")]


def _controls(data: ReportInput) -> list[dict]:
    return [r for r in data.rows if r.get("is_control")]


def _md(text) -> str:
    """A table cell: no pipes or line breaks."""
    return str(text).replace("|", "/").replace("\n", " ")


def _table(header: list[str], rows: list[list]) -> list[str]:
    """A Markdown table (pandas' ``to_markdown``: columns padded to their width)."""
    return _markdown(pd.DataFrame([[_md(c) for c in row] for row in rows],
                                  columns=[_md(h) for h in header]))


def _markdown(frame: pd.DataFrame) -> list[str]:
    """The lines of ``frame`` as a Markdown table, its cells as written (no number parsing)."""
    return frame.astype(str).to_markdown(index=False, disable_numparse=True).splitlines()


def table1(data: ReportInput) -> list[str]:
    """The Table-1-style table of the objects with hangable parts, the paper's beside it."""
    hangable = _hangable(data)
    n_objects = len({r["object"] for r in hangable})
    out = []
    for method in data.methods:
        rows = [r for r in hangable if r["method"] == method]
        tally = Tally.of(rows)
        views = sorted({r["viewpoints"] for r in rows if r.get("viewpoints")})
        paper = data.paper.get(method, "")
        if paper in PAPER_TABLE1:
            _, total, success = PAPER_TABLE1[paper]
            paper = f"{paper}: {success}/{total} = {100.0 * success / total:.1f} %"
        out.append([method, ", ".join(map(str, views)) or "-", tally.total, tally.success,
                    tally.fail, tally.rate(), tally.interval(), tally.cage, tally.pinch,
                    paper or "-"])
    lines = _table(["Method", "Viewpoints", "Total", "Success", "Fail", "Rate", "95 % CI",
                    "Cage", "Pinch", "Paper (real robot, 15 objects x 5 trials)"], out)
    lines.append("")
    lines.append(f"Objects with hangable parts only ({n_objects}); 95 % CI: the rate's Wilson "
                 "score interval; Cage and Pinch: how the "
                 "successes were held (the cage test after the carry). The paper's baseline is "
                 "GraspNet (learned); ours is a learning-free antipodal sampler with the same "
                 "two straight fingers.")
    released = []
    for method in data.methods:
        carried = [r for r in hangable if r["method"] == method and r["success"]]
        let_go = sum(bool(((r.get("record") or {}).get("verdict") or {}).get("released_on_table"))
                     for r in carried)
        # Rows of ``pick.set_down: false`` end after the cage test: nothing set down to count.
        kept = sum("lower" not in ((r.get("record") or {}).get("phases") or {"lower": 0})
                   for r in carried)
        released.append(f"{method} {let_go}/{len(carried) - kept}" +
                        (f" ({kept} not set down: pick.set_down false)" if kept else ""))
    lines.append("")
    lines.append("Released on the table after the carry (not part of success, as in the paper): "
                 + ", ".join(released) + ".")
    return lines + ["", "### Paired comparison on the same poses", ""] + paired(data)


def paired(data: ReportInput) -> list[str]:
    """Every pair of methods on the (object, trial) poses both ran (objects with hangable
    parts): McNemar's exact test and the difference in rate with its paired-bootstrap 95 %
    interval (:func:`gbh_drake.experiment.stats.mcnemar`), p-values also Holm-adjusted over the
    pairs."""
    outcome = {(r["object"], r["method"], int(r["trial"]), protocol_of(r)): bool(r["success"])
               for r in _hangable(data)}
    poses = sorted({(o, t, p) for o, _, t, p in outcome})
    tests = []
    for i, a in enumerate(data.methods):
        for b in data.methods[i + 1:]:
            both = [(o, t, p) for o, t, p in poses
                    if (o, a, t, p) in outcome and (o, b, t, p) in outcome]
            if both:
                tests.append((a, b, mcnemar([outcome[(o, a, t, p)] for o, t, p in both],
                                            [outcome[(o, b, t, p)] for o, t, p in both])))
    if not tests:
        return ["No two methods ran on the same poses."]
    adjusted = holm([t.p_value for _, _, t in tests])
    rows = [[f"{a} vs {b}", t.pairs, t.both, t.n10, t.n01, t.neither,
             f"{100.0 * t.diff:+.1f}", f"[{100.0 * t.diff_lo:+.1f}, {100.0 * t.diff_hi:+.1f}]",
             _p(t.p_value), _p(q)] for (a, b, t), q in zip(tests, adjusted, strict=True)]
    return _table(["A vs B", "Pairs", "Both", "A only (n10)", "B only (n01)", "Neither",
                   "Rate A - B (pp)", "95 % CI (pp)", "p (McNemar exact)", "p (Holm)"], rows) + [
        "", "Pairs: the (object, trial) poses both methods ran; n10 and n01, the discordant "
        "pairs, decide McNemar's exact test (two-sided binomial of n10 in n10 + n01 at 1/2). "
        "The difference in rate (percentage points) has a paired-bootstrap 95 % interval (the "
        "pairs resampled, 10000 draws, fixed seed); p (Holm): adjusted over the "
        f"{len(tests)} pairs."]


def _p(p: float) -> str:
    return f"{p:.3f}" if p >= 0.001 else f"{p:.1e}"


def summary_markdown(data: ReportInput, *, runs: list[dict] | None = None) -> str:
    """The whole ``summary.md`` (see the module docstring)."""
    hangable, controls = _hangable(data), _controls(data)
    n_expected = len(data.objects) * len(data.methods) * data.trials * len(data.protocols)
    commits = Counter(r.get("commit", "") for r in data.rows)
    lines = [f"# Experiment {data.name}", ""]
    done = f"{len(data.rows)} of {n_expected} trials done" if data.expected else \
        f"{len(data.rows)} trials"
    protocols = "" if data.protocols == [DEFAULT_PROTOCOL] else \
        f" x {_count(len(data.protocols), 'protocol')} ({', '.join(data.protocols)})"
    lines.append(f"{_count(len(data.objects), 'object')} x {_count(data.trials, 'trial')} x "
                 f"{_count(len(data.methods), 'method')}{protocols}: {done}. Rebuilt from "
                 f"`{ROWS_FILE}` by `gbh report`.")
    if data.rows and len(data.rows) < n_expected:
        lines.append("")
        lines.append("**Incomplete**: run the same `gbh experiment` command again to finish "
                     "(finished trials are not redone).")
    lines.append("")
    lines.append("Commit: " + ", ".join(f"`{c or 'unknown'}` ({n} trials)"
                                        for c, n in sorted(commits.items())))
    lines += ["", presets_line(data.rows)] if presets_line(data.rows) else []
    if data.left_out:
        lines.append("")
        lines.append(f"{data.left_out} rows of the file are not trials of this experiment "
                     "(objects, methods or trials it no longer lists) and are left out.")
    for suffix, one in _per_protocol(data):
        lines += ["", f"## Table 1{suffix}", ""]
        lines += [PROTOCOL_TEXT[one.protocols[0]], ""] if suffix else []
        lines += table1(one)

    for suffix, one in _per_protocol(data):
        lines += ["", f"## By resting pose (objects with hangable parts){suffix}", ""] + \
            by_resting_pose(one)

    lines += ["", "## Controls (nothing hangable)", ""]
    rows = []
    for label, method, protocol in _groups(data):
        mine = [r for r in controls if _of(r, method, protocol)]
        outcomes = Counter(r["outcome"] for r in mine)
        rows.append([label, len(mine), sum(bool(r["success"]) for r in mine),
                     _counts(outcomes) or "-"])
    lines += _table(["Method", "Total", "Picked", "Outcomes"], rows)
    lines.append("")
    lines.append("GbH should find nothing to hang on a control; a pick is a fallback grasp or a "
                 "false hanging structure.")

    for suffix, one in _per_protocol(data):
        lines += ["", f"## Per object{suffix}", ""]
        rows = []
        for obj in one.objects:
            mine = [r for r in one.rows if r["object"] == obj]
            cells = []
            for method in one.methods:
                tally = Tally.of(r for r in mine if r["method"] == method)
                cells.append(f"{tally.success}/{tally.total} {tally.interval(0)}" if tally.total
                             else "-")
            control = any(r.get("is_control") for r in mine)
            rows.append([obj + (" (control)" if control else ""), *cells])
        lines += _table(["Object", *one.methods], rows)
        lines.append("")
        lines.append("Successes / trials and the rate's Wilson 95 % interval (with 5 trials an "
                     "interval spans some 50 points: tell objects apart with care).")

    for suffix, one in _per_protocol(data):
        lines += per_object_detail(one, suffix)

    groups = _groups(data)
    lines += ["", "## Failures by outcome (objects with hangable parts)", ""]
    failed = [r for r in hangable if not r["success"]]
    outcomes = Counter(r["outcome"] for r in failed)
    rows = [[o, *(sum(r["outcome"] == o and _of(r, m, p) for r in failed)
                  for _, m, p in groups)]
            for o, _ in sorted(outcomes.items(), key=lambda kv: (-kv[1], kv[0]))]
    lines += _table(["Outcome", *(g[0] for g in groups)], rows) if rows else ["No failures."]

    lines += ["", "## Failures by cause (objects with hangable parts)", ""] + by_cause(data)
    lines += ["", "## What a loop can reach (objects with hangable parts)", ""] + by_reach(data)
    if any(r.get("grasp_method") in BEYOND_METHODS for r in data.rows):
        lines += ["", "## Beyond the paper: where no rigid loop reaches", ""] + beyond(data)

    lines += ["", "## Grasps refused by reason (objects with hangable parts)", ""]
    refusals: Counter = Counter()
    per_group: dict[str, Counter] = {g[0]: Counter() for g in groups}
    for r in hangable:
        for reason, n in (r.get("refusals") or {}).items():
            refusals[reason] += n
            for label, m, p in groups:
                if _of(r, m, p):
                    per_group[label][reason] += n
    rows = [[reason, *(per_group[g[0]][reason] for g in groups)]
            for reason, _ in sorted(refusals.items(), key=lambda kv: (-kv[1], kv[0]))]
    lines += _table(["Refused by", *(g[0] for g in groups)], rows) if rows else \
        ["No grasp was refused."]
    lines.append("")
    lines.append("A refused grasp is one the planner could not execute (no IK solution or no "
                 "collision-free path for a stage); the next ranked grasp is then tried.")

    lines += ["", "## Executed grasps by rank", ""] + by_rank(data)
    lines += ["", "## The lift (objects with hangable parts)", ""] + by_lift(data)

    lines += ["", "## Failed trials (objects with hangable parts)", ""]
    several = data.protocols != [DEFAULT_PROTOCOL]
    rows = [[r["object"], r["method"], r["trial"], *([protocol_of(r)] if several else []),
             r["seed"], r["outcome"], r["reason"],
             f"[replay]({r['replay']})" if r.get("replay") else "-"] for r in failed]
    lines += _table(["Object", "Method", "Trial", *(["Protocol"] if several else []), "Seed",
                     "Outcome", "Reason", "Replay"], rows) if rows else ["None."]
    if rows:
        lines.append("")
        lines.append("Rerun one trial: `gbh run scenarios/<method>.yaml --set '{seed: <Seed>, "
                     "object: {name: <Object>}}'` in this folder.")
        if several:
            lines.append("For a trial of another protocol than the file's, add its rest: "
                         "`object: {name: <Object>, random_pose: {rest: <Protocol>}}`.")

    lines += ["", "## Time", ""]
    rows = []
    for method in data.methods:
        mine = [r.get("stage_times") or {} for r in data.rows if r["method"] == method]
        if not mine:
            continue
        mean = {k: sum(t.get(k, 0.0) for t in mine) / len(mine)
                for k in STAGES}
        rows.append([method, len(mine), *(f"{mean[k]:.1f}" for k in STAGES)])
    lines += _table(["Method", "Trials", *(f"{k.capitalize()} (s)" for k in STAGES)], rows) \
        if rows else ["No trials yet."]
    lines.append("")
    lines.append("Wall seconds per trial in one worker (means); scan, grasps (GbH or the "
                 "sampler) and plan happen inside the simulation.")
    for run in runs or []:
        rate = 60.0 * run.get("trials", 0) / run["wall"] if run.get("wall") else 0.0
        lines.append(f"- {run.get('started', '?')}: {run.get('trials', 0)} trials on "
                     f"{run.get('engine', '?')} in {run.get('wall', 0.0) / 60:.1f} min "
                     f"({rate:.2f} trials/min){' (interrupted)' if run.get('interrupted') else ''}")
    return "\n".join(lines) + "\n"


#: A grasp executed with a score below this fraction of its list's best is of low value.
LOW_VALUE = 0.1


def presets_line(rows: list[dict]) -> str:
    """Which GbH rules each method's trials ran with (``gbh.preset``: ``paper``, the paper's
    values alone, or this implementation's defaults); "" without GbH trials (rows without the
    record field predate it and are left out)."""
    presets: Counter = Counter()
    for r in rows:
        record = r.get("record") or {}
        if r.get("grasp_method", "gbh") != "antipodal" and "gbh_preset" in record:
            presets[(r["method"], record["gbh_preset"] or "ours")] += 1
    if not presets:
        return ""
    return "GbH rules (`gbh.preset`; ours: this implementation's defaults, paper: the paper's " \
        "values): " + "; ".join(f"{m}: {p} ({n} trials)" for (m, p), n in sorted(presets.items()))


def by_rank(data: ReportInput) -> list[str]:
    """Per method: the executed grasps by rank in their list (the first, 2-3, 4-10, a fallback)
    and those of low value (score below LOW_VALUE x the list's best), each as successes/total:
    how often the planner had to go down the list, and whether that paid."""
    buckets = (("#1", lambda r: r["grasp_rank"] == 0), ("#2-3", lambda r: 1 <= r["grasp_rank"] <= 2),
               ("#4+", lambda r: r["grasp_rank"] >= 3))
    rows = []
    for method in data.methods:
        done = [r for r in data.rows if r["method"] == method and r.get("grasp_rank", -1) >= 0]
        primary = [r for r in done if not r.get("fallback")]
        cells = []
        for _, test in buckets:
            mine = [r for r in primary if test(r)]
            cells.append(f"{sum(bool(r['success']) for r in mine)}/{len(mine)}")
        fallback = [r for r in done if r.get("fallback")]
        cells.append(f"{sum(bool(r['success']) for r in fallback)}/{len(fallback)}")
        low = [r for r in done if _low_value(r)]
        cells.append(f"{sum(bool(r['success']) for r in low)}/{len(low)}")
        rows.append([method, *cells])
    return _table(["Method", *(b[0] for b in buckets), "Fallback",
                   f"Score < {LOW_VALUE:g} x best"], rows) + [
        "", "Successes / executed grasps, by the executed grasp's rank in its ranked list."]


def _low_value(row: dict) -> bool:
    record = row.get("record") or {}
    score, best = row.get("grasp_score"), record.get("best_score")
    return score is not None and best is not None and best > 0 and score < LOW_VALUE * best


#: The start of the plan note that says the unseen space raised the lift (planning/pick.py).
UNSEEN_LIFT_NOTE = "the lift allows for unseen space"


def by_lift(data: ReportInput) -> list[str]:
    """Per method (and protocol): the executed hooks, those whose lift the unseen space next to
    the scan raised (the plan's note, :data:`UNSEEN_LIFT_NOTE`) and how many of them were
    carried, and the trials judged dragged (held but touching the table at the place)."""
    rows = []
    for label, method, protocol in _groups(data):
        mine = [r for r in _hangable(data) if _of(r, method, protocol)]
        hooks = [r for r in mine if r.get("grasp_kind") in ("parallel", "vertical", "scoop")]
        raised = [r for r in mine if any(str(n).startswith(UNSEEN_LIFT_NOTE)
                                         for n in (r.get("record") or {}).get("plan_notes") or [])]
        dragged = sum("dragged" in str(r.get("reason", "")) for r in mine)
        rows.append([label, len(hooks), len(raised), sum(bool(r["success"]) for r in raised),
                     dragged])
    return _table(["Method", "Hooks executed", "Lift raised for unseen space", "Of them carried",
                   "Dragged (held, touching the table at the place)"], rows) + [
        "", "The lift clears the scan's farthest point from the hook by `pick.lift_clearance`, "
            "and the space no camera saw free next to the scan by as much (README, the pick)."]


def by_resting_pose(data: ReportInput) -> list[str]:
    """Success per method for each resting-pose class of the start poses (objects with hangable
    parts): how much of the rate the poses the random stable-pose draw gives decide."""
    hangable = _hangable(data)
    rows = []
    for method in data.methods:
        cells = []
        for name, _, _ in RESTING_POSES:
            mine = [r for r in hangable if r["method"] == method and r.get("pose")
                    and resting_pose(r["pose"]) == name]
            tally = Tally.of(mine)
            cells.append(f"{tally.success}/{tally.total} ({tally.rate()}, {tally.interval()})"
                         if tally.total else "-")
        rows.append([method, *cells])
    return _table(["Method", *(name for name, _, _ in RESTING_POSES)], rows) + [
        "", "Successes / trials (rate, Wilson 95 % interval). "
        "The start pose's tilt from the mesh as modelled (z up): upright below 30 deg, "
        "upside down above 150 deg, on its side between. " + (
            "The poses are each object's natural rest (every object of the set is modelled in "
            "it: all upright here, the flat objects lying flat)." if data.protocols == ["natural"]
            else
            "The poses are the random stable "
            "resting poses the experiment fixes (by their probability); this only shows where the "
            "failures lie (a mug on its side rests on its handle; a flat object has no room for the "
            "bar under it). For a user's mesh, z is the mesh's "
            "own z axis.")]


def per_object_detail(data: ReportInput, suffix: str = "") -> list[str]:
    """Per object and method, over its trials: was a true hangable part found, which grasp kinds
    were executed, cage or pinch, the outcomes (``suffix`` ends the heading)."""
    lines = ["", f"## Per object, in detail{suffix}", "",
             "Over each object's trials (its random resting poses): *part found*, trials in which "
             "a hanging structure lay on a true hangable part (the object's ground truth); "
             "*hooked it*, trials whose executed GbH grasp hooked one; *kinds*, the executed "
             "grasps; *cage / pinch*, how the successes were held.", ""]
    rows = []
    for obj in data.objects:
        for method in data.methods:
            mine = [r for r in data.rows if r["object"] == obj and r["method"] == method]
            if not mine:
                continue
            rec = [r.get("record") or {} for r in mine]
            found = [x.get("true_part_found") for x in rec]
            hooked = [x.get("grasped_true_part") for x in rec]
            kinds = Counter(r.get("grasp_kind") or "none" for r in mine)
            held = Counter(r.get("held_by") for r in mine if r.get("success"))
            outcomes = Counter(r["outcome"] for r in mine)
            rows.append([
                obj, method, len(mine),
                _fraction(found), _fraction(hooked),
                _counts(kinds),
                f"{sum(bool(r['success']) for r in mine)}/{len(mine)}",
                f"{held.get('cage', 0)} / {held.get('pinch', 0)}",
                _counts(outcomes)])
    return lines + _table(["Object", "Method", "Trials", "Part found", "Hooked it", "Kinds",
                           "Success", "Cage / pinch", "Outcomes"], rows)


def _counts(counter: Counter) -> str:
    """``a x2, b x1``: a counter's keys in order, each with its count."""
    return ", ".join(f"{k} x{n}" for k, n in sorted(counter.items()))


def _fraction(flags: list) -> str:
    """``k/n`` of the flags that are known (not None), or ``-``."""
    known = [f for f in flags if f is not None]
    return f"{sum(bool(f) for f in known)}/{len(known)}" if known else "-"


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


def cause_counts(data: ReportInput) -> pd.DataFrame:
    """Failed trials of the objects with hangable parts by cause (rows: every class of
    :data:`~gbh_drake.experiment.taxonomy.CAUSES`, zeros included) and method (columns; with
    several protocols, method and protocol: ``gbh-10 (natural)``)."""
    failed = [r for r in _hangable(data) if not r["success"]]
    groups = _groups(data)
    label = {(m, p): name for name, m, p in groups}
    several = len(data.protocols) > 1
    frame = pd.DataFrame({"cause": [cause_of(r) for r in failed],
                          "method": [label.get((r["method"], protocol_of(r) if several else None),
                                               r["method"]) for r in failed]})
    return (pd.crosstab(frame["cause"], frame["method"])
            .reindex(index=list(CAUSES), columns=[g[0] for g in groups], fill_value=0))


def by_cause(data: ReportInput) -> list[str]:
    """The table of :func:`cause_counts`, with what each class means."""
    counts = cause_counts(data)
    table = counts.reset_index().rename(columns={"cause": "Cause"})
    table["Total"] = counts.sum(axis=1).to_numpy()
    total = counts.to_numpy().sum()
    return _markdown(table) + [
        "", f"Each of the {total} failed trials in exactly one class, derived from its row "
        "(gbh_drake/experiment/taxonomy.py): *out of reach*, no candidate passed and the reach "
        "search (below) found no hook pose of this gripper that clears the table and avoids "
        "collision on the true mesh where the object lay; *candidate set missed*, no candidate "
        "passed but the search found a pose on both the true mesh and the trial's scan; *no "
        "structure*, GbH found nothing to hang by; *table clearance*, *collision N_c*, *closing "
        "sweep*, the rule that removed the last candidates (the record's `rejected_by`) when the "
        "search did not decide; *no grasp found*, no candidate passed, in rows without "
        "`rejected_by` (older rows, the antipodal sampler); *IK* / *planner*, every offered "
        "grasp refused, mostly by IK / by the path (RRT-Connect, a collision on a segment, no "
        "clear approach); *lift too low*, held but not lifted clear; *slipped during carry*, "
        "dropped after the lift began; *scan cut/partial*, an empty scan, or a failure decided on "
        "a scan warned to reach the edge of the framed region or the image. "
        f"Plot: {CAUSES_PLOT_FILE}."]


#: Record fields copied into trials.csv.
RECORD_FIELDS = ("n_structures", "n_candidates", "n_ranked", "true_parts", "true_part_found",
                 "grasped_true_part", "best_score", "lift", "sim_time")


#: A no-grasp trial's reach, from its row's ``reach`` field (gbh_drake/experiment/reach.py).
REACH_CLASSES = ("out of reach", "candidate set missed", "lost in the scan", "undecided",
                 "not analysed")


#: The grasp methods that go beyond the paper's grasps (the scoop, the regrasp, both).
BEYOND_METHODS = ("gbh_scoop", "gbh_regrasp", "gbh_plus")
#: The objects that lie flat (every resting pose: the bar cannot pass under their material) and
#: the cups that rest on their handle when lying on their side: the trials issue 19 names, fixed
#: before any number of its methods was seen.
FLAT_OBJECTS = ("clothes_hanger", "key_ring", "scissors", "tape_roll")
CUPS = ("mug_classic", "mug_large", "mug_square_handle", "pybullet_mug", "teacup")


def out_of_the_loops_reach(row: dict) -> bool:
    """Whether ``row`` is one of the trials no rigid loop of the paper's gripper reaches as the
    object lies: a flat object (:data:`FLAT_OBJECTS`), or a cup (:data:`CUPS`) lying on its
    side, resting on its handle."""
    return row["object"] in FLAT_OBJECTS or (
        row["object"] in CUPS and bool(row.get("pose")) and
        resting_pose(row["pose"]) == "on its side")


def held_how(row: dict) -> str:
    """How a successful trial's object was taken: ``hook`` (a GbH grasp as it lay), ``scoop``,
    ``regrasp, hook`` / ``regrasp, scoop`` / ``regrasp, fallback pinch`` (after setting it down
    anew), ``fallback pinch``."""
    record = row.get("record") or {}
    source = record.get("grasp_source") or ("fallback_grasps" if row.get("fallback") else
                                            "grasps")
    how = {"grasps": "hook" if row.get("grasp_kind") != "antipodal" else "pinch",
           "scoop_grasps": "scoop", "fallback_grasps": "fallback pinch"}.get(source, source)
    return f"regrasp, {how}" if record.get("regrasps") else how


#: The ways a success came, in the order :func:`beyond` tables them.
HELD_HOW = ("hook", "scoop", "regrasp, hook", "regrasp, scoop", "regrasp, fallback pinch",
            "fallback pinch", "pinch")


def beyond(data: ReportInput) -> list[str]:
    """The trials no rigid loop reaches as the object lies (:func:`out_of_the_loops_reach`), per
    method and protocol: successes, those held by a cage, and how each success was taken
    (:func:`held_how`); then, per object, each beyond-the-paper method beside GbH with the
    fallback; then the controls they hooked by a false structure."""
    lines, rows = [], []
    for label, method, protocol in _groups(data):
        mine = [r for r in _hangable(data) if _of(r, method, protocol)
                and out_of_the_loops_reach(r)]
        if not mine:
            continue
        tally = Tally.of(mine)
        ways = Counter(held_how(r) for r in mine if r["success"])
        caged = sum(bool(r["success"]) and r.get("held_by") == "cage" for r in mine)
        rows.append([label, len(mine), f"{tally.success} ({tally.rate()})", caged,
                     *(ways[w] for w in HELD_HOW)])
    lines += _table(["Method", "Trials", "Success", "Cage", *(w.capitalize() for w in HELD_HOW)],
                    rows)
    lines += ["", "The trials of the flat objects (" + ", ".join(FLAT_OBJECTS) + ": the 8 mm bar "
              "cannot pass under material lying on the table) and of the cups (" +
              ", ".join(CUPS) + ") lying on their side, resting on their handle: out of reach of "
              "the paper's grasps as the object lies (docs/reach.md). *Success by*: a hook as it "
              "lay; a scoop (the wedge bar slid under the material, core/scoop.py); a hook or "
              "scoop after a regrasp (set down in a pose GbH can hook, scanned again, "
              "core/regrasp.py); the antipodal fallback's pinch. *Cage*: successes the cage test "
              "found held on the closed loop."]
    beyond_methods = sorted({r["method"] for r in data.rows
                             if r.get("grasp_method") in BEYOND_METHODS},
                            key=data.methods.index)
    fallback = [m for m in data.methods if any(r["method"] == m and
                                               r.get("grasp_method") == "gbh_fallback"
                                               for r in data.rows)]
    for suffix, one in _per_protocol(data):
        compared = [*fallback, *beyond_methods]
        rows = []
        for obj in [o for o in one.objects if not any(r.get("is_control") for r in one.rows
                                                      if r["object"] == o)]:
            cells = []
            for method in compared:
                mine = [r for r in one.rows if r["object"] == obj and r["method"] == method]
                tally = Tally.of(mine)
                caged = sum(bool(r["success"]) and r.get("held_by") == "cage" for r in mine)
                cells.append(f"{tally.success}/{tally.total} ({caged} cage)" if mine else "-")
            rows.append([obj, *cells])
        lines += ["", f"### Per object{suffix}", ""] + _table(["Object", *compared], rows)
    rows = []
    for label, method, protocol in _groups(data):
        if method not in beyond_methods:
            continue
        mine = [r for r in _controls(data) if _of(r, method, protocol)]
        hooked = sum(bool(r["success"]) and held_how(r) in ("hook", "scoop") for r in mine)
        pinched = sum(bool(r["success"]) and "pinch" in held_how(r) for r in mine)
        rows.append([label, len(mine), hooked, pinched])
    if rows:
        lines += ["", "### Controls", ""] + _table(
            ["Method", "Trials", "Hooked (a false structure)", "Pinched (the fallback)"], rows)
    return lines + retries(data)


def retries(data: ReportInput) -> list[str]:
    """Per method (and protocol) that retried: the trials whose first lift came away empty
    (``record.attempts``), how many of them were then carried, and held by a cage or a pinch."""
    rows = []
    for label, method, protocol in _groups(data):
        mine = [r for r in data.rows if _of(r, method, protocol)
                and (r.get("record") or {}).get("attempts")]
        if mine:
            carried = [r for r in mine if r["success"]]
            rows.append([label, len(mine), len(carried),
                         sum(r.get("held_by") == "cage" for r in carried),
                         sum(r.get("held_by") == "pinch" for r in carried)])
    if not rows:
        return []
    return ["", "### Retries", ""] + _table(
        ["Method", "Trials retried (a lift came away empty)", "Then carried", "Cage", "Pinch"],
        rows) + ["", "A retry: the hand opens, goes home, the object is scanned again and the "
                     "pick planned anew without the structure that failed (`pick.max_retries`)."]


def reach_class(row: dict) -> str:
    """The reach class (:data:`REACH_CLASSES`) of a ``no_grasp_found`` row: *out of reach*, no
    hook pose of the gripper passes on the true mesh; *candidate set missed*, one passes on the
    true mesh and on the trial's scan; *lost in the scan*, on the true mesh only; *undecided*,
    a search did not finish; *not analysed*, no ``reach`` field (a method without GbH, an older
    row)."""
    reach = row.get("reach") or {}
    true, scan = reach.get("true"), reach.get("scan")
    if true == "out of reach":
        return "out of reach"
    if true == "reachable":
        return "candidate set missed" if scan == "reachable" else \
            "undecided" if scan == "undecided" else "lost in the scan"
    return "undecided" if true == "undecided" else "not analysed"


def by_reach(data: ReportInput) -> list[str]:
    """Per method (and protocol): the trials GbH offered no grasp in, by :func:`reach_class`,
    and the success rate among the trials a loop can reach (all but those *out of reach*)."""
    rows = []
    for label, method, protocol in _groups(data):
        mine = [r for r in _hangable(data) if _of(r, method, protocol)]
        no_grasp = [r for r in mine if r.get("outcome") == "no_grasp_found"]
        classes = Counter(reach_class(r) for r in no_grasp)
        reachable = [r for r in mine if not (r.get("outcome") == "no_grasp_found"
                                             and reach_class(r) == "out of reach")]
        tally = Tally.of(reachable)
        rows.append([label, len(mine), len(no_grasp), *(classes[c] for c in REACH_CLASSES),
                     f"{tally.success}/{tally.total}", tally.rate(), tally.interval()])
    return _table(["Method", "Trials", "No grasp", *(c.capitalize() for c in REACH_CLASSES),
                   "Success / reachable", "Rate", "95 % CI"], rows) + [
        "", "A trial in which GbH offered no grasp (no_grasp_found) is searched again, densely "
        "(gbh_drake/core/reach.py: every turn about the hole, the rod within 60 deg of the "
        "hole's axis or the vertical, the same gripper solid, table rule and closing sweep), on "
        "the trial's scan and on the true mesh where the object lay (docs/reach.md). *Success / "
        "reachable*: the method's successes among its trials less those *out of reach* (a loop "
        "of this gripper cannot hold the object as it lies: the method's limit, not a defect). "
        "Trials that failed later (IK, planner, carry) are not searched: they count as "
        "reachable."]


def trials_frame(data: ReportInput) -> pd.DataFrame:
    """One row per trial (controls included): the row's flat fields (the pose as pose_x ..
    pose_yaw, refusals as ``key xN``), its ``cause`` (empty for a success), ``resting_pose``,
    :data:`RECORD_FIELDS` from the record, whether it was released on the table, and the stage
    times as ``time_<stage>`` (wall s)."""
    out = []
    for r in data.rows:
        record = r.get("record") or {}
        pose = list(r.get("pose") or [])
        flat = {k: v for k, v in r.items()
                if not isinstance(v, dict | list) and k not in ("traceback",)}
        flat["protocol"] = protocol_of(r)
        flat["refusals"] = _counts(Counter(r.get("refusals") or {}))
        flat["cause"] = cause_of(r)
        flat["resting_pose"] = resting_pose(pose) if len(pose) == 6 else ""
        flat.update({f"pose_{k}": v for k, v in zip(("x", "y", "z", "roll", "pitch", "yaw"),
                                                     pose, strict=False)})
        flat.update({k: record.get(k) for k in RECORD_FIELDS})
        flat["released_on_table"] = (record.get("verdict") or {}).get("released_on_table")
        flat.update({f"time_{k}": (r.get("stage_times") or {}).get(k) for k in STAGES})
        out.append(flat)
    first = ["object", "is_control", "method", "trial", "protocol", "seed", "outcome", "success",
             "held_by",
             "cause", "grasp_kind", "grasp_rank", "grasp_score", "resting_pose"]
    frame = pd.DataFrame(out) if out else pd.DataFrame(columns=first)
    return frame[[c for c in first if c in frame] + [c for c in frame if c not in first]]


def table1_frame(data: ReportInput) -> pd.DataFrame:
    """Table 1 as numbers (objects with hangable parts): per protocol and method its trials,
    successes, rate and Wilson 95 % interval (fractions; empty without trials), cage, pinch."""
    out = []
    for protocol, method in [(p, m) for p in data.protocols for m in data.methods]:
        rows = [r for r in _hangable(data) if _of(r, method, protocol)]
        tally = Tally.of(rows)
        lo, hi = wilson(tally.success, tally.total) if tally.total else (None, None)
        out.append({"protocol": protocol, "method": method,
                    "viewpoints": ",".join(str(v) for v in sorted({r["viewpoints"] for r in rows
                                                                    if r.get("viewpoints")})),
                    "trials": tally.total, "successes": tally.success,
                    "rate": tally.success / tally.total if tally.total else None,
                    "wilson_lo": lo, "wilson_hi": hi, "cage": tally.cage, "pinch": tally.pinch})
    return pd.DataFrame(out, columns=["protocol", "method", "viewpoints", "trials", "successes",
                                      "rate",
                                      "wilson_lo", "wilson_hi", "cage", "pinch"])


def _rate_bars(ax, rows_by_method: list[list[dict]], colours):
    """One bar per method: the success rate with its Wilson 95 % interval; a method with a zero
    rate gets a marker at 0 (so that it is seen to have run), one without trials nothing."""
    for j, rows in enumerate(rows_by_method):
        if not rows:
            continue
        tally = Tally.of(rows)
        rate = tally.success / tally.total
        lo, hi = wilson(tally.success, tally.total)
        ax.bar(j, rate, width=0.8, color=colours[j])
        ax.errorbar(j, rate, yerr=[[rate - lo], [hi - rate]], color="black", capsize=2,
                    linewidth=0.8)
        if tally.success == 0:
            ax.plot(j, 0.0, marker="_", markersize=16, markeredgewidth=4, color=colours[j],
                    clip_on=False, zorder=3)
    ax.set_xticks([])
    ax.set_xlim(-0.6, len(rows_by_method) - 0.4)
    ax.set_ylim(0.0, 1.05)
    ax.set_yticks([0.0, 0.5, 1.0])
    ax.grid(axis="y", alpha=0.3)


def _save(fig, path: Path) -> None:
    """``path`` (PNG) and the same with .svg, each written whole or not at all (the SVG without a
    date and with fixed ids: the same rows give the same file)."""
    import matplotlib

    for target in (path, path.with_suffix(".svg")):
        tmp = target.with_name(f".{target.stem}.{os.getpid()}.tmp{target.suffix}")
        with matplotlib.rc_context({"svg.hashsalt": "gbh"}):
            fig.savefig(tmp, metadata={"Date": None} if target.suffix == ".svg" else None)
        os.replace(tmp, target)


def _figure(width: float, height: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=100)
    FigureCanvasAgg(fig)
    return fig


def plot_success(data: ReportInput, path: Path) -> None:
    """Success per method with Wilson 95 % error bars: a first panel of the methods' totals over
    the objects with hangable parts, then one panel per object (PNG and SVG)."""
    import matplotlib

    colours = [matplotlib.colormaps["tab10"](j % 10) for j in range(len(data.methods))]
    controls = {r["object"] for r in _controls(data)}
    panels = []
    for suffix, one in _per_protocol(data):
        tag = f" ({one.protocols[0]})" if suffix else ""
        panels += [("all hangable objects" + tag, _hangable(one))] + [
            (obj + (" (control)" if obj in controls else "") + tag,
             [r for r in one.rows if r["object"] == obj]) for obj in one.objects]
    ncols = min(6, len(panels))
    nrows = math.ceil(len(panels) / ncols)
    fig = _figure(2.1 * ncols + 0.4, 1.75 * nrows + 0.9)
    for k, (title, rows) in enumerate(panels):
        ax = fig.add_subplot(nrows, ncols, k + 1)
        _rate_bars(ax, [[r for r in rows if r["method"] == m] for m in data.methods],
                   colours)
        n = len({(r["object"], r["trial"]) for r in rows})
        ax.set_title(f"{title} ({n})", fontsize=8,
                     fontweight="bold" if title.startswith("all hangable") else "normal")
        ax.tick_params(labelsize=7)
        if k % ncols:
            ax.set_yticklabels([])
    height = fig.get_figheight()
    fig.suptitle(f"{data.name}: success rate per method with Wilson 95 % intervals (trials in "
                 "parentheses; a dash at 0: no success)", fontsize=9, y=1 - 0.08 / height,
                 va="top")
    from matplotlib.patches import Patch

    fig.legend(handles=[Patch(color=c, label=m) for m, c in zip(data.methods, colours, strict=True)],
               loc="upper center", bbox_to_anchor=(0.5, 1 - 0.3 / height),
               ncols=min(6, len(data.methods)), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.6 / height))
    _save(fig, path)


def plot_causes(data: ReportInput, path: Path) -> None:
    """The failed trials of the objects with hangable parts per method, stacked by cause (the
    classes with at least one trial), PNG and SVG."""
    import matplotlib

    counts = cause_counts(data)
    counts = counts[counts.sum(axis=1) > 0]
    groups = _groups(data)
    fig = _figure(max(5.0, 1.3 * len(groups) + 3.2), 4.2)
    ax = fig.add_subplot(1, 1, 1)
    xs = list(range(len(groups)))
    bottom = [0] * len(groups)
    top = max(1, counts.sum(axis=0).max() if len(counts) else 1)
    palette = matplotlib.colormaps["tab20"]
    for cause, values in counts.iterrows():
        colour = palette(2 * CAUSES.index(cause) % 20)  # tab20's darker shades first
        ax.bar(xs, values.to_list(), bottom=bottom, width=0.6, label=cause, color=colour)
        for x, v, b in zip(xs, values, bottom, strict=True):
            if v >= 0.04 * top:  # a label where it fits
                ax.text(x, b + v / 2, str(v), ha="center", va="center", fontsize=7)
        bottom = [b + v for b, v in zip(bottom, values, strict=True)]
    totals = {g: sum(1 for r in _hangable(data) if _of(r, m, p)) for g, m, p in groups}
    ax.set_xticks(xs)
    ax.set_xticklabels([f"{g}\n({totals[g]} trials)" for g, _, _ in groups], fontsize=8)
    ax.set_ylabel("failed trials")
    ax.set_title(f"{data.name}: failures by cause (objects with hangable parts)", fontsize=10)
    if len(counts):
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False,
                  reverse=True)
    else:
        ax.text(0.5, 0.5, "no failures", transform=ax.transAxes, ha="center")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    _save(fig, path)
