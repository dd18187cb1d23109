"""One trial in a worker process: build the trial diagram, simulate it, make its row.

A GbH trial that offered no grasp (:data:`REACH_OUTCOMES`) also gets a ``reach`` field: the
reach analysis of :mod:`gbh_drake.experiment.reach` on its scan and on the true mesh
(``stage_times["reach"]`` its seconds).

A worker process (local or a Ray worker) runs one trial at a time and keeps its imported modules,
the objects' models and one Meshcat server across trials. Trials run single-threaded
(``OMP_NUM_THREADS=1``, set before the first heavy import): the experiment's parallelism is
across trials, and a fixed thread count keeps every row the same whatever the number of workers
or the engine.

This module imports nothing heavy at its top (see :mod:`gbh_drake.experiment.task`).
"""

from __future__ import annotations

import logging
import os
import signal
import socket
import time
import traceback

from gbh_drake.experiment.task import TrialResult, TrialTask
from gbh_drake.outputs import plain

#: Row fields that are measurements of this run, not results: they differ between runs and are
#: left out when rows are compared (:func:`gbh_drake.experiment.rows.comparable`).
TIMING_FIELDS = ("stage_times", "worker")

#: Outcomes of a GbH trial that get a ``reach`` field (the reach analysis, issue 18): GbH
#: found structures but offered no grasp. Not ``no_hangable_structure``: with no structure on
#: the scan there is nothing to search around on it, and the cause is the perception's.
REACH_OUTCOMES = ("no_grasp_found",)

_meshcat = None
_worker_process = False
_assets: dict = {}
#: Objects whose models a worker keeps (an object set's worth).
ASSET_CACHE_SIZE = 32


def set_single_threaded() -> None:
    """Makes this process a trial worker: one OpenMP thread per trial (call it before open3d or
    pydrake are imported: the pool's initializer, the first task of a Ray worker), Drake's INFO
    messages silenced (they would break the progress bar), Ctrl-C left to the parent."""
    global _worker_process
    _worker_process = True
    os.environ["OMP_NUM_THREADS"] = "1"
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's: it ends the workers


def _local_meshcat():
    """This process's Meshcat (loopback only), created at the first trial and reused."""
    global _meshcat
    if _meshcat is None:
        from gbh_drake.viz.meshcat_server import local_meshcat

        _meshcat = local_meshcat()
    return _meshcat


def _object_asset(scenario):
    """The trial's object model (mesh, mass properties), built once per worker and object:
    the trials of an object differ only in its pose (stable poses are cached by the object set
    itself)."""
    from gbh_drake.modeling.object_asset import load_object_asset

    o = scenario.object
    key = (o.name, o.set, o.mesh, o.scale, o.orientation, o.density, o.mass,
           str(scenario.directory))
    if key not in _assets:
        while len(_assets) >= ASSET_CACHE_SIZE:
            _assets.pop(next(iter(_assets)))
        _assets[key] = load_object_asset(o, scenario.directory)
    return _assets[key]


def run_worker_task(task: TrialTask) -> TrialResult:
    """:func:`run_trial_task` in a process made a trial worker first (:func:`set_single_threaded`,
    once): what a Ray worker runs, whose process has no initializer."""
    if not _worker_process:
        set_single_threaded()
    return run_trial_task(task)


def run_trial_task(task: TrialTask) -> TrialResult:
    """Runs ``task`` and returns its row (and its replay's HTML when it failed and replays are
    kept). An exception in the pipeline becomes a row with outcome ``error`` (and the traceback),
    so that one broken trial does not stop the experiment. It leaves the process as it found
    it (its signal handlers too): a process made a trial worker is the engine's doing
    (:func:`set_single_threaded`, :func:`run_worker_task`)."""
    start = time.perf_counter()
    try:
        return _run(task, start)
    except Exception as e:  # a bug in the pipeline: recorded, not fatal
        row = _base_row(task)
        row.update(outcome="error", success=False, reason=f"{type(e).__name__}: {e}",
                   traceback=traceback.format_exc(),
                   stage_times={"total": time.perf_counter() - start})
        return TrialResult(plain(row))


def _run(task: TrialTask, start: float) -> TrialResult:
    from pydrake.common.yaml import yaml_load_typed

    from gbh_drake.scenario import Scenario
    from gbh_drake.trial import record_trial

    if _worker_process:  # (pydrake's import sets the level: set it after)
        logging.getLogger("drake").setLevel(logging.WARNING)
    scenario = yaml_load_typed(schema=Scenario, data=task.scenario_yaml)
    scenario.source_path = task.source_path
    meshcat = _local_meshcat() if task.replays != "none" else None
    done = record_trial(scenario, meshcat=meshcat, asset=_object_asset(scenario),
                        keep_replay=lambda r: task.replays == "all" or not r.success)
    record, seconds = done.record, done.seconds
    row = _base_row(task)
    row.update(
        grasp_method=record.method, viewpoints=record.num_views, pose=record.pose,
        outcome=record.outcome, success=bool(record.success), reason=record.reason,
        held_by=record.held_by, grasp_kind=record.grasp_kind, grasp_score=record.grasp_score,
        grasp_rank=record.grasp_rank, fallback=bool(record.fallback),
        refusals=dict(record.refusals),
        stage_times={"build": seconds["build"], "scan": record.timings.get("scan", 0.0),
                     "grasps": record.timings.get("grasps", 0.0),
                     "plan": record.timings.get("plan", 0.0),
                     "simulate": seconds["simulate"], "replay": seconds["replay"],
                     "total": time.perf_counter() - start},
        record=record.to_dict(),
    )
    if record.outcome in REACH_OUTCOMES and done.trial.source.hanging_structures is not None:
        reach_start = time.perf_counter()
        try:
            row["reach"] = _reach(done).row()
        except Exception as e:  # the analysis, not the trial, failed: recorded, not fatal
            row["reach"] = {"error": f"{type(e).__name__}: {e}"}
        row["stage_times"]["reach"] = time.perf_counter() - reach_start
        row["stage_times"]["total"] = time.perf_counter() - start
    return TrialResult(plain(row), done.replay_html)


def _reach(done):
    """The reach analysis (:func:`gbh_drake.experiment.reach.reach_of_trial`) of a finished
    GbH trial ``done`` (a ``TrialRun``): on the structures GbH found on its scan, and on the
    object's true mesh at the pose it ended in (the robot never touched it: an outcome of
    :data:`REACH_OUTCOMES`, so that is where it rested when scanned), with the trial's GbH
    params and sampling seed."""
    from gbh_drake.experiment.reach import reach_of_trial

    trial, context = done.trial, done.simulator.get_context()
    hangability = trial.source.hanging_structures.Eval(
        trial.source.hanging_structures.get_system().GetMyContextFromRoot(context))
    plant = trial.station.plant
    X_WO = plant.EvalBodyPoseInWorld(plant.GetMyContextFromRoot(context),
                                     trial.station.object_body())
    true_mesh = trial.station.asset.mesh.copy().apply_transform(X_WO.GetAsMatrix4())
    return reach_of_trial(hangability.object, true_mesh, trial.scenario.gbh,
                          seed=trial.seeds.sampling, scan_structures=hangability.structures)


def _base_row(task: TrialTask) -> dict:
    """The fields every row has, also an ``error`` row (and ``object_digest`` for an object
    set's mesh)."""
    digest = {"object_digest": task.object_digest} if task.object_digest else {}
    return {
        "experiment": task.experiment, "object": task.object, "is_control": task.is_control,
        "object_tags": list(task.object_tags),
        "method": task.method, "trial": task.trial, "seed": task.seed,
        "grasp_method": "", "viewpoints": 0, "pose": [], "outcome": "", "success": False,
        "reason": "", "held_by": "", "grasp_kind": "", "grasp_score": None, "grasp_rank": -1,
        "fallback": False, "refusals": {}, "replay": "", "commit": task.commit,
        "scenario_digest": task.digest, "worker": f"{socket.gethostname()}:{os.getpid()}",
        "stage_times": {}, "record": {}, **digest,
    }
