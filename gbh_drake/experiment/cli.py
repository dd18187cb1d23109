"""The ``gbh experiment`` and ``gbh report`` subcommands (wired into :mod:`gbh_drake.cli`).

    gbh experiment EXPERIMENT.yaml [--workers N] [--ray ADDRESS] [--out DIR] [--set YAML]
                                   [--no-progress]
    gbh report DIR

``--ray ADDRESS`` overrides the experiment file's ``engine`` and ``ray_address`` (docs/ray.md).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

#: The subcommands this module adds.
COMMANDS = ("experiment", "report")


def default_workers() -> int:
    """This process's CPUs."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else \
        (os.cpu_count() or 1)


def add_subcommands(sub) -> None:
    """Adds ``experiment`` and ``report`` to the ``gbh`` subparsers ``sub``."""
    p = sub.add_parser("experiment", help="run objects x trials x methods (the paper's Table 1)",
                       description="Runs the experiment's trials not yet in its folder (an "
                                   "interrupted experiment resumes), then writes summary.md, "
                                   "trials.csv, table1.csv and the plots.")
    p.add_argument("experiment", help="experiment YAML file (e.g. "
                                      "scenarios/experiment_small.yaml)")
    p.add_argument("--workers", type=int, default=default_workers(),
                   help="local worker processes, each one trial at a time (default: the "
                        "CPUs, %(default)s); with --ray local: the local Ray's CPUs")
    p.add_argument("--ray", default="", metavar="ADDRESS",
                   help="run the trials as Ray tasks: 'local' (a Ray on this machine, "
                        "loopback only), 'auto' (the cluster this machine is in) or a "
                        "cluster's address; overrides the file's engine and ray_address "
                        "(docs/ray.md)")
    p.add_argument("--out", default=None, help="the experiment's folder (default: its "
                                               "output_dir, else output/<file stem>)")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="YAML",
                   help="YAML applied over the experiment file, e.g. --set 'trials: 1' (may be "
                        "repeated: applied in order); a relative path in it (output_dir, base) "
                        "is relative to the current folder, one in the file to its folder")
    p.add_argument("--reuse", action="append", default=[], metavar="FOLDER",
                   help="another experiment's folder: its rows of the same trials with the "
                        "same scenarios (object, pose, seed, method overrides) are copied in "
                        "instead of running them again (may be repeated); the rows keep their "
                        "commit, which the report lists")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")

    p = sub.add_parser("report", help="rebuild an experiment's summary.md, CSVs and plots "
                                      "from its rows")
    p.add_argument("folder", help="the experiment's folder (holds trials.jsonl)")


def run_command(args: argparse.Namespace) -> int:
    """Runs ``gbh experiment`` or ``gbh report``; returns the exit code."""
    if args.command == "report":
        return _report(Path(args.folder))
    return _experiment(args)


def _report(folder: Path) -> int:
    from gbh_drake.experiment.report import read_input, table1_by_protocol, write_report
    from gbh_drake.experiment.rows import ROWS_FILE, FolderError

    if not (folder / ROWS_FILE).is_file():
        print(f"gbh: {folder}: no {ROWS_FILE} (not an experiment folder)", file=sys.stderr)
        return 2
    try:  # everything is read and checked before anything is written
        data = read_input(folder, warn=_warn)
        summary, plot = write_report(folder, warn=_warn, data=data)
        lines = table1_by_protocol(data)
    except FolderError as e:
        _say(f"damaged experiment folder: {e}")
        return 2
    print("\n".join(lines))
    print(f"wrote {summary} and {plot}")
    return 0


def _experiment(args: argparse.Namespace) -> int:
    from gbh_drake import interrupts

    try:
        return _run_experiment(args)
    except KeyboardInterrupt:  # SIGINT, SIGTERM, SIGHUP (gbh_drake.interrupts)
        _say(f"experiment {interrupts.describe()}; the finished trials are saved: run the "
             "same command to resume")
        interrupts.mark_said()
        return interrupts.exit_code()


def _run_experiment(args: argparse.Namespace) -> int:
    from gbh_drake import interrupts
    from gbh_drake.experiment.config import ExperimentError, field_error, load_experiment
    from gbh_drake.experiment.engines import RAY_MISSING, RayError, ray_installed, ray_missing
    from gbh_drake.experiment.report import read_input, table1_by_protocol
    from gbh_drake.experiment.rows import FolderError
    from gbh_drake.experiment.runner import run_experiment

    interrupts.check()  # a signal during the imports above
    if args.workers < 1:
        print("gbh: --workers must be at least 1", file=sys.stderr)
        return 2
    if args.ray and not ray_installed():  # before anything runs: Ray is an optional extra
        print(f"gbh: {RAY_MISSING}", file=sys.stderr)
        return 2
    try:
        experiment = load_experiment(args.experiment, overrides=args.overrides)
        if not args.ray and experiment.engine == "ray" and not ray_installed():
            _say("cannot use Ray: " + str(field_error(
                experiment, "engine", "ray " + ray_missing("--set 'engine: local'"))))
            return 2
        interrupts.check()
        result = run_experiment(experiment, out=Path(args.out) if args.out else None,
                                workers=args.workers, ray_address=args.ray,
                                progress=not args.no_progress, reuse=tuple(args.reuse))
        interrupts.check()
    except ExperimentError as e:
        _say(f"invalid experiment: {e}")
        return 2
    except FolderError as e:
        _say(f"damaged experiment folder: {e}")
        return 2
    except RayError as e:
        _say(f"cannot use Ray: {e}")
        return 2
    print("\n".join(table1_by_protocol(read_input(result.folder))))
    print(f"{result.ran} trials run, {result.skipped} found done, in {result.wall / 60:.1f} min; "
          f"wrote {result.folder / 'summary.md'}")
    return 0


def _say(message: str) -> None:
    """One line on stderr (a message is never split over lines)."""
    print(f"gbh: {' '.join(message.split())}", file=sys.stderr, flush=True)


def _warn(message: str) -> None:
    print(f"gbh: warning: {message}", file=sys.stderr, flush=True)
