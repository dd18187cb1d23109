"""The report's tables as frames (``trials.csv``, ``table1.csv``, the causes) and the helpers
the sections share: rates with their Wilson intervals, the columns by method (and protocol),
Markdown tables."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator

import pandas as pd

from gbh_drake.experiment.report.columns import COLUMNS, UNKNOWN_CAUSE
from gbh_drake.experiment.report.facts import tagged
from gbh_drake.experiment.report.inputs import ReportInput
from gbh_drake.experiment.rows import DEFAULT_PROTOCOL
from gbh_drake.experiment.stats import wilson
from gbh_drake.experiment.taxonomy import CAUSES


# ---- rates ----------------------------------------------------------------------------------
def rate(successes: int, total: int) -> str:
    """``75.0 %``; ``-`` without trials."""
    return f"{100.0 * successes / total:.1f} %" if total else "-"


def interval(successes: int, total: int, digits: int = 1) -> str:
    """The Wilson 95 % interval of the rate, ``[lo, hi] %``; ``-`` without trials."""
    if not total:
        return "-"
    lo, hi = wilson(successes, total)
    return f"[{100.0 * lo:.{digits}f}, {100.0 * hi:.{digits}f}] %"


def tally(frame: pd.DataFrame) -> tuple[int, int]:
    """(trials, successes) of ``frame``."""
    return len(frame), int(frame.success.sum())


def held(frame: pd.DataFrame, by: str) -> int:
    """The successes of ``frame`` held by ``by`` (``cage`` or ``pinch``)."""
    return int((frame.success & frame.held_by.eq(by).fillna(False)).sum())


def fraction(flags: pd.Series) -> str:
    """``k/n`` of the flags that are known (not missing), or ``-``."""
    known = flags.dropna()
    return f"{int(known.sum())}/{len(known)}" if len(known) else "-"


def counts(values) -> str:
    """``a x2, b x1``: each distinct value (sorted) with its count."""
    return ", ".join(f"{k} x{n}" for k, n in sorted(Counter(values).items()))


# ---- which rows ------------------------------------------------------------------------------
def hangable(frame: pd.DataFrame) -> pd.DataFrame:
    """The rows of objects with hangable parts (not tagged ``control``)."""
    return frame[~tagged(frame, "control")]


def controls(frame: pd.DataFrame) -> pd.DataFrame:
    """The rows of the controls (objects tagged ``control``: nothing to hang by)."""
    return frame[tagged(frame, "control")]


def groups(data: ReportInput) -> list[tuple[str, str, str | None]]:
    """(column label, method, protocol) of the tables by method: each method (protocol None:
    any), or with several protocols each method in each protocol, ``gbh-10 (natural)``."""
    if len(data.protocols) <= 1:
        return [(m, m, None) for m in data.methods]
    return [(f"{m} ({p})", m, p) for p in data.protocols for m in data.methods]


def per_group(data: ReportInput, frame: pd.DataFrame) -> Iterator[tuple[str, pd.DataFrame]]:
    """(label, the rows of ``frame`` of that method and protocol) for each of :func:`groups`."""
    for label, method, protocol in groups(data):
        yield label, frame[(frame.method == method) & (
            True if protocol is None else frame.protocol == protocol)]


def per_protocol(data: ReportInput) -> list[tuple[str, ReportInput]]:
    """(heading suffix, the input of one protocol) for each protocol; a single ``("", data)``
    for an experiment of the ``stable`` protocol alone (its report as before protocols)."""
    if data.protocols == [DEFAULT_PROTOCOL]:
        return [("", data)]
    return [(f", protocol `{p}`", data.of_protocol(p)) for p in data.protocols]


# ---- Markdown --------------------------------------------------------------------------------
def _md(text) -> str:
    """A table cell: no pipes or line breaks."""
    return str(text).replace("|", "/").replace("\n", " ")


def table(header: list[str], rows: list[list]) -> list[str]:
    """A Markdown table (pandas' ``to_markdown``: columns padded to their width)."""
    return markdown(pd.DataFrame([[_md(c) for c in row] for row in rows],
                                 columns=[_md(h) for h in header]))


def markdown(frame: pd.DataFrame) -> list[str]:
    """The lines of ``frame`` as a Markdown table, its cells as written (no number parsing)."""
    return frame.astype(str).to_markdown(index=False, disable_numparse=True).splitlines()


# ---- the frames written beside summary.md ------------------------------------------------------
def trials_frame(data: ReportInput) -> pd.DataFrame:
    """``trials.csv``: one row per trial (controls included), the frame's columns marked for it
    (:data:`~gbh_drake.experiment.report.columns.COLUMNS`: the row's fields, its ``cause``
    (empty for a success), ``resting_pose``, the pose as pose_x .. pose_yaw, record fields,
    stage times as ``time_<stage>`` (wall s), the borderline-success fields), refusals as
    ``key xN``, then any other field the rows carry."""
    frame = data.frame
    out = frame[[c.name for c in COLUMNS if c.csv] + list(frame.columns[len(COLUMNS):])].copy()
    out["refusals"] = frame.refusals.map(lambda d: counts(Counter(d)) if isinstance(d, dict) else "")
    return out


def table1_frame(data: ReportInput) -> pd.DataFrame:
    """Table 1 as numbers (objects with hangable parts): per protocol and method its trials,
    successes, rate and Wilson 95 % interval (fractions; empty without trials), cage, pinch."""
    out = []
    mine = hangable(data.frame)
    for protocol, method in [(p, m) for p in data.protocols for m in data.methods]:
        rows = mine[(mine.method == method) & (mine.protocol == protocol)]
        total, success = tally(rows)
        lo, hi = wilson(success, total) if total else (None, None)
        out.append({"protocol": protocol, "method": method, "viewpoints": viewpoints(rows, ","),
                    "trials": total, "successes": success,
                    "rate": success / total if total else None, "wilson_lo": lo, "wilson_hi": hi,
                    "cage": held(rows, "cage"), "pinch": held(rows, "pinch")})
    return pd.DataFrame(out, columns=["protocol", "method", "viewpoints", "trials", "successes",
                                      "rate", "wilson_lo", "wilson_hi", "cage", "pinch"])


def viewpoints(rows: pd.DataFrame, sep: str) -> str:
    """The rows' viewpoints (those given and nonzero), sorted, joined by ``sep``."""
    return sep.join(str(v) for v in sorted(set(rows.viewpoints.dropna()) - {0}))


def cause_counts(data: ReportInput) -> pd.DataFrame:
    """Failed trials of the objects with hangable parts by cause (rows: every class of
    :data:`~gbh_drake.experiment.taxonomy.CAUSES`, zeros included, and ``unknown`` when a row's
    outcome had none) and method (columns; with several protocols, method and protocol:
    ``gbh-10 (natural)``)."""
    failed = hangable(data.frame)
    failed = failed[~failed.success]
    label = pd.Series(pd.NA, index=failed.index, dtype="string")
    for name, rows in per_group(data, failed):
        label[rows.index] = name
    causes = [*CAUSES, *([UNKNOWN_CAUSE] if failed.cause.eq(UNKNOWN_CAUSE).any() else [])]
    return (pd.crosstab(failed.cause, label)
            .reindex(index=causes, columns=[g[0] for g in groups(data)], fill_value=0)
            .rename_axis(index="cause", columns="method"))
