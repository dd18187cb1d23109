"""One-view scans of an experiment's trials: the view GbH-1 takes, and every view it could take.

For each trial (object, trial, protocol) of an experiment's one-view method, the trial's diagram
is simulated until the object is still and the scan is taken (as ``gbh experiment`` does), then,
on the scene as it is at that moment:

* ``fixed``: the scan the trial took (the method's one view);
* ``look``: the first look (its two small side views, what the view choice sees);
* ``candidates``: {index: scan} of one full view from each direction of the candidate layout
  (``perception.view_choice.candidate_configs``), each scanned as a one-view scan; with
  ``--candidates 0``, only the fixed view's (index 0, the trial's scan) and the chosen one's
  (``perception.view_choice.choose_view``): enough for every variant but the oracle;

with the object's true hangable parts in W and whether it is a control. Written one pickle per
trial into ``<out>/scans/`` (existing ones are kept: the run resumes). ``tools/sweep_oneview.py``
reads them. Usage::

    python tools/oneview_scans.py scenarios/experiment.yaml --method gbh-1 --out /tmp/ov1 \\
        --objects mug_classic,pot --protocols stable,natural --trials 5
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")


def scan_key(task) -> str:
    """The file stem of a trial's scans: object, protocol, trial."""
    return f"{task.object}__{task.protocol}__{task.trial}"


def _scan_task(args):
    """Scans one trial (see the module docstring) into ``path``."""
    path, scenario_yaml, source_path, is_control, candidates = args
    import numpy as np
    from sweep_thresholds import scanned_trial  # tools/, this script's folder

    from gbh_drake.perception.scan import first_look, scan_object
    from gbh_drake.perception.view_choice import candidate_configs
    from gbh_drake.station import scene_query_port

    scenario, trial, simulator, scan = scanned_trial(scenario_yaml, source_path)
    station_context = trial.station.GetMyContextFromRoot(simulator.get_context())
    query = trial.station.GetOutputPort(scene_query_port(scenario.scan.renderer_name)).Eval(
        station_context)
    config, p_WT = scenario.scan, scenario.scan_target
    seed = trial.seeds.noise
    look = first_look(query, config, p_WT, noise_seed=seed)
    configs = candidate_configs(config, candidates or None)
    if candidates:
        views = {i: scan_object(query, c, p_WT, noise_seed=seed) for i, c in enumerate(configs)}
    else:  # the fixed view (the trial's scan) and the chosen one
        from gbh_drake.perception.view_choice import choose_view
        from gbh_drake.perception.viewpoints import fit_view_distance

        views = {0: scan}
        if look.found:
            index = choose_view(look, config, look.centre_W,
                                fit_view_distance(look.radius, config)[0]).index
            views[index] = views.get(index) or scan_object(query, configs[index], p_WT,
                                                           noise_seed=seed)
    X = trial.station.X_WO_initial
    parts = [(np.asarray(X.multiply(p.center_O)), np.asarray(X.rotation().multiply(p.axis_O)),
              float(p.clear_diameter)) for p in trial.station.asset.hangable_parts]
    record = {"fixed": scan, "look": look, "candidates": views, "parts": parts,
              "control": bool(is_control), "seed": trial.seeds.sampling, "gbh": scenario.gbh,
              "scan_config": config, "p_WT": np.asarray(p_WT, dtype=float),
              "X_WO": X.GetAsMatrix4(), "mesh_O": (np.asarray(trial.station.asset.mesh.vertices),
                                                   np.asarray(trial.station.asset.mesh.faces))}
    tmp = Path(str(path) + ".tmp")
    tmp.write_bytes(pickle.dumps(record))
    tmp.replace(path)
    return str(path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiment")
    parser.add_argument("--out", required=True)
    parser.add_argument("--method", default="gbh-1", help="the experiment's one-view method")
    parser.add_argument("--objects", default="", help="comma-separated (default: all)")
    parser.add_argument("--protocols", default="", help="comma-separated (default: the file's)")
    parser.add_argument("--trials", type=int, default=0, help="default: the file's")
    parser.add_argument("--candidates", type=int, default=10,
                        help="candidate views (the spiral layout of this many); 0: the "
                             "fixed and the chosen view alone (the scan config's candidates)")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)

    from gbh_drake.experiment.config import load_experiment, make_tasks

    experiment = load_experiment(args.experiment)
    experiment.methods = [m for m in experiment.methods if m.name == args.method]
    if args.objects:
        experiment.objects = args.objects.split(",")
    if args.protocols:
        experiment.protocols = args.protocols.split(",")
    if args.trials:
        experiment.trials = args.trials
    out = Path(args.out) / "scans"
    out.mkdir(parents=True, exist_ok=True)
    tasks = make_tasks(experiment)
    todo = [(out / f"{scan_key(t)}.pkl", t.scenario_yaml, t.source_path, t.is_control,
             args.candidates) for t in tasks if not (out / f"{scan_key(t)}.pkl").is_file()]
    start = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        for i, path in enumerate(pool.map(_scan_task, todo)):
            print(f"{i + 1}/{len(todo)} {Path(path).stem} ({time.perf_counter() - start:.0f} s)",
                  file=sys.stderr, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
