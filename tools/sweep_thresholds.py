"""Sensitivity of GbH's thresholds over the whole object set, on the experiment's own trials.

Every trial of an experiment (its objects x trials, at the same seeds and poses as
``gbh experiment``) is scanned once, for each GbH method of the experiment (10 views, 1 view):
the trial's diagram is built and simulated until the scan is taken. Then GbH's three stages run
on each scan once per value of each swept parameter (the others at the scenario's values), and
per value the script counts, over all trials:

* ``part found``: trials with a hanging structure on a true hangable part (the object set's
  ground truth: c within half the part's clear diameter + 2 cm of its centre);
* ``grasp on part``: trials with a ranked (collision-free, table-clear) grasp on a true part,
  ``top on part``: whose best grasp is on one: what the planner would try first;
* ``false structures``: structures not on a true part, ``controls hit``: control trials with any
  structure (a control hooked by a false structure is the worst error);
* ``seconds``: the GbH core's median time per scan.

It does not simulate the pick (the experiment does that with the chosen values): these are the
pre-execution counts, the stage a threshold decides. Several experiment files may be given (an
object set each: the own set's ``scenarios/experiment.yaml`` and the external set's
``scenarios/experiment_external.yaml``), so that a threshold is swept over every set together:
each table has a row per set and one for all of them (``all``). Usage::

    python tools/sweep_thresholds.py scenarios/experiment.yaml \\
        scenarios/experiment_external.yaml --out docs/thresholds \\
        --sweep contact_angle_deg=25,30,35,40,45 --sweep snap_tilt_max_deg=0,30,45,60 \\
        --sweep "approach_rotations_deg=[0];[0,-20,20];[0,-20,20,-40,40]"

A trial's key is ``[object, method, trial, experiment]`` (the experiment's ``name``).

``free_views`` (``scan`` or ``all``) is not a GbH parameter: it gives the core the scan's free
space alone, or also that of the first look's two side views (``FreeSpace.with_views``), e.g.
``--set unknown_is_occupied=true --sweep free_views=scan,all``. Since the exit proof
(``GbhParams.through_proof_exit``) a scan's ``free_space`` already holds the first look's
views, as the trial's GbH gets it; scans stored before hold the fused views alone, and ``all``
is what the trial does now.

writes ``<out>/scans.pkl`` (the scans, reused by later runs; ``--scans PATH``: a cache several
sweeps share) with its keys beside it (``scans.keys.json``: the main process reads those, not
the scans, when they are newer than the cache), ``<out>/rows.jsonl`` and prints the Markdown
tables (``<out>/README.md``).
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")


def scanned_trial(scenario_yaml: str, source_path):
    """(scenario, trial, simulator, scan): the trial of ``scenario_yaml`` (its file
    ``source_path``) built and simulated until its Scanner has taken the scan (once the object
    is still; at most 10 simulated seconds), as ``gbh experiment`` would."""
    import logging

    from pydrake.common.yaml import yaml_load_typed
    from pydrake.systems.analysis import Simulator

    from gbh_drake.scenario import Scenario
    from gbh_drake.trial import build_trial

    logging.getLogger("drake").setLevel(logging.WARNING)
    scenario = yaml_load_typed(schema=Scenario, data=scenario_yaml)
    scenario.source_path = source_path
    trial = build_trial(scenario)
    simulator = Simulator(trial.diagram)
    simulator.Initialize()
    port = trial.scanner.GetOutputPort("mesh_W")
    t = scenario.settle_time
    while True:  # until the scan is taken (once the object is still)
        simulator.AdvanceTo(t)
        scan = port.Eval(trial.scanner.GetMyContextFromRoot(simulator.get_context()))
        if getattr(scan, "taken_at", t) == getattr(scan, "taken_at", t) or t > 10.0:  # not nan
            break
        t += 0.05
    return scenario, trial, simulator, scan


def _scan_task(args):
    """(key, scan record) of one trial: the scanned mesh, the ground and the truth (parts in W)."""
    key, scenario_yaml, source_path = args
    import numpy as np

    scenario, trial, _, scan = scanned_trial(scenario_yaml, source_path)
    X = trial.station.X_WO_initial
    parts = [(np.asarray(X.multiply(p.center_O)), 0.5 * p.clear_diameter + 0.02)
             for p in trial.station.asset.hangable_parts]
    return key, {"vertices": np.asarray(scan.mesh_W.vertices), "faces": np.asarray(
        scan.mesh_W.faces), "empty": bool(scan.empty), "ground": scan.table.as_ground()
        if scan.table is not None else None, "parts": parts, "seed": trial.seeds.sampling,
        "gbh": scenario.gbh, "gbh_overrides": gbh_overrides(scenario.gbh),
        "free_space": getattr(scan, "free_space", None),
        "look_free_space": getattr(scan, "first_look_free_space", None)}


def gbh_overrides(params) -> dict:
    """The fields of a trial's GbhParams that differ from the defaults (the experiment's method
    overrides, e.g. ``d2``): what a later run applies to *its* defaults, so that a cache of
    scans outlives a change of the code's defaults or new fields."""
    import dataclasses

    from gbh_drake.core.params import GbhParams

    default = GbhParams()
    return {f.name: getattr(params, f.name) for f in dataclasses.fields(GbhParams)
            if getattr(params, f.name) != getattr(default, f.name)}


def trial_params(record: dict):
    """The GbhParams a scan's trial runs with today: today's defaults with the trial's
    overrides (``gbh_overrides``); a cache written before those were kept: the stored
    parameters' fields over today's defaults (new fields at their defaults)."""
    import copy as copy_
    import dataclasses

    from gbh_drake.core.params import GbhParams

    if "gbh_overrides" in record:
        return dataclasses.replace(GbhParams(), **copy_.deepcopy(record["gbh_overrides"]))
    stored = vars(record["gbh"])
    return dataclasses.replace(GbhParams(), **{f.name: copy_.deepcopy(stored[f.name])
                                               for f in dataclasses.fields(GbhParams)
                                               if f.name in stored})


#: The pseudo-parameter that picks the free space GbH gets (``scan`` or ``all``, see _gbh_task).
FREE_VIEWS = "free_views"
_SCANS: dict = {}
#: Parameter values set under every swept value (``--set``).
_BASE: dict = {}


def _load_scans(path: str, base: dict) -> None:
    """Worker initializer: the scans, read once per worker (not sent with every job), and the
    ``--set`` values."""
    _SCANS.update(pickle.loads(Path(path).read_bytes()))
    _BASE.update(base)


def _gbh_task(args):
    """Counts of one scan (by key, from the worker's copy) under one parameter value."""
    key, name, value = args
    record = _SCANS[key]
    import numpy as np
    import trimesh

    from gbh_drake.core.pipeline import plan_grasps
    from gbh_drake.core.results import GbhInputError

    params = trial_params(record)  # the trial's own, as the trial's GbH systems use it
    options = {**_BASE, name: value}
    # Not a GbH parameter: which views' free space the core gets, the fused views' ("scan") or
    # also the first look's two side views ("all").
    views = options.pop(FREE_VIEWS, "scan")
    for option, option_value in options.items():
        setattr(params, option, option_value)
    free = record.get("free_space")
    if views == "all" and free is not None and record.get("look_free_space") is not None:
        free = free.with_views(record["look_free_space"])
    out = {"key": list(key), "param": name, "value": value, "base": dict(_BASE),
           "structures": 0, "false": 0,
           "part_found": False, "grasp_on_part": False, "top_on_part": False,
           "top_false": False, "ranked": 0, "seconds": 0.0}
    if record["empty"] or not len(record["faces"]):
        return out
    mesh = trimesh.Trimesh(record["vertices"], record["faces"], process=False)

    def on_part(c) -> bool:
        return any(np.linalg.norm(np.asarray(c) - center) <= r for center, r in record["parts"])

    start = time.perf_counter()
    try:
        result = plan_grasps(mesh, params, seed=record["seed"], free_space=free)
    except GbhInputError:
        return out
    out["seconds"] = time.perf_counter() - start
    found = [on_part(s.c) for s in result.structures]
    ranked = [on_part(g.structure.c) for g in result.ranked]
    out.update(structures=len(found), false=len(found) - sum(found), part_found=any(found),
               grasp_on_part=any(ranked), top_on_part=bool(ranked and ranked[0]),
               top_false=bool(ranked and not ranked[0]), ranked=len(ranked))
    return out


def _parse_sweep(text: str):
    """``NAME=V1,V2`` (numbers), ``NAME=[..];[..]`` (lists) or ``free_views=scan,all``: the
    name and its values, integers for a GbhParams field of type int, booleans for a bool."""
    name, values = text.split("=", 1)
    if name == FREE_VIEWS:
        return name, values.split(",")
    if values.startswith("["):
        return name, [json.loads(v) for v in values.split(";")]
    kind = _field_type(name)
    if kind is bool:
        return name, [json.loads(v) for v in values.split(",")]
    return name, [kind(float(v)) if kind is int else float(v) for v in values.split(",")]


def _field_type(name: str):
    """The type of GbhParams field ``name`` (float when it has none of that name)."""
    import dataclasses

    from gbh_drake.core.params import GbhParams

    types = {f.name: f.type for f in dataclasses.fields(GbhParams)}
    return types.get(name, float) if types.get(name) in (int, bool, float) else float


def _table(rows: list[dict], controls: set[tuple[str, str]]) -> list[str]:
    """Markdown tables, one per swept parameter: a row per value, method and set (the
    experiment's name, the key's 4th item) and, with more than one set, for ``all``.
    ``controls``: (experiment, object) of the control objects."""
    lines = []
    sets = list(dict.fromkeys(_set_of(r) for r in rows))
    groups = [*sets, "all"] if len(sets) > 1 else sets
    by = {}
    for r in rows:
        for s in (_set_of(r), "all"):
            by.setdefault((r["param"], json.dumps(r["value"]), r["key"][1], s), []).append(r)
    for param in dict.fromkeys(r["param"] for r in rows):
        lines += ["", f"### `{param}`", "",
                  "| value | method | set | part found | grasp on part | top on part | top on a "
                  "false part | false structures | controls hit | median s |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        first = list(dict.fromkeys(k[:3] for k in by))  # each value's rows: per set, then all
        for (p, value, method, s), group in sorted(
                by.items(), key=lambda kv: (first.index(kv[0][:3]),
                                            groups.index(kv[0][3]) if kv[0][3] in groups else 0)):
            if p != param or s not in groups:
                continue
            is_control = [(_set_of(r), r["key"][0]) in controls for r in group]
            parts = [r for r, c in zip(group, is_control, strict=True) if not c]
            ctrl = [r for r, c in zip(group, is_control, strict=True) if c]
            lines.append(
                f"| {value} | {method} | {s} | {sum(r['part_found'] for r in parts)}/{len(parts)} | "
                f"{sum(r['grasp_on_part'] for r in parts)}/{len(parts)} | "
                f"{sum(r['top_on_part'] for r in parts)}/{len(parts)} | "
                f"{sum(r.get('top_false', False) for r in parts)}/{len(parts)} | "
                f"{sum(r['false'] for r in group)} | "
                f"{sum(r['structures'] > 0 for r in ctrl)}/{len(ctrl)} | "
                f"{statistics.median(r['seconds'] for r in group):.2f} |")
    return lines


def _set_of(row: dict) -> str:
    """The set (experiment name) of a row; rows of one experiment before sets were keyed
    [object, method, trial]: ``own``."""
    return row["key"][3] if len(row["key"]) > 3 else "own"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiments", nargs="+", metavar="experiment",
                        help="experiment files (one per object set: all are swept together)")
    parser.add_argument("--out", required=True)
    parser.add_argument("--sweep", action="append", default=[], metavar="NAME=V1,V2")
    parser.add_argument("--set", dest="base", action="append", default=[],
                        metavar="NAME=VALUE", help="a GbH parameter set under every swept value "
                                                   "(JSON value, e.g. unknown_is_occupied=true)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--scans", help="the scans' cache (default <out>/scans.pkl): several "
                                         "sweeps may share one")
    parser.add_argument("--methods", default="gbh-10,gbh-1")
    parser.add_argument("--protocols", default="stable",
                        help="the experiment's protocols to scan (comma-separated); the scans "
                             "of one protocol per output folder (a trial's key has none)")
    args = parser.parse_args(argv)

    from gbh_drake.experiment.config import load_experiment, make_tasks

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    methods = args.methods.split(",")
    tasks, controls = [], set()
    for path in args.experiments:
        experiment = load_experiment(path)
        experiment.methods = [m for m in experiment.methods if m.name in methods]
        experiment.protocols = args.protocols.split(",")
        for t in make_tasks(experiment):
            tasks.append((experiment.name, t))
            if t.is_control:
                controls.add((experiment.name, t.object))
    cache = Path(args.scans) if args.scans else out / "scans.pkl"
    listed = cache.with_suffix(".keys.json")  # the cache's keys, so this process need not load it
    keys_only = cache.is_file() and listed.is_file() \
        and listed.stat().st_mtime >= cache.stat().st_mtime
    if keys_only:
        scans = dict.fromkeys(tuple(k) for k in json.loads(listed.read_text()))
    else:
        scans = pickle.loads(cache.read_bytes()) if cache.is_file() else {}
    todo = [((t.object, t.method, t.trial, name), t.scenario_yaml, t.source_path)
            for name, t in tasks if (t.object, t.method, t.trial, name) not in scans]
    start = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        for i, (key, record) in enumerate(pool.map(_scan_task, todo, chunksize=2)):
            scans[key] = record
            if (i + 1) % 20 == 0:
                print(f"scanned {i + 1}/{len(todo)} ({time.perf_counter() - start:.0f} s)",
                      file=sys.stderr)
    if todo:
        if keys_only:  # only the keys were read: add the new scans to the cache's own
            scans = {**pickle.loads(cache.read_bytes()),
                     **{k: v for k, v in scans.items() if v is not None}}
        cache.write_bytes(pickle.dumps(scans))
    keys = set(scans)
    listed.write_text(json.dumps(sorted(keys)))
    del scans  # each worker reads the cache itself: one copy per process is enough
    sweeps = [_parse_sweep(s) for s in args.sweep]
    base = {k: v if k == FREE_VIEWS else json.loads(v)
            for k, v in (b.split("=", 1) for b in args.base)}
    wanted = {(t.object, t.method, t.trial, name) for name, t in tasks}
    jobs = [(key, name, value) for name, values in sweeps for value in values
            for key in sorted(k for k in keys if k in wanted)]
    with ProcessPoolExecutor(args.workers, initializer=_load_scans,
                             initargs=(str(cache), base)) as pool:
        rows = []
        for i, row in enumerate(pool.map(_gbh_task, jobs, chunksize=4)):
            rows.append(row)
            if (i + 1) % 200 == 0:
                print(f"GbH {i + 1}/{len(jobs)} ({time.perf_counter() - start:.0f} s)",
                      file=sys.stderr)
    with open(out / "rows.jsonl", "w") as f:
        for r in rows:
            f.write(json.dumps(r) + "\n")
    text = "\n".join(_table(rows, controls))
    (out / "README.md").write_text(text + "\n")
    print(text)
    print(f"{len(keys)} scans, {len(rows)} GbH runs in {time.perf_counter() - start:.0f} s",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
