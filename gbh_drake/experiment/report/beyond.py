"""The sections about how the successes came: beyond the paper's grasps (where no rigid loop
reaches, the retries) and the borderline successes (down while held)."""

from __future__ import annotations

import pandas as pd

from gbh_drake.experiment.report.columns import HELD_HOW
from gbh_drake.experiment.report.facts import UNKNOWN, beyond_paper, object_tags, tagged
from gbh_drake.experiment.report.inputs import ReportInput
from gbh_drake.experiment.report.tables import (
    controls,
    groups,
    hangable,
    held,
    per_group,
    per_protocol,
    rate,
    table,
)
from gbh_drake.experiment.rows import DEFAULT_PROTOCOL


def out_of_the_loops_reach(frame: pd.DataFrame) -> pd.Series:
    """Per row: whether it is a trial no rigid loop of the paper's gripper reaches as the object
    lies: an object tagged ``flat``, or one tagged ``cup`` lying on its side, resting on its
    handle (:func:`~gbh_drake.experiment.report.facts.object_tags`)."""
    return tagged(frame, "flat") | (tagged(frame, "cup") & frame.resting_pose.eq("on its side"))


def beyond(data: ReportInput) -> list[str]:
    """The trials no rigid loop reaches as the object lies (:func:`out_of_the_loops_reach`), per
    method and protocol: successes, those held by a cage, and how each success was taken
    (``held_how``); then, per object, each beyond-the-paper method beside GbH with the
    fallback; then the controls they hooked by a false structure; then the retries."""
    frame, rows = hangable(data.frame), []
    for label, mine in per_group(data, frame[out_of_the_loops_reach(frame)]):
        if len(mine):
            ways = mine[mine.success].held_how.value_counts()
            rows.append([label, len(mine), f"{int(mine.success.sum())} "
                         f"({rate(int(mine.success.sum()), len(mine))})", held(mine, "cage"),
                         *(int(ways.get(w, 0)) for w in HELD_HOW)])
    tags = object_tags(data.frame)
    names = {t: ", ".join(sorted(o for o, s in tags.items() if t in s)) or "none"
             for t in ("flat", "cup", UNKNOWN)}
    lines = table(["Method", "Trials", "Success", "Cage", *(w.capitalize() for w in HELD_HOW)],
                  rows) + [
        "", f"The trials of the flat objects ({names['flat']}: the 8 mm bar cannot pass under "
        f"material lying on the table) and of the cups ({names['cup']}) lying on their side, "
        "resting on their handle: out of reach of the paper's grasps as the object lies "
        "(docs/reach.md). *Success by*: a hook as it lay; a scoop (the wedge bar slid under the "
        "material, core/scoop.py); a tall scoop (the same under material taller than the "
        "wedge); a hook or a scoop after a regrasp (set down in a pose GbH can "
        "hook, scanned again, core/regrasp.py); the antipodal fallback's pinch. *Cage*: "
        "successes the cage test found held on the closed loop." + (
            f" Objects the report has no facts about ({names[UNKNOWN]}) are not counted here."
            if names[UNKNOWN] != "none" else "")]
    def using(test) -> list[str]:
        return [m for m in data.methods
                if any(test(data.frame[data.frame.method == m].grasp_method.dropna()))]

    extra = using(beyond_paper)
    compared = using(lambda kinds: kinds.eq("gbh_fallback")) + extra
    for suffix, one in per_protocol(data):
        one_tags, cells = object_tags(one.frame), []
        mine = one.frame.groupby(["object", "method"]).agg(
            trials=("success", "size"), successes=("success", "sum"),
            cage=("held_by", lambda h: int(h.eq("cage").sum())))
        for obj in [o for o in one.objects if "control" not in one_tags.get(o, ())]:
            cells.append([obj, *(_tally_cell(mine, obj, m) for m in compared)])
        lines += ["", f"### Per object{suffix}", ""] + table(["Object", *compared], cells)
    hooked = ["hook", "scoop", "tall scoop"]
    rows = [[label, len(mine), int((mine.success & mine.held_how.isin(hooked)).sum()),
             int((mine.success & mine.held_how.str.contains("pinch")).sum())]
            for (label, method, _), (_, mine) in zip(groups(data),
                                                     per_group(data, controls(data.frame)),
                                                     strict=True)
            if method in extra]
    if rows:
        lines += ["", "### Controls", ""] + table(
            ["Method", "Trials", "Hooked (a false structure)", "Pinched (the fallback)"], rows)
    return lines + retries(data)


def _tally_cell(counted: pd.DataFrame, obj: str, method: str) -> str:
    """``k/n (c cage)`` of (object, method) in ``counted`` (trials, successes, cage); ``-``."""
    if (obj, method) not in counted.index:
        return "-"
    row = counted.loc[(obj, method)]
    return f"{row.successes}/{row.trials} ({row.cage} cage)"


def retries(data: ReportInput) -> list[str]:
    """Per method (and protocol) that retried: the trials whose first lift came away empty
    (the record's ``attempts``), how many of them were then carried, and held by a cage or a
    pinch; no retries, no section."""
    rows = []
    for label, mine in per_group(data, data.frame[data.frame.attempts.fillna(0) > 0]):
        if len(mine):
            carried = mine[mine.success]
            rows.append([label, len(mine), len(carried), held(carried, "cage"),
                         held(carried, "pinch")])
    if not rows:
        return []
    return ["", "### Retries", ""] + table(
        ["Method", "Trials retried (a lift came away empty)", "Then carried", "Cage", "Pinch"],
        rows) + ["", "A retry: the hand opens, goes home, the object is scanned again and the "
                     "pick planned anew without the structure that failed (`pick.max_retries`)."]


def _cm(metres) -> str:
    return "unknown" if pd.isna(metres) else f"{100.0 * metres:.1f} cm"


def borderline(data: ReportInput) -> list[str]:
    """The successes whose lifted object came back down while held (the verdict's
    ``sank_phase`` in the lift, carry or hold) or touched the table while carried
    (``table_touch_while_carried``), per method and protocol and one by one, with how low it
    came (``min_clearance_after_lift`` where the rows have it, else unknown)."""
    frame = data.frame
    rows = []
    for label, mine in per_group(data, frame[frame.success]):
        down = mine[mine.borderline_success]
        rows.append([label, len(mine), len(down),
                     int(down.table_touch_while_carried.fillna(False).sum()),
                     _cm(down.min_clearance_after_lift.min())])
    lines = table(["Method", "Successes", "Down while held", "Of them touched the table",
                   "Lowest after the lift"], rows)
    several = data.protocols != [DEFAULT_PROTOCOL]
    down = frame[frame.borderline_success.fillna(False)]
    listed = [[r.object, r.method, r.trial, *([r.protocol] if several else []), r.held_by,
               r.sank_phase or "-", "-" if pd.isna(r.sank_at) else f"{r.sank_at:.2f}",
               "yes" if pd.notna(r.table_touch_while_carried) and r.table_touch_while_carried
               else "no",
               _cm(r.min_clearance_after_lift) + ("" if pd.isna(r.min_clearance_phase) else
                                                  f" ({r.min_clearance_phase})")]
              for r in down.itertuples()]
    if listed:
        lines += [""] + table(["Object", "Method", "Trial", *(["Protocol"] if several else []),
                               "Held by", "Came down in", "At (s)", "Touched the table",
                               "Lowest after the lift"], listed)
    in_test = int((frame.success & frame.sank_phase.eq("cage_test").fillna(False)).sum())
    unknown = not frame.min_clearance_after_lift.notna().any()
    return lines + [
        "", f"{int(frame.borderline_success.sum())} of {int(frame.success.sum())} successes "
        "(controls included) are borderline: once lifted, the object came back below half the "
        "lifted height (`monitor.lifted_height`; 1 cm at its default 2 cm) while a gripper body "
        "still touched it, in the lift, carry or hold (the verdict's `sank_phase`, `sank_at`), "
        "or touched the table during the lift or carry (`table_touch_while_carried`). They "
        "count as successes (held, and lifted clear at the end of the hold) but came down on "
        "the way. *Lowest after the lift*: the verdict's `min_clearance_after_lift`"
        + (" (these rows do not have it: unknown)" if unknown else "") + f". {in_test} "
        "successes came down during the cage test, after success was decided (the squeeze "
        "relaxed: a pinch), and are not counted here."]
