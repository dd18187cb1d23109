"""Runs an experiment into its folder: resume, run the remaining trials, write rows and reports.

The steps of :func:`run_experiment`: list every trial (:func:`~gbh_drake.experiment.config.
make_tasks`), read the rows already in the folder and skip their trials (except those that ended
in an error, a bug rather than a result: they are run again), run the others on the chosen
engine (local worker processes or Ray) under a progress bar, append each row as it arrives (and
its replay when it failed), then sort the rows and write the reports
(:func:`~gbh_drake.experiment.report.write_report`).

The folder::

    trials.jsonl          one row per trial (see gbh_drake.experiment.rows)
    summary.md            Table 1 beside the paper's (Wilson 95 % intervals, McNemar's test per
                          pair of methods), per object, failures by outcome and by cause, timings
    trials.csv            one row per trial, flat (pandas.read_csv), with its failure cause
    table1.csv            per method: trials, successes, rate, Wilson lo/hi, cage, pinch
    success.png, .svg     success rate per method with Wilson error bars: totals, then per object
    causes.png, .svg      the failures per method stacked by cause
    experiment.yaml       the resolved experiment (gbh report reads it), without where it ran
                          (engine, ray_address: runs.jsonl says); its paths relative to the
                          folder and its output the folder: gbh experiment on it resumes there
    scenarios/<m>.yaml    each method's scenario (rerun a trial with gbh run and --set)
    replays/<o>__<m>__<t>.html   a Meshcat replay of every failed trial (``__<protocol>``
                          before ``.html`` for a protocol other than ``stable``)
    runs.jsonl            when each run started, on what, how long it took (and the trials
                          it reused from other folders, if any)
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import datetime
import json
import os
import re
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from gbh_drake import interrupts
from gbh_drake.core.arguments import argument_problem, require
from gbh_drake.experiment.config import (
    Experiment,
    ExperimentError,
    experiment_yaml,
    git_commit,
    make_tasks,
    method_scenarios,
    trial_scenario_yaml,
)
from gbh_drake.experiment.engines import local_results, ray_results
from gbh_drake.experiment.report import EXPERIMENT_FILE, RUNS_FILE, read_runs, write_report
from gbh_drake.experiment.reuse import reuse_rows
from gbh_drake.experiment.rows import (
    DEFAULT_PROTOCOL,
    ROWS_FILE,
    RowStore,
    protocol_of,
    row_key,
    sort_key,
)
from gbh_drake.outputs import (
    MIN_FREE_BYTES,
    FolderLock,
    OutputError,
    prepare_folder,
    reason,
    remove,
    write_atomically,
    write_file,
)


@dataclass
class ExperimentRun:
    """What one call of :func:`run_experiment` did."""

    folder: Path
    total: int
    """Trials of the experiment."""
    skipped: int
    """Trials found finished in the folder (not redone)."""
    ran: int
    """Trials run now."""
    wall: float
    """Seconds this run took."""

    @property
    def complete(self) -> bool:
        return self.skipped + self.ran == self.total


def replay_name(row: dict) -> str:
    """``<object>__<method>__<trial>.html`` (``<object>__<method>__<trial>__<protocol>.html``
    for a protocol other than ``stable``) with anything unusual in a name made ``_``."""
    def safe(s) -> str:
        return re.sub(r"[^A-Za-z0-9._+-]", "_", str(s))

    protocol = protocol_of(row)
    tail = "" if protocol == DEFAULT_PROTOCOL else f"__{safe(protocol)}"
    return f"{safe(row['object'])}__{safe(row['method'])}__{int(row['trial'])}{tail}.html"


def run_experiment(experiment: Experiment, *, out: Path | None = None, workers: int = 1,
                   ray_address: str = "", progress: bool = True, log=print,
                   reuse: tuple = ()) -> ExperimentRun:
    """Runs the trials of ``experiment`` not yet in its folder (``out`` or its ``output_dir``);
    see the module docstring. ``workers``: local worker processes (or the CPUs of a ``local``
    Ray); ``ray_address``: run on Ray at that address (``local``, ``auto`` or a cluster's
    address) whatever the experiment's ``engine``; empty: where the experiment says (``engine:
    ray``: Ray at its ``ray_address``, else local workers). The engine changes no row: a folder
    resumes whatever ran it. ``reuse``: other experiments' folders whose rows of the same trials
    and scenarios are taken instead of running them (:mod:`gbh_drake.experiment.reuse`).
    Raises :class:`ExperimentError` when the folder holds rows of other scenarios."""
    require("run_experiment", "experiment", experiment, Experiment,
            "an Experiment (gbh_drake.experiment.config.load_experiment(path))")
    require("run_experiment", "out", out, (str, os.PathLike, type(None)), "a folder's path or None")
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise TypeError(argument_problem("run_experiment", "workers", "an integer >= 1", workers))
    start = time.perf_counter()
    ray_address = ray_address or experiment.ray_engine_address()
    folder = Path(out) if out else experiment.output_path()
    scenarios = method_scenarios(experiment)  # a bad method is refused before the folder is made
    prepare_folder(folder, min_free=MIN_FREE_BYTES)  # OutputError: exit 2
    with FolderLock(folder, holder="gbh experiment", hint="give another folder (--out)"):
        tasks = make_tasks(experiment, commit=git_commit(), scenarios=scenarios)
        store = RowStore(folder)
        done = _finished(store, tasks, warn=log)
        read_runs(folder, warn=log, repair=True)  # a damaged log refuses before any trial runs
        reused = reuse_rows(folder, store, tasks, done, reuse, log=log)
        pending = [t for t in tasks if t.key not in done]
        _write_definition(folder, experiment, scenarios)
        engine = (f"Ray ({ray_address}" + (f", {workers} CPUs)" if ray_address == "local"
                                           else ")")) if ray_address else \
            f"{workers} local worker{'s' if workers != 1 else ''}"
        protocols = "" if experiment.protocols == [DEFAULT_PROTOCOL] else \
            f" x {len(experiment.protocols)} protocols"
        log(f"{experiment.name}: {len(tasks)} trials ({len(experiment.objects)} objects x "
            f"{experiment.trials} x {len(experiment.methods)} methods{protocols}) in {folder}; "
            f"{len(done)} done before, {len(pending)} to run on {engine}")
        per_worker = experiment.trials_per_worker
        results = ray_results(pending, ray_address, workers=workers, log=log,
                              trials_per_worker=per_worker) if ray_address \
            else local_results(pending, workers, trials_per_worker=per_worker)
        started = datetime.datetime.now().isoformat(timespec="seconds")
        ran, interrupted, failed, replay_errors = 0, True, None, {}
        bar = _progress_bar(len(pending), experiment.name, enabled=progress)
        by_digest = {(t.object, t.method, t.trial, t.digest): t for t in pending}

        def warn(message: str) -> None:
            bar.write(message, file=sys.stderr)

        try:
            for result in results:
                interrupts.check()  # a signal whose exception some library dropped
                row = result.row
                _set_protocol(row, by_digest)
                with interrupts.deferred():  # the row, then its replay
                    problem = _save(folder, store, row, result.replay_html, warn=warn)
                if problem:
                    replay_errors[row_key(row)] = problem
                done[row_key(row)] = row
                if row["outcome"] == "error":
                    bar.write(f"{experiment.name}: trial {row_key(row)} ended in an error "
                              f"(run again to retry it): {row['reason']}")
                ran += 1
                bar.set_postfix_str(f"{sum(bool(r['success']) for r in done.values())}/"
                                    f"{len(done)} succeeded", refresh=False)
                bar.update(1)
            interrupted = False
        except BaseException as e:
            failed = e
            raise
        finally:
            bar.close()
            wall = time.perf_counter() - start
            # Stopped by an error or a signal: what follows must not hide it (a full disk fails
            # these too): their own failures are warnings then, every row written is kept.
            with _said_if(failed is not None, warn):
                if ran or reused or interrupted:  # (a run that only reused rows is a run)
                    _log_run(folder, started=started, wall=wall, trials=ran, engine=engine,
                             interrupted=interrupted, **({"reused": reused} if reused else {}))
            if not interrupted and len(done) == len(tasks):
                _sort_rows(store, experiment, replay_errors)
            with _said_if(failed is not None, warn):
                write_report(folder, warn=log, command="gbh experiment")
    return ExperimentRun(folder, len(tasks), len(tasks) - len(pending), ran, wall)


@contextlib.contextmanager
def _said_if(stopping: bool, warn):
    """While an experiment is stopping on an error or a signal: an output that cannot be
    written is a warning (the first error is the one reported), else it is raised."""
    try:
        yield
    except OSError as e:
        if not stopping:
            raise
        warn(f"gbh: warning: {e if isinstance(e, OutputError) else reason(e)}")


def _save(folder: Path, store: RowStore, row: dict, replay_html: str | None, *, warn
          ) -> str | None:
    """Appends ``row`` first, then puts its replay (if any) into ``replays/`` (written to a
    hidden temporary file, renamed into place): a finished trial's row is kept whatever becomes
    of its replay. A replay that cannot be written (the disk filled, a name too long) is a
    warning naming the file, and the experiment goes on; the row says where the replay should
    be until the rows are sorted at the end of a complete run (:func:`_sort_rows`: ``replay``
    emptied, ``replay_error`` says why); returns why (``<file>: <problem>``), or None. A row that cannot
    be appended is an :class:`OutputError` (the file keeps its whole rows; that trial runs
    again on resume)."""
    target = None
    if replay_html is not None:
        name = replay_name(row)
        target = folder / "replays" / name
        row["replay"] = f"replays/{name}"
    try:
        store.append(row)
    except OSError as e:
        raise OutputError(store.path, f"could not append the row of trial {row_key(row)} "
                                      f"({reason(e)})") from None
    if target is None:
        return None
    staged = None
    try:
        target.parent.mkdir(exist_ok=True)
        staged = write_file(target, replay_html)
        os.replace(staged, target)
    except OSError as e:
        if staged is not None:
            remove(staged)
        problem = f"{target}: {e.problem if isinstance(e, OutputError) else reason(e)}"
        warn(f"gbh: warning: trial {row_key(row)}: its replay was not kept: {problem}; its row "
             "is")
        return problem
    return None


def _set_protocol(row: dict, by_digest: dict) -> None:
    """Writes the protocol of the row's task into it (the worker's row does not carry it; its
    object, method, trial and scenario digest name the task)."""
    task = by_digest[(row["object"], row["method"], int(row["trial"]), row["scenario_digest"])]
    row["protocol"] = task.protocol


def _finished(store: RowStore, tasks, *, warn=None) -> dict:
    """The rows already in the folder that are trials of ``tasks``, by key; a trial that ended
    in an error (a bug, not a result) is not finished: it is run again. Raises
    :class:`ExperimentError` if a row was made with another scenario than its task's, or with
    another version of its object set's entry
    (:meth:`~gbh_drake.experiment.task.TrialTask.differs`)."""
    from gbh_drake.objects.sets import OBJECT_FACTS

    by_key = {t.key: t for t in tasks}
    done, stale = {}, {"scenario": [], "object": []}
    for row in store.load(repair=True, warn=warn):
        task = by_key.get(row_key(row))
        if task is None:
            continue  # not a trial of this experiment: kept in the file, left out of reports
        differs = task.differs(row)
        if differs:
            stale[differs].append(row_key(row))
        elif row.get("outcome") == "error":
            done.pop(task.key, None)
        else:
            done[task.key] = row
    start_over = f"write to another folder (--out), or move {ROWS_FILE} away to start over"
    if stale["scenario"]:
        raise ExperimentError(
            str(store.path), "", None,
            f"{len(stale['scenario'])} rows were made with other scenarios than this "
            f"experiment's (its base, method overrides, pose or seed changed since), e.g. "
            f"{stale['scenario'][0]}; {start_over}")
    if stale["object"]:
        objects = sorted({key[0] for key in stale["object"]})
        raise ExperimentError(
            str(store.path), "", None,
            f"{len(stale['object'])} rows were made with other objects than this experiment's "
            f"(the object set's entry of {', '.join(objects)} changed since: its mesh file or "
            f"{', '.join(f.replace('_', ' ') for f in OBJECT_FACTS)}), e.g. "
            f"{stale['object'][0]}; {start_over}")
    return done


def _write_definition(folder: Path, experiment: Experiment, scenarios: dict) -> None:
    """``experiment.yaml`` and each method's scenario, for reports and reruns (its
    ``object.set`` relative to ``scenarios/``, where the file is: ``gbh run
    scenarios/<method>.yaml`` finds the manifest)."""
    write_atomically(folder / EXPERIMENT_FILE, experiment_yaml(experiment, folder))
    (folder / "scenarios").mkdir(exist_ok=True)
    for name, scenario in scenarios.items():
        if scenario.object.set:
            manifest = scenario.resolve(scenario.object.set)
            scenario = copy.copy(scenario)
            scenario.object = dataclasses.replace(scenario.object, set=os.path.relpath(
                manifest, (folder / "scenarios").resolve()))
        write_atomically(folder / "scenarios" / f"{name}.yaml", trial_scenario_yaml(scenario))


def _sort_rows(store: RowStore, experiment: Experiment, replay_errors: dict | None = None
               ) -> None:
    """Rewrites the rows in report order (object, method, trial), one per trial; a row of this
    run whose replay could not be written says so (``replay_errors``, by trial: ``replay``
    emptied, ``replay_error`` why). The rows of earlier runs are kept as they are."""
    rows = {row_key(r): r for r in store.load()}
    for key, problem in (replay_errors or {}).items():
        row = rows.get(key)
        if row is not None and row.get("replay") and \
                not (store.path.parent / row["replay"]).is_file():
            row["replay"], row["replay_error"] = "", problem
    key = sort_key(experiment.objects, [m.name for m in experiment.methods],
                   experiment.protocols)
    store.rewrite(sorted(rows.values(), key=key))


def _log_run(folder: Path, **fields) -> None:
    """Appends one line to ``runs.jsonl`` (an :class:`OutputError` when it cannot)."""
    try:
        with open(folder / RUNS_FILE, "a") as f:
            f.write(json.dumps(fields, sort_keys=True) + "\n")
    except OSError as e:
        raise OutputError(folder / RUNS_FILE, f"could not append to it ({reason(e)})") from None


def _progress_bar(total: int, name: str, *, enabled: bool):
    from tqdm import tqdm

    return tqdm(total=total, desc=name, unit="trial", disable=not enabled or total == 0,
                dynamic_ncols=True, smoothing=0.1)
