"""Hand check of the reach analysis on one experiment trial: search the trial's scan (or the true
mesh at its start pose) and execute the best passing pose through the trial's own diagram
(``GivenGrasps``: the same scan, planner, physics and cage test). Usage::

    python tools/reach_handcheck.py OBJECT METHOD TRIAL {scan,true} \\
        [--scans /tmp/sweep_fs/scans.pkl] [--rows docs/experiment/trials.jsonl]

needs the sweep's scans (tools/sweep_thresholds.py) and the experiment's rows (the pose); the
stable protocol.
"""

from __future__ import annotations

import argparse
import logging
import pickle
import sys
from dataclasses import dataclass

import numpy as np


@dataclass
class Grasp:
    """A grasp of one's own: the open gripper's pose X_WG and how it closes."""

    X_WG: np.ndarray
    kind: str


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("object")
    parser.add_argument("method")
    parser.add_argument("trial", type=int)
    parser.add_argument("mesh", choices=["scan", "true"])
    parser.add_argument("--scans", default="/tmp/sweep_fs/scans.pkl")
    parser.add_argument("--rows", default="docs/experiment/trials.jsonl")
    args = parser.parse_args(argv)

    import trimesh
    from pydrake.common.yaml import yaml_load_typed
    from pydrake.math import RigidTransform, RollPitchYaw

    from gbh_drake.core.pipeline import detect
    from gbh_drake.core.reach import search_reach
    from gbh_drake.experiment.config import load_experiment, make_tasks
    from gbh_drake.methods import GivenGrasps
    from gbh_drake.modeling.object_asset import load_object_asset
    from gbh_drake.scenario import Scenario
    from gbh_drake.scenario.schema import ObjectConfig
    from gbh_drake.trial import build_trial, simulate_trial

    logging.getLogger("drake").setLevel(logging.WARNING)
    experiment = load_experiment("scenarios/experiment.yaml")
    experiment.protocols = ["stable"]
    task = next(t for t in make_tasks(experiment) if (t.object, t.method, t.trial) ==
                (args.object, args.method, args.trial))
    scenario = yaml_load_typed(schema=Scenario, data=task.scenario_yaml)
    scenario.source_path = task.source_path
    with open(args.scans, "rb") as f:
        scan = pickle.load(f)[(args.object, "gbh-10" if args.method == "gbh+fallback"
                               else args.method, args.trial)]
    params = scan["gbh"]
    if args.mesh == "scan":
        mesh = trimesh.Trimesh(scan["vertices"], scan["faces"], process=False)
    else:
        from gbh_drake.experiment.rows import read_jsonl, row_problem

        row = next(r for r in read_jsonl(args.rows, check=row_problem)
                   if (r["object"], r["method"], r["trial"]) == (args.object, args.method, args.trial))
        x, y, z, roll, pitch, yaw = row["pose"]
        X_WO = RigidTransform(RollPitchYaw(roll, pitch, yaw), np.array([x, y, z]))
        mesh = load_object_asset(ObjectConfig(name=args.object), ".").mesh.copy()
        mesh.apply_transform(X_WO.GetAsMatrix4())
    obj, structures = detect(mesh, params, scan["seed"])
    reach = search_reach(obj, structures, params, budget_s=float("inf"))
    print(f"reach on the {args.mesh}: {reach.classification}, best margin "
          f"{reach.best_margin * 1e3:.1f} mm, {reach.best_kind}")
    if reach.best_X_WG is None:
        return 0
    trial = build_trial(scenario, method=GivenGrasps([Grasp(reach.best_X_WG, reach.best_kind)]))
    _, record = simulate_trial(trial)
    print(f"executed: {record.outcome} [{record.held_by}]: {record.reason}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
