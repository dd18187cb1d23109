"""The most any hook grasp of this gripper could carry on an experiment's poses: an upper bound.

    python tools/reach_bound.py FOLDER [--method gbh-10] [--clearance 0] [--workers 2]

For every trial of ``--method`` in the experiment folder FOLDER (its ``experiment.yaml`` and
``trials.jsonl``) on an object with hangable parts that did not succeed, the reach search
(:func:`gbh_drake.core.reach.search_reach`: every turn about each hanging structure, the rod
within 60 deg of the hole's axis or the vertical, the pipeline's collision and closing-sweep
rules) runs on the object's **true** mesh where it rested when GbH planned (the verdict's first
planned pose; the robot never touched it before), with the trial's own GbH parameters except
the table clearance, which is ``--clearance`` (m; default 0: the gripper may touch the table but
not enter it, a physical limit rather than the planner's 3 mm margin). A trial with no
collision-free pose at or above that clearance that holds material cannot be carried by any hook
grasp of this gripper where the object lies, whatever the scan, the ranking or the planner. The
bound per protocol is

    (trials - those out of reach) / trials

of the objects with hangable parts; successes count as reachable without a search, and so does
a trial on whose true mesh GbH's detector finds no structure (nothing to search around: not
proved out of reach). It prints each searched trial (its best pose's height above the table)
and the bound per protocol.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")


def rest_pose(row: dict) -> list[float]:
    """[x, y, z, roll, pitch, yaw] (m, rad) of the object where it rested when GbH planned (the
    verdict's first planned pose), else the trial's start pose (``drop_height`` above its rest:
    its ground distances are then that much too high)."""
    planned = ((row.get("record") or {}).get("verdict") or {}).get("planned_poses") or []
    return list(planned[0]) if planned else list(row["pose"])


def true_reach(args: tuple) -> dict:
    """The reach search on the true mesh of one row's trial (see the module docstring)."""
    experiment_path, row, clearance = args
    import numpy as np
    from pydrake.math import RigidTransform, RollPitchYaw

    from gbh_drake.core.pipeline import detect
    from gbh_drake.core.reach import search_reach
    from gbh_drake.core.results import GbhInputError
    from gbh_drake.experiment.config import trial_scenario
    from gbh_drake.modeling.object_asset import load_object_asset

    scenario = trial_scenario(experiment_path, row["object"], row["method"], row["trial"],
                              row.get("protocol") or "stable")
    params = dataclasses.replace(scenario.gbh, ground_clearance=float(clearance))
    asset = load_object_asset(scenario.object, scenario.directory)
    x, y, z, roll, pitch, yaw = rest_pose(row)
    X_WO = RigidTransform(RollPitchYaw(roll, pitch, yaw), np.array([x, y, z]))
    mesh = asset.mesh.copy()
    mesh.apply_transform(X_WO.GetAsMatrix4())
    key = {k: row[k] for k in ("object", "trial", "protocol")}
    try:
        obj, structures = detect(mesh, params, int(row["seed"]))
    except GbhInputError as e:
        return key | {"class": "no structure", "ground_mm": None, "note": str(e)}
    result = search_reach(obj, structures, params)
    ground = result.best_ground_distance
    return key | {"class": result.classification, "structures": len(structures),
                  "ground_mm": None if ground != ground else round(1e3 * ground, 2)}


def bounds(rows: list[dict], searched: list[dict]) -> dict[str, tuple[int, int, int]]:
    """Per protocol of ``rows`` (one method's rows on objects with parts): (successes, trials,
    trials proved out of reach in ``searched``, :func:`true_reach`'s results)."""
    out = {}
    for protocol in dict.fromkeys(r.get("protocol") or "stable" for r in rows):
        mine = [r for r in rows if (r.get("protocol") or "stable") == protocol]
        out[protocol] = (sum(1 for r in mine if r["success"]), len(mine),
                         sum(1 for s in searched if s["protocol"] == protocol
                             and s["class"] == "out of reach"))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path)
    parser.add_argument("--method", default="gbh-10")
    parser.add_argument("--clearance", type=float, default=0.0,
                        help="table clearance (m) a pose must keep (default 0)")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)

    from gbh_drake.experiment.rows import read_jsonl, row_problem

    experiment_path = args.folder / "experiment.yaml"
    rows = [r for r in read_jsonl(args.folder / "trials.jsonl", check=row_problem)
            if r["method"] == args.method and not r["is_control"]]
    if not rows:
        print(f"{args.folder}: no rows of method {args.method!r} on objects with parts",
              file=sys.stderr)
        return 2
    todo = [(str(experiment_path), r, args.clearance) for r in rows if not r["success"]]
    with ProcessPoolExecutor(args.workers) as pool:
        searched = list(pool.map(true_reach, todo))
    for s in searched:
        best = ("no collision-free pose within 3 cm of the table" if s["ground_mm"] is None
                else f"best pose {s['ground_mm']} mm above the table")
        print(f"{s['protocol']:8} {s['object']:32} t{s['trial']}  {s['class']:13} {best}")
    print(f"\n{args.method} in {args.folder}, table clearance {1e3 * args.clearance:g} mm:")
    for protocol, (won, n, out) in bounds(rows, searched).items():
        print(f"  {protocol}: {won}/{n} carried; {out} out of reach of any hook grasp; "
              f"at most {n - out}/{n} = {100.0 * (n - out) / n:.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
