"""The reach analysis of an experiment's no-grasp trials, after the fact, from the sweep's scans.

A run made before the worker attached a ``reach`` field to its rows (docs/experiment's stable
protocol) can still be asked: for every GbH row with outcome ``no_grasp_found``, this takes the
trial's scan from a ``tools/sweep_thresholds.py`` cache (``scans.pkl``: the same seeds and poses,
scanned by the same diagram; a ``gbh+fallback`` row uses its ``gbh-10`` scan, the same 10 views
of the same pose), the object's true mesh at the row's start pose (the robot never touched it),
and runs :func:`gbh_drake.experiment.reach.reach_of_trial`, as the worker does. It prints each
trial's classes and, per method, the counts and the success rate among the trials a loop can
reach (:func:`gbh_drake.experiment.report.by_reach`). Usage::

    python tools/reach_of_rows.py docs/experiment/trials.jsonl /tmp/sweep_fs/scans.pkl \\
        --out /tmp/reach_rows.jsonl
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import sys
from concurrent.futures import ProcessPoolExecutor

os.environ.setdefault("OMP_NUM_THREADS", "1")

#: The scan a method's trial used (its key's method in the sweep's cache).
SCAN_OF = {"gbh-10": "gbh-10", "gbh-1": "gbh-1", "gbh+fallback": "gbh-10"}

_SCANS: dict = {}


def _load(path: str) -> None:
    _SCANS.update(pickle.loads(open(path, "rb").read()))


def _reach(row: dict) -> dict:
    import numpy as np
    import trimesh
    from pydrake.math import RigidTransform, RollPitchYaw

    from gbh_drake.core.pipeline import detect
    from gbh_drake.experiment.reach import reach_of_trial
    from gbh_drake.modeling.object_asset import load_object_asset
    from gbh_drake.scenario.schema import ObjectConfig

    scan = _SCANS[(row["object"], SCAN_OF[row["method"]], row["trial"])]
    params = scan["gbh"]
    mesh = trimesh.Trimesh(scan["vertices"], scan["faces"], process=False)
    obj, structures = detect(mesh, params, scan["seed"], scan.get("free_space"))
    asset = load_object_asset(ObjectConfig(name=row["object"]), ".")
    x, y, z, roll, pitch, yaw = row["pose"]
    X_WO = RigidTransform(RollPitchYaw(roll, pitch, yaw), np.array([x, y, z]))
    true_mesh = asset.mesh.copy().apply_transform(X_WO.GetAsMatrix4())
    reach = reach_of_trial(obj, true_mesh, params, seed=scan["seed"],
                           scan_structures=structures).to_dict()
    return {k: row[k] for k in ("object", "method", "trial")} | {"reach": reach}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("rows")
    parser.add_argument("scans")
    parser.add_argument("--out", required=True)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)

    from gbh_drake.experiment.report import ReportInput, by_reach
    from gbh_drake.experiment.rows import read_jsonl, row_problem

    rows = read_jsonl(args.rows, check=row_problem)  # a damaged line: named with its line
    todo = [r for r in rows if r["outcome"] == "no_grasp_found" and r["method"] in SCAN_OF
            and (r.get("protocol") or "stable") == "stable"]
    with ProcessPoolExecutor(args.workers, initializer=_load, initargs=(args.scans,)) as pool:
        found = {(r["object"], r["method"], r["trial"]): r["reach"]
                 for r in pool.map(_reach, todo)}
    with open(args.out, "w") as f:
        for key, reach in sorted(found.items()):
            f.write(json.dumps({"object": key[0], "method": key[1], "trial": key[2],
                                "reach": reach}) + "\n")
            print(*key, reach["true"], reach["scan"], f"{reach['best_margin_mm']:.1f} mm",
                  f"{reach['seconds']:.1f} s")
    for r in rows:
        r["reach"] = found.get((r["object"], r["method"], r["trial"]))
    methods = list(dict.fromkeys(r["method"] for r in rows))
    data = ReportInput(name="reach", objects=sorted({r["object"] for r in rows}),
                       methods=methods, trials=max(r["trial"] for r in rows) + 1, paper={},
                       rows=rows)
    print("\n".join(by_reach(data)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
