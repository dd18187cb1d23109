"""The sections of ``summary.md``, each a short function of the report's frame
(:attr:`ReportInput.frame <gbh_drake.experiment.report.inputs.ReportInput.frame>`) returning
its lines; :func:`summary_markdown` puts them together."""

from __future__ import annotations

import pandas as pd

from gbh_drake.core.resting import RESTING_POSES
from gbh_drake.core.words import counted
from gbh_drake.experiment.report.beyond import beyond, borderline
from gbh_drake.experiment.report.columns import REACH_CLASSES, STAGES
from gbh_drake.experiment.report.facts import (
    PAPER_TABLE1,
    UNKNOWN,
    beyond_paper,
    object_tags,
    protocol_text,
)
from gbh_drake.experiment.report.inputs import ReportInput
from gbh_drake.experiment.report.tables import (
    cause_counts,
    controls,
    counts,
    fraction,
    hangable,
    held,
    interval,
    markdown,
    per_group,
    per_protocol,
    rate,
    table,
    tally,
    viewpoints,
)
from gbh_drake.experiment.rows import DEFAULT_PROTOCOL, ROWS_FILE
from gbh_drake.experiment.stats import holm, mcnemar, wilson

#: The causes plot's file (named in the causes section).
CAUSES_PLOT_FILE = "causes.png"
#: A grasp executed with a score below this fraction of its list's best is of low value.
LOW_VALUE = 0.1


def table1(data: ReportInput) -> list[str]:
    """The Table-1-style table of the objects with hangable parts, the paper's beside it, the
    releases on the table, and the paired comparison."""
    mine, out, released = hangable(data.frame), [], []
    for method in data.methods:
        rows = mine[mine.method == method]
        total, success = tally(rows)
        paper = data.paper.get(method, "")
        if paper in PAPER_TABLE1:
            _, n, k = PAPER_TABLE1[paper]
            paper = f"{paper}: {k}/{n} = {100.0 * k / n:.1f} %"
        out.append([method, viewpoints(rows, ", ") or "-", total, success, total - success,
                    rate(success, total), interval(success, total), held(rows, "cage"),
                    held(rows, "pinch"), paper or "-"])
        carried = rows[rows.success]
        kept = int((~carried.set_down).sum())  # pick.set_down false: nothing set down to count
        released.append(f"{method} {int(carried.released_on_table.fillna(False).sum())}/"
                        f"{len(carried) - kept}" +
                        (f" ({kept} not set down: pick.set_down false)" if kept else ""))
    return table(["Method", "Viewpoints", "Total", "Success", "Fail", "Rate", "95 % CI", "Cage",
                  "Pinch", "Paper (real robot, 15 objects x 5 trials)"], out) + [
        "", f"Objects with hangable parts only ({mine.object.nunique()}); 95 % CI: the rate's "
        "Wilson score interval; Cage and Pinch: how the successes were held (the cage test "
        "after the carry). The paper's baseline is GraspNet (learned); ours is a learning-free "
        "antipodal sampler with the same two straight fingers.",
        "", "Released on the table after the carry (not part of success, as in the paper): "
        + ", ".join(released) + ".", "", "### Paired comparison on the same poses", "",
        *paired(data)]


def table1_by_protocol(data: ReportInput) -> list[str]:
    """:func:`table1` of each protocol under its heading, as ``summary.md`` has them (what
    ``gbh experiment`` and ``gbh report`` print); one table without a heading for an experiment
    of the ``stable`` protocol alone."""
    lines: list[str] = []
    for suffix, one in per_protocol(data):
        lines += ([f"## Table 1{suffix}", ""] if suffix else []) + table1(one) + [""]
    return lines[:-1]


def paired(data: ReportInput) -> list[str]:
    """Every pair of methods on the (object, trial) poses both ran (objects with hangable
    parts): McNemar's exact test and the difference in rate with its paired-bootstrap 95 %
    interval (:func:`gbh_drake.experiment.stats.mcnemar`), p-values also Holm-adjusted over the
    pairs."""
    outcome = hangable(data.frame).assign(ok=lambda f: f.success.astype(int)).pivot_table(
        index=["object", "trial", "protocol"], columns="method", values="ok", aggfunc="last")
    tests = []
    for i, a in enumerate(data.methods):
        for b in data.methods[i + 1:]:
            both = outcome[[a, b]].dropna() if {a, b} <= set(outcome.columns) else []
            if len(both):
                tests.append((a, b, mcnemar(both[a].astype(bool).tolist(),
                                            both[b].astype(bool).tolist())))
    if not tests:
        return ["No two methods ran on the same poses."]
    adjusted = holm([t.p_value for _, _, t in tests])
    rows = [[f"{a} vs {b}", t.pairs, t.both, t.n10, t.n01, t.neither,
             f"{100.0 * t.diff:+.1f}", f"[{100.0 * t.diff_lo:+.1f}, {100.0 * t.diff_hi:+.1f}]",
             _p(t.p_value), _p(q)] for (a, b, t), q in zip(tests, adjusted, strict=True)]
    return table(["A vs B", "Pairs", "Both", "A only (n10)", "B only (n01)", "Neither",
                  "Rate A - B (pp)", "95 % CI (pp)", "p (McNemar exact)", "p (Holm)"], rows) + [
        "", "Pairs: the (object, trial) poses both methods ran; n10 and n01, the discordant "
        "pairs, decide McNemar's exact test (two-sided binomial of n10 in n10 + n01 at 1/2). "
        "The difference in rate (percentage points) has a paired-bootstrap 95 % interval (the "
        "pairs resampled, 10000 draws, fixed seed); p (Holm): adjusted over the "
        f"{len(tests)} pairs."]


def _p(p: float) -> str:
    return f"{p:.3f}" if p >= 0.001 else f"{p:.1e}"


def by_resting_pose(data: ReportInput) -> list[str]:
    """Success per method for each resting-pose class of the start poses (objects with hangable
    parts): how much of the rate the poses the random stable-pose draw gives decide."""
    mine, rows = hangable(data.frame), []
    for method in data.methods:
        cells = []
        for name, _, _ in RESTING_POSES:
            total, success = tally(mine[(mine.method == method) & (mine.resting_pose == name)])
            cells.append(f"{success}/{total} ({rate(success, total)}, "
                         f"{interval(success, total)})" if total else "-")
        rows.append([method, *cells])
    return table(["Method", *(name for name, _, _ in RESTING_POSES)], rows) + [
        "", "Successes / trials (rate, Wilson 95 % interval). "
        "The start pose's tilt from the mesh as modelled (z up): upright below 30 deg, "
        "upside down above 150 deg, on its side between. " + (
            "The poses are each object's natural rest (every object of the set is modelled in "
            "it: all upright here, the flat objects lying flat)." if data.protocols == ["natural"]
            else "The poses are the random stable resting poses the experiment fixes (by their "
            "probability); this only shows where the failures lie (a mug on its side rests on "
            "its handle; a flat object has no room for the bar under it). For a user's mesh, z "
            "is the mesh's own z axis.")]


def controls_table(data: ReportInput) -> list[str]:
    """Per method (and protocol), the controls' trials, picks and outcomes."""
    rows = [[label, len(mine), int(mine.success.sum()), counts(mine.outcome) or "-"]
            for label, mine in per_group(data, controls(data.frame))]
    return table(["Method", "Total", "Picked", "Outcomes"], rows) + [
        "", "GbH should find nothing to hang on a control; a pick is a fallback grasp or a "
        "false hanging structure."]


def _by_object_and_method(data: ReportInput, *columns: str) -> dict[tuple, pd.DataFrame]:
    """The rows of each (object, method) that has any, with ``columns`` alone."""
    narrow = data.frame[["object", "method", *columns]]
    return {key: rows for key, rows in narrow.groupby(["object", "method"], sort=False)}


def per_object(data: ReportInput) -> list[str]:
    """Per object and method: successes / trials and the Wilson interval."""
    tags, rows = object_tags(data.frame), []
    tallies = data.frame.groupby(["object", "method"]).success.agg(["size", "sum"])
    for obj in data.objects:
        cells = []
        for method in data.methods:
            total, success = tallies.loc[(obj, method)] if (obj, method) in tallies.index \
                else (0, 0)
            cells.append(f"{success}/{total} {interval(success, total, 0)}" if total else "-")
        rows.append([obj + (" (control)" if "control" in tags.get(obj, ()) else ""), *cells])
    return table(["Object", *data.methods], rows) + [
        "", "Successes / trials and the rate's Wilson 95 % interval"
        f"{_widths(list(tallies.itertuples(index=False)))}."]


def _widths(cells: list) -> str:
    """`` (with 5 trials each, these intervals span 43 to 65 points: ...)``: the widths of
    the Wilson intervals (:func:`~gbh_drake.experiment.stats.wilson`) of the cells' (trials,
    successes); "" without cells."""
    if not cells:
        return ""
    sizes = sorted({int(n) for n, _ in cells})
    widths = sorted({round(100.0 * (hi - lo)) for lo, hi in
                     (wilson(int(k), int(n)) for n, k in cells)})
    trials = counted(sizes[0], "trial") if len(sizes) == 1 else \
        f"{sizes[0]} to {sizes[-1]} trials"
    span = f"{widths[0]}" if len(widths) == 1 else f"{widths[0]} to {widths[-1]}"
    return f" (with {trials} each, these intervals span {span} points: tell objects apart " \
        "with care)"


def per_object_detail(data: ReportInput, suffix: str = "") -> list[str]:
    """Per object and method, over its trials: was a true hangable part found, which grasp kinds
    were executed, cage or pinch, the outcomes (``suffix`` ends the heading); an object the
    report has no facts about, or that is no control and has no true hangable part in its
    records (a set's entry without ``hangable_parts``), reads ``unknown`` in the ground-truth
    columns."""
    tags, rows = object_tags(data.frame), []
    parts = data.frame.groupby("object", sort=False).true_parts.max()
    groups = _by_object_and_method(data, "true_part_found", "grasped_true_part", "grasp_kind",
                                   "success", "held_by", "outcome")
    for obj, method in [(o, m) for o in data.objects for m in data.methods]:
        mine = groups.get((obj, method))
        if mine is None:
            continue
        truth = [fraction(mine.true_part_found), fraction(mine.grasped_true_part)]
        no_truth = "control" not in tags.get(obj, ()) and not (
            pd.notna(parts.get(obj)) and parts.get(obj) > 0)
        if UNKNOWN in tags.get(obj, ()) or no_truth:
            truth = [UNKNOWN if t == "-" else t for t in truth]
        rows.append([obj, method, len(mine), *truth,
                     counts(mine.grasp_kind.fillna("").replace("", "none")),
                     f"{int(mine.success.sum())}/{len(mine)}",
                     f"{held(mine, 'cage')} / {held(mine, 'pinch')}", counts(mine.outcome)])
    if not rows:
        return ["", f"## Per object, in detail{suffix}", "", "No trials yet."]
    return ["", f"## Per object, in detail{suffix}", "",
            "Over each object's trials (its random resting poses): *part found*, trials in which "
            "a hanging structure lay on a true hangable part (the object's ground truth); "
            "*hooked it*, trials whose executed GbH grasp hooked one; *kinds*, the executed "
            "grasps; *cage / pinch*, how the successes were held.", ""] + table(
        ["Object", "Method", "Trials", "Part found", "Hooked it", "Kinds", "Success",
         "Cage / pinch", "Outcomes"], rows)


def by_outcome(data: ReportInput) -> list[str]:
    """The failed trials of objects with hangable parts by outcome and method."""
    failed = hangable(data.frame)
    failed = failed[~failed.success]
    by_group = dict(per_group(data, failed))
    order = failed.outcome.value_counts().reset_index().sort_values(
        ["count", "outcome"], ascending=[False, True]).outcome
    rows = [[o, *(int(g.outcome.eq(o).sum()) for g in by_group.values())] for o in order]
    return table(["Outcome", *by_group], rows) if rows else ["No failures."]


def by_cause(data: ReportInput) -> list[str]:
    """The table of :func:`cause_counts`, with what each class means."""
    causes = cause_counts(data)
    out = causes.reset_index().rename(columns={"cause": "Cause"})
    out["Total"] = causes.sum(axis=1).to_numpy()
    return markdown(out) + [
        "", f"Each of the {causes.to_numpy().sum()} failed trials in exactly one class, derived "
        "from its row (gbh_drake/experiment/taxonomy.py): *out of reach*, no candidate passed and "
        "the reach search (below) found no hook pose of this gripper that clears the table and "
        "avoids collision on the true mesh where the object lay; *candidate set missed*, no "
        "candidate passed but the search found a pose on both the true mesh and the trial's "
        "scan; *no structure*, GbH found nothing to hang by; *table clearance*, *collision N_c*, "
        "*closing sweep*, the rule that removed the last candidates (the record's `rejected_by`) "
        "when the search did not decide; *no grasp found*, no candidate passed, in rows without "
        "`rejected_by` (older rows, the antipodal sampler); *IK* / *planner*, every offered "
        "grasp refused, mostly by IK / by the path (RRT-Connect, a collision on a segment, no "
        "clear approach); *lift too low*, held but not lifted clear; *slipped during carry*, "
        "dropped after the lift began; *scan cut/partial*, an empty scan, or a failure decided on "
        "a scan warned to reach the edge of the framed region or the image. "
        f"Plot: {CAUSES_PLOT_FILE}."]


def by_reach(data: ReportInput) -> list[str]:
    """Per method (and protocol): the trials GbH offered no grasp in, by reach class
    (:data:`~gbh_drake.experiment.report.columns.REACH_CLASSES`), and the success rate among
    the trials a loop can reach (all but those *out of reach*)."""
    rows = []
    for label, mine in per_group(data, hangable(data.frame)):
        no_grasp = mine[mine.outcome == "no_grasp_found"]
        reachable = mine.drop(no_grasp.index[no_grasp.reach_class == "out of reach"])
        total, success = tally(reachable)
        rows.append([label, len(mine), len(no_grasp),
                     *(int(no_grasp.reach_class.eq(c).sum()) for c in REACH_CLASSES),
                     f"{success}/{total}", rate(success, total), interval(success, total)])
    return table(["Method", "Trials", "No grasp", *(c.capitalize() for c in REACH_CLASSES),
                  "Success / reachable", "Rate", "95 % CI"], rows) + [
        "", "A trial in which GbH offered no grasp (no_grasp_found) is searched again, densely "
        "(gbh_drake/core/reach.py: every turn about the hole, the rod within 60 deg of the "
        "hole's axis or the vertical, the same gripper solid, table rule and closing sweep), on "
        "the trial's scan and on the true mesh where the object lay (docs/reach.md). *Success / "
        "reachable*: the method's successes among its trials less those *out of reach* (a loop "
        "of this gripper cannot hold the object as it lies: the method's limit, not a defect). "
        "Trials that failed later (IK, planner, carry) are not searched: they count as "
        "reachable."]


def refusals(data: ReportInput) -> list[str]:
    """Grasps refused, by reason (``reason:stage``) and method (objects with hangable parts)."""
    mine = hangable(data.frame)
    long = pd.DataFrame([(i, reason, n) for i, d in mine.refusals.dropna().items()
                         for reason, n in d.items()], columns=["row", "reason", "n"])
    by_group = {label: long[long.row.isin(rows.index)].groupby("reason").n.sum()
                for label, rows in per_group(data, mine)}
    totals = long.groupby("reason").n.sum().reset_index().sort_values(
        ["n", "reason"], ascending=[False, True])
    rows = [[reason, *(int(g.get(reason, 0)) for g in by_group.values())]
            for reason in totals.reason]
    return (table(["Refused by", *by_group], rows) if rows else ["No grasp was refused."]) + [
        "", "A refused grasp is one the planner could not execute (no IK solution or no "
        "collision-free path for a stage); the next ranked grasp is then tried."]


def by_rank(data: ReportInput) -> list[str]:
    """Per method: the executed grasps by rank in their list (the first, 2-3, 4-10, a fallback)
    and those of low value (score below LOW_VALUE x the list's best), each as successes/total:
    how often the planner had to go down the list, and whether that paid."""
    frame, rows = data.frame, []
    for method in data.methods:
        done = frame[(frame.method == method) & frame.grasp_rank.ge(0).fillna(False)]
        primary, rank = done[~done.fallback.fillna(False)], done.grasp_rank
        low = done.grasp_score < LOW_VALUE * done.best_score
        picked = [primary[rank[primary.index] == 0], primary[rank[primary.index].between(1, 2)],
                  primary[rank[primary.index] >= 3], done[done.fallback.fillna(False)],
                  done[(low & done.best_score.gt(0)).fillna(False)]]
        rows.append([method, *(f"{int(p.success.sum())}/{len(p)}" for p in picked)])
    return table(["Method", "#1", "#2-3", "#4+", "Fallback", f"Score < {LOW_VALUE:g} x best"],
                 rows) + [
        "", "Successes / executed grasps, by the executed grasp's rank in its ranked list."]


def by_lift(data: ReportInput) -> list[str]:
    """Per method (and protocol): the executed hooks, those whose lift the unseen space next to
    the scan raised (the plan's note) and how many of them were carried, and the trials judged
    dragged (held but touching the table at the place)."""
    rows = []
    for label, mine in per_group(data, hangable(data.frame)):
        raised = mine[mine.lift_raised]
        rows.append([label, int(mine.grasp_kind.isin(["parallel", "vertical", "scoop"]).sum()),
                     len(raised), int(raised.success.sum()), int(mine.dragged.sum())])
    return table(["Method", "Hooks executed", "Lift raised for unseen space", "Of them carried",
                  "Dragged (held, touching the table at the place)"], rows) + [
        "", "The lift clears the scan's farthest point from the hook by `pick.lift_clearance`, "
            "and the space no camera saw free next to the scan by as much (README, the pick)."]


def failed_trials(data: ReportInput) -> list[str]:
    """Every failed trial of an object with hangable parts, with its replay and how to rerun
    it."""
    failed = hangable(data.frame)
    failed = failed[~failed.success].fillna({"replay": "", "reason": ""})
    several = data.protocols != [DEFAULT_PROTOCOL]
    rows = [[r.object, r.method, r.trial, *([r.protocol] if several else []), r.seed, r.outcome,
             r.reason, f"[replay]({r.replay})" if r.replay else "-"]
            for r in failed.itertuples()]
    if not rows:
        return ["None."]
    return table(["Object", "Method", "Trial", *(["Protocol"] if several else []), "Seed",
                  "Outcome", "Reason", "Replay"], rows) + [
        "", "Rerun one trial: `gbh run scenarios/<method>.yaml --set '{seed: <Seed>, "
        "object: {name: <Object>}}'` in this folder."] + (
        ["For a trial of another protocol than the file's, add its rest: "
         "`object: {name: <Object>, random_pose: {rest: <Protocol>}}`."] if several else [])


def timings(data: ReportInput, runs: list[dict]) -> list[str]:
    """Mean wall seconds per stage and method (a stage a row has no time for counts 0), then
    one line per run of the experiment."""
    frame = data.frame
    rows = [[method, len(mine), *(f"{mine[f'time_{s}'].fillna(0.0).mean():.1f}" for s in STAGES)]
            for method in data.methods if len(mine := frame[frame.method == method])]
    lines = table(["Method", "Trials", *(f"{s.capitalize()} (s)" for s in STAGES)], rows) \
        if rows else ["No trials yet."]
    lines += ["", "Wall seconds per trial in one worker (means); scan, grasps (GbH or the "
                  "sampler) and plan happen inside the simulation."]
    for run in runs:
        trials, wall = run.get("trials") or 0, run.get("wall") or 0.0
        reused = run.get("reused") or 0
        lines.append(f"- {run.get('started') or '?'}: {trials} trials on "
                     f"{run.get('engine') or '?'} in {wall / 60:.1f} min "
                     f"({60.0 * trials / wall if wall else 0.0:.2f} trials/min)"
                     + (f"; {counted(reused, 'trial')} reused from other folders" if reused
                        else "")
                     + (" (interrupted)" if run.get("interrupted") else ""))
    return lines


def presets_line(frame_or_rows) -> str:
    """Which GbH rules each method's trials ran with (``gbh.preset``: ``paper``, the paper's
    values alone, or this implementation's defaults); "" without GbH trials (rows without the
    record field predate it and are left out)."""
    from gbh_drake.experiment.report.columns import frame_of

    frame = frame_or_rows if isinstance(frame_or_rows, pd.DataFrame) else \
        frame_of(list(frame_or_rows))
    gbh = frame[frame.grasp_method.fillna("gbh").ne("antipodal") & frame.gbh_preset.notna()]
    presets = gbh.groupby(["method", gbh.gbh_preset.replace("", "ours")]).size()
    if not len(presets):
        return ""
    return "GbH rules (`gbh.preset`; ours: this implementation's defaults, paper: the paper's " \
        "values): " + "; ".join(f"{m}: {p} ({n} trials)" for (m, p), n in presets.items())


def head(data: ReportInput, command: str = "gbh report") -> list[str]:
    """The title, what ran and how much of it (rebuilt by ``command``), the commits, the GbH
    rules."""
    frame = data.frame
    expected = len(data.objects) * len(data.methods) * data.trials * len(data.protocols)
    done = f"{len(frame)} of {expected} trials done" if data.expected else f"{len(frame)} trials"
    protocols = "" if data.protocols == [DEFAULT_PROTOCOL] else \
        f" x {counted(len(data.protocols), 'protocol')} ({', '.join(data.protocols)})"
    commits = frame.commit.fillna("").value_counts().sort_index()
    lines = [f"# Experiment {data.name}", "",
             f"{counted(len(data.objects), 'object')} x {counted(data.trials, 'trial')} x "
             f"{counted(len(data.methods), 'method')}{protocols}: {done}. Rebuilt from "
             f"`{ROWS_FILE}` by `{command}`."]
    if len(frame) and len(frame) < expected:
        lines += ["", "**Incomplete**: run the same `gbh experiment` command again to finish "
                      "(finished trials are not redone)."]
    lines += ["", "Commit: " + ", ".join(f"`{c or 'unknown'}` ({n} trials)"
                                         for c, n in commits.items())]
    lines += ["", presets_line(frame)] if presets_line(frame) else []
    if data.left_out:
        lines += ["", f"{data.left_out} rows of the file are not trials of this experiment "
                      "(objects, methods or trials it no longer lists) and are left out."]
    return lines


def summary_markdown(data: ReportInput, *, runs: list[dict] | None = None,
                     command: str = "gbh report") -> str:
    """The whole ``summary.md`` (see the package docstring); ``command``: the one writing it
    (``gbh report`` or ``gbh experiment``), as its head says."""
    lines = head(data, command)
    parts = per_protocol(data)
    for suffix, one in parts:
        said = [protocol_text(one.protocols[0], data.object_set), ""] if suffix else []
        lines += ["", f"## Table 1{suffix}", ""] + said + table1(one)
    for suffix, one in parts:
        lines += ["", f"## By resting pose (objects with hangable parts){suffix}", ""] + \
            by_resting_pose(one)
    lines += ["", "## Controls (nothing hangable)", ""] + controls_table(data)
    for suffix, one in parts:
        lines += ["", f"## Per object{suffix}", ""] + per_object(one)
    for suffix, one in parts:
        lines += per_object_detail(one, suffix)
    lines += ["", "## Failures by outcome (objects with hangable parts)", ""] + by_outcome(data)
    lines += ["", "## Failures by cause (objects with hangable parts)", ""] + by_cause(data)
    lines += ["", "## What a loop can reach (objects with hangable parts)", ""] + by_reach(data)
    if any(beyond_paper(data.frame.grasp_method.dropna().unique())):
        lines += ["", "## Beyond the paper: where no rigid loop reaches", ""] + beyond(data)
    lines += ["", "## Grasps refused by reason (objects with hangable parts)", ""] + \
        refusals(data)
    lines += ["", "## Executed grasps by rank", ""] + by_rank(data)
    lines += ["", "## The lift (objects with hangable parts)", ""] + by_lift(data)
    lines += ["", "## Borderline successes: down while held", ""] + borderline(data)
    lines += ["", "## Failed trials (objects with hangable parts)", ""] + failed_trials(data)
    lines += ["", "## Time", ""] + timings(data, runs or [])
    return "\n".join(lines) + "\n"

