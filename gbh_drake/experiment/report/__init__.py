"""The experiment's reports, rebuilt from its rows alone.

The rows are read once into one typed pandas DataFrame (:mod:`.columns`: a trial per row, every
column named with its dtype and meaning; :mod:`.inputs` reads the folder), and each section of
``summary.md`` is a short function of it (:mod:`.sections`, :mod:`.beyond`); object-set facts
come from :func:`~.facts.object_tags`, the paper's figures from :mod:`.facts`.

``summary.md`` holds: the Table-1-style table (objects with hangable parts; Method, Viewpoints,
Total, Success, Fail, Rate and its Wilson 95 % interval, held by cage or pinch) with the paper's
real-robot figures beside it, and under it every pair of methods compared on the same (object,
trial) poses (McNemar's exact test, the difference in rate with a paired-bootstrap 95 %
interval, Holm-adjusted p-values: :mod:`gbh_drake.experiment.stats`); success by resting pose
(upright, on its side, upside down), the controls (objects with nothing to hang) apart, a table
per object (each rate with its interval), the failures by outcome and by cause
(:func:`gbh_drake.experiment.taxonomy.cause_of`), what a loop can reach, beyond the paper, the
grasps refused by reason, the executed grasps by rank, the lift, the borderline successes (the
object down while held), a list of the failed trials with their replays and how to rerun one,
and timings. A rate of zero trials is printed "-".

Beside it, for a researcher to load: ``trials.csv`` (one row per trial: the columns of
:data:`~.columns.COLUMNS` marked for it; see :func:`trials_frame`) and ``table1.csv`` (per
protocol and method: trials, successes, rate, Wilson lo/hi, cage, pinch); the plots
``success.png``/``.svg`` (a heatmap of object x method per protocol, cell k/n, colour the rate)
and ``causes.png``/``.svg`` (the failure causes per method, stacked, a colour per cause). Rows
are ordered by object, method and trial as the experiment lists them, never by when they
finished, so the same rows give the same report.

Protocols (``stable``, ``natural``: how the objects were set down): an experiment of the
``stable`` protocol alone gets the report it had before protocols existed (but for the
``protocol`` columns of the CSVs); with another protocol, Table 1 (with its paired comparison),
the resting poses, the per-object tables and the success plot are given once per protocol, and
the tables by method have a column per method and protocol (``gbh-10 (natural)``). A row
without a protocol is ``stable``; a protocol the report has no description for is said to be
one.
"""

from __future__ import annotations

from pathlib import Path

from gbh_drake.core.resting import resting_pose
from gbh_drake.experiment.report.beyond import beyond, borderline, out_of_the_loops_reach, retries
from gbh_drake.experiment.report.columns import (
    COLUMNS,
    HELD_HOW,
    REACH_CLASSES,
    RECORD_FIELDS,
    STAGES,
    UNSEEN_LIFT_NOTE,
    Column,
    frame_of,
)
from gbh_drake.experiment.report.facts import (
    CUPS,
    FLAT_OBJECTS,
    PAPER_TABLE1,
    PROTOCOL_TEXT,
    beyond_paper,
    object_tags,
)
from gbh_drake.experiment.report.inputs import (
    EXPERIMENT_FILE,
    RUNS_FILE,
    ReportInput,
    read_input,
    read_runs,
    read_saved_experiment,
)
from gbh_drake.experiment.report.plots import plot_causes, plot_success
from gbh_drake.experiment.report.sections import (
    CAUSES_PLOT_FILE,
    LOW_VALUE,
    by_cause,
    by_lift,
    by_rank,
    by_reach,
    by_resting_pose,
    paired,
    per_object_detail,
    presets_line,
    summary_markdown,
    table1,
    table1_by_protocol,
)
from gbh_drake.experiment.report.tables import cause_counts, table1_frame, trials_frame
from gbh_drake.outputs import write_atomically

#: Files the report writes into the folder.
SUMMARY_FILE = "summary.md"
PLOT_FILE = "success.png"
TRIALS_CSV = "trials.csv"
TABLE1_CSV = "table1.csv"


def write_report(folder: Path, *, warn=None, data: ReportInput | None = None,
                 command: str = "gbh report") -> tuple[Path, Path]:
    """Writes ``summary.md``, ``trials.csv``, ``table1.csv`` and the plots (``success`` and
    ``causes``, PNG and SVG) into ``folder`` from its rows (``data``: as read already by
    :func:`read_input`); returns the summary and ``success.png``. ``command``: the command
    writing it (``gbh experiment`` passes its name), named in the summary's head. Everything is
    read (and checked) before anything is written."""
    folder = Path(folder)
    data = data or read_input(folder, warn=warn)
    runs = read_runs(folder, warn=warn)
    summary = folder / SUMMARY_FILE
    write_atomically(summary, summary_markdown(data, runs=runs, command=command))
    write_atomically(folder / TRIALS_CSV, trials_frame(data).to_csv(index=False))
    write_atomically(folder / TABLE1_CSV, table1_frame(data).to_csv(index=False))
    plot = folder / PLOT_FILE
    plot_success(data, plot)
    plot_causes(data, folder / CAUSES_PLOT_FILE)
    return summary, plot


def held_how(row: dict) -> str:
    """How a successful trial's object was taken (:data:`HELD_HOW`), from one row."""
    return frame_of([row]).held_how.iloc[0]


def reach_class(row: dict) -> str:
    """The reach class (:data:`REACH_CLASSES`) of a ``no_grasp_found`` row (see
    :func:`~.columns.reach_class_of`)."""
    return frame_of([row]).reach_class.iloc[0]


__all__ = [
    "CAUSES_PLOT_FILE", "COLUMNS", "CUPS", "EXPERIMENT_FILE", "FLAT_OBJECTS", "HELD_HOW",
    "LOW_VALUE", "PAPER_TABLE1", "PLOT_FILE", "PROTOCOL_TEXT", "REACH_CLASSES", "RECORD_FIELDS",
    "RUNS_FILE", "STAGES", "SUMMARY_FILE", "TABLE1_CSV", "TRIALS_CSV", "UNSEEN_LIFT_NOTE",
    "Column", "ReportInput", "beyond", "beyond_paper", "borderline", "by_cause", "by_lift",
    "by_rank", "by_reach", "by_resting_pose", "cause_counts", "frame_of", "held_how",
    "object_tags", "out_of_the_loops_reach", "paired", "per_object_detail", "plot_causes",
    "plot_success", "presets_line", "read_input", "read_runs", "read_saved_experiment",
    "reach_class", "resting_pose", "retries", "summary_markdown", "table1",
    "table1_by_protocol", "table1_frame", "trials_frame", "write_atomically", "write_report"
]
