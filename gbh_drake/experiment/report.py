"""The experiment's reports, rebuilt from its rows alone: ``summary.md`` and ``success.png``.

``summary.md`` holds: the Table-1-style table (objects with hangable parts; Method, Viewpoints,
Total, Success, Fail, Rate, held by cage or pinch) with the paper's real-robot figures beside
it, success by resting pose (upright, on its side, upside down), the controls (objects with
nothing to hang) apart, a table per object, the failures by outcome
and the grasps refused by reason, a list of the failed trials with their replays and how to rerun
one, and timings. ``success.png``: the success rate per object and method. Rows are ordered by
object, method and trial as the experiment lists them, never by when they finished, so the same
rows give the same report.
"""

from __future__ import annotations

import json
import math
import os
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import yaml

from gbh_drake.experiment.rows import ROWS_FILE, RowStore, row_key, sort_key
from gbh_drake.outputs import write_atomically

#: Files of an experiment folder besides the rows.
EXPERIMENT_FILE = "experiment.yaml"
SUMMARY_FILE = "summary.md"
PLOT_FILE = "success.png"
RUNS_FILE = "runs.jsonl"

#: The stage times of a row shown in the report (wall seconds).
STAGES = ("build", "scan", "grasps", "plan", "simulate", "total")

#: The paper's Table 1 (real robot, 15 objects x 5 trials): name -> (viewpoints, total, success).
PAPER_TABLE1 = {
    "GraspNet 1 view": (1, 75, 23),
    "GbH 1 view": (1, 75, 54),
    "GbH 10 views": (10, 75, 68),
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


def read_input(folder: Path) -> ReportInput:
    """The rows of ``folder`` and its saved experiment (when there is one)."""
    folder = Path(folder)
    rows = RowStore(folder).load()
    unique = {row_key(r): r for r in rows}  # a trial run twice: its last row
    saved = folder / EXPERIMENT_FILE
    if saved.is_file():  # written by the runner (yaml_dump_typed of the Experiment: no tags)
        e = yaml.safe_load(saved.read_text()) or {}
        objects, trials = list(e.get("objects", [])), int(e.get("trials", 0))
        methods = [m["name"] for m in e.get("methods", [])]
        wanted = {(o, m, t) for o in objects for m in methods for t in range(trials)}
        kept = [r for k, r in unique.items() if k in wanted]
        return ReportInput(e.get("name") or folder.name, objects, methods, trials,
                           {m["name"]: m["paper"] for m in e.get("methods", [])
                            if m.get("paper")},
                           sorted(kept, key=sort_key(objects, methods)),
                           left_out=len(unique) - len(kept))
    objects = sorted({r["object"] for r in unique.values()})
    methods = sorted({r["method"] for r in unique.values()})
    trials = 1 + max((int(r["trial"]) for r in unique.values()), default=-1)
    return ReportInput(folder.name, objects, methods, trials, {},
                       sorted(unique.values(), key=sort_key(objects, methods)), expected=False)


def write_report(folder: Path) -> tuple[Path, Path]:
    """Writes ``summary.md`` and ``success.png`` into ``folder`` from its rows; returns them."""
    folder = Path(folder)
    data = read_input(folder)
    summary = folder / SUMMARY_FILE
    write_atomically(summary, summary_markdown(data, runs=read_runs(folder)))
    plot = folder / PLOT_FILE
    plot_success(data, plot)
    return summary, plot


def read_runs(folder: Path) -> list[dict]:
    path = Path(folder) / RUNS_FILE
    if not path.is_file():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def _hangable(data: ReportInput) -> list[dict]:
    return [r for r in data.rows if not r.get("is_control")]


def _controls(data: ReportInput) -> list[dict]:
    return [r for r in data.rows if r.get("is_control")]


def _md(text) -> str:
    """A table cell: no pipes or line breaks."""
    return str(text).replace("|", "/").replace("\n", " ")


def _table(header: list[str], rows: list[list]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_md(c) for c in row) + " |" for row in rows]
    return lines


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
                    tally.fail, tally.rate(), tally.cage, tally.pinch, paper or "-"])
    lines = _table(["Method", "Viewpoints", "Total", "Success", "Fail", "Rate", "Cage",
                    "Pinch", "Paper (real robot, 15 objects x 5 trials)"], out)
    lines.append("")
    lines.append(f"Objects with hangable parts only ({n_objects}); Cage and Pinch: how the "
                 "successes were held (the cage test after the carry). The paper's baseline is "
                 "GraspNet (learned); ours is a learning-free antipodal sampler with the same "
                 "two straight fingers.")
    released = []
    for method in data.methods:
        carried = [r for r in hangable if r["method"] == method and r["success"]]
        let_go = sum(bool(((r.get("record") or {}).get("verdict") or {}).get("released_on_table"))
                     for r in carried)
        released.append(f"{method} {let_go}/{len(carried)}")
    lines.append("")
    lines.append("Released on the table after the carry (not part of success, as in the paper): "
                 + ", ".join(released) + ".")
    return lines


def summary_markdown(data: ReportInput, *, runs: list[dict] | None = None) -> str:
    """The whole ``summary.md`` (see the module docstring)."""
    hangable, controls = _hangable(data), _controls(data)
    n_expected = len(data.objects) * len(data.methods) * data.trials
    commits = Counter(r.get("commit", "") for r in data.rows)
    lines = [f"# Experiment {data.name}", ""]
    done = f"{len(data.rows)} of {n_expected} trials done" if data.expected else \
        f"{len(data.rows)} trials"
    lines.append(f"{_count(len(data.objects), 'object')} x {_count(data.trials, 'trial')} x "
                 f"{_count(len(data.methods), 'method')}: {done}. Rebuilt from `{ROWS_FILE}` by "
                 "`gbh report`.")
    if data.rows and len(data.rows) < n_expected:
        lines.append("")
        lines.append("**Incomplete**: run the same `gbh experiment` command again to finish "
                     "(finished trials are not redone).")
    lines.append("")
    lines.append("Commit: " + ", ".join(f"`{c or 'unknown'}` ({n} trials)"
                                        for c, n in sorted(commits.items())))
    if data.left_out:
        lines.append("")
        lines.append(f"{data.left_out} rows of the file are not trials of this experiment "
                     "(objects, methods or trials it no longer lists) and are left out.")
    lines += ["", "## Table 1", ""] + table1(data)

    lines += ["", "## By resting pose (objects with hangable parts)", ""] + by_resting_pose(data)

    lines += ["", "## Controls (nothing hangable)", ""]
    rows = []
    for method in data.methods:
        mine = [r for r in controls if r["method"] == method]
        outcomes = Counter(r["outcome"] for r in mine)
        rows.append([method, len(mine), sum(bool(r["success"]) for r in mine),
                     _counts(outcomes) or "-"])
    lines += _table(["Method", "Total", "Picked", "Outcomes"], rows)
    lines.append("")
    lines.append("GbH should find nothing to hang on a control; a pick is a fallback grasp or a "
                 "false hanging structure.")

    lines += ["", "## Per object", ""]
    rows = []
    for obj in data.objects:
        mine = [r for r in data.rows if r["object"] == obj]
        cells = []
        for method in data.methods:
            tally = Tally.of(r for r in mine if r["method"] == method)
            cells.append(f"{tally.success}/{tally.total}" if tally.total else "-")
        control = any(r.get("is_control") for r in mine)
        rows.append([obj + (" (control)" if control else ""), *cells])
    lines += _table(["Object", *data.methods], rows)

    lines += per_object_detail(data)

    lines += ["", "## Failures by outcome (objects with hangable parts)", ""]
    failed = [r for r in hangable if not r["success"]]
    outcomes = Counter(r["outcome"] for r in failed)
    rows = [[o, *(sum(r["outcome"] == o and r["method"] == m for r in failed)
                  for m in data.methods)]
            for o, _ in sorted(outcomes.items(), key=lambda kv: (-kv[1], kv[0]))]
    lines += _table(["Outcome", *data.methods], rows) if rows else ["No failures."]

    lines += ["", "## Grasps refused by reason (objects with hangable parts)", ""]
    refusals: Counter = Counter()
    per_method: dict[str, Counter] = {m: Counter() for m in data.methods}
    for r in hangable:
        for reason, n in (r.get("refusals") or {}).items():
            refusals[reason] += n
            per_method[r["method"]][reason] += n
    rows = [[reason, *(per_method[m][reason] for m in data.methods)]
            for reason, _ in sorted(refusals.items(), key=lambda kv: (-kv[1], kv[0]))]
    lines += _table(["Refused by", *data.methods], rows) if rows else \
        ["No grasp was refused."]
    lines.append("")
    lines.append("A refused grasp is one the planner could not execute (no IK solution or no "
                 "collision-free path for a stage); the next ranked grasp is then tried.")

    lines += ["", "## Executed grasps by rank", ""] + by_rank(data)

    lines += ["", "## Failed trials (objects with hangable parts)", ""]
    rows = [[r["object"], r["method"], r["trial"], r["seed"], r["outcome"], r["reason"],
             f"[replay]({r['replay']})" if r.get("replay") else "-"] for r in failed]
    lines += _table(["Object", "Method", "Trial", "Seed", "Outcome", "Reason", "Replay"],
                    rows) if rows else ["None."]
    if rows:
        lines.append("")
        lines.append("Rerun one trial: `gbh run scenarios/<method>.yaml --set '{seed: <Seed>, "
                     "object: {name: <Object>}}'` in this folder.")

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


#: Resting-pose classes by the tilt of the object's z axis from the world's (deg): the start pose
#: as drawn from the object's stable resting poses, relative to its mesh as modelled (z up).
RESTING_POSES = (("upright", 0.0, 30.0), ("on its side", 30.0, 150.0), ("upside down", 150.0, 180.1))


#: A grasp executed with a score below this fraction of its list's best is of low value.
LOW_VALUE = 0.1


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


def resting_pose(pose: list[float]) -> str:
    """The class of a row's start ``pose`` [x, y, z, roll, pitch, yaw] (m, rad; Drake's
    RollPitchYaw, R = Rz(yaw) Ry(pitch) Rx(roll)): the tilt of the object's z axis from the
    world's is acos(cos(pitch) cos(roll))."""
    roll, pitch = float(pose[3]), float(pose[4])
    tilt = math.degrees(math.acos(max(-1.0, min(1.0, math.cos(pitch) * math.cos(roll)))))
    return next(name for name, lo, hi in RESTING_POSES if lo <= tilt < hi)


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
            cells.append(f"{tally.success}/{tally.total} ({tally.rate()})" if tally.total else "-")
        rows.append([method, *cells])
    return _table(["Method", *(name for name, _, _ in RESTING_POSES)], rows) + [
        "", "The start pose's tilt from the mesh as modelled (z up): upright below 30 deg, "
        "upside down above 150 deg, on its side between. The poses are the random stable "
        "resting poses the experiment fixes (by their probability); this only shows where the "
        "failures lie (a mug on its side rests on its handle; a flat object has no room for the "
        "bar under it). For a user's mesh, z is the mesh's "
        "own z axis."]


def per_object_detail(data: ReportInput) -> list[str]:
    """Per object and method, over its trials: was a true hangable part found, which grasp kinds
    were executed, cage or pinch, the outcomes."""
    lines = ["", "## Per object, in detail", "",
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


def plot_success(data: ReportInput, path: Path) -> None:
    """Grouped bars: the success rate of each method on each object (PNG, matplotlib's Agg)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    n_obj, n_met = len(data.objects), max(1, len(data.methods))
    fig = Figure(figsize=(max(6.0, 0.55 * n_obj * max(1.0, n_met / 3) + 2.0), 4.2), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    width = 0.8 / n_met
    controls = {r["object"] for r in _controls(data)}
    for j, method in enumerate(data.methods):
        rates, xs = [], []
        for i, obj in enumerate(data.objects):
            mine = [r for r in data.rows if r["object"] == obj and r["method"] == method]
            if mine:
                xs.append(i - 0.4 + width * (j + 0.5))
                rates.append(sum(bool(r["success"]) for r in mine) / len(mine))
        ax.bar(xs, rates, width=width, label=method)
    ax.set_xticks(range(n_obj))
    ax.set_xticklabels([o + (" *" if o in controls else "") for o in data.objects],
                       rotation=45, ha="right", fontsize=8)
    ax.set_xlim(-0.6, n_obj - 0.4)
    ax.set_ylim(0.0, 1.22)  # the legend sits above 1
    ax.set_yticks([0.0, 0.25, 0.5, 0.75, 1.0])
    ax.set_ylabel("success rate")
    ax.set_title(f"{data.name}: success per object and method ({_count(data.trials, 'trial')} "
                 "each; * control)", fontsize=10)
    ax.legend(fontsize=8, ncols=min(4, n_met), loc="upper center", frameon=False)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.png")
    fig.savefig(tmp)
    os.replace(tmp, path)
