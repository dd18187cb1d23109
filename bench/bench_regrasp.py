"""Time the regrasp's choice of a resting pose (``core.regrasp.choose_regrasp_pose``): one GbH
pipeline run per resting orientation it tries, the facets of a side the object rolls on (a
family) included; the whole list, and the best ``max_poses`` the RegraspPlanner asks for.

Run:  .venv/bin/python bench/bench_regrasp.py [--repeats 3] [--objects tape_roll mug_classic]

Per object, lying in its least probable stable pose the regrasp would start from (the object
set's true mesh: a scan of it has more facets on a rolled side, so more family members): the
stable orientations found, the poses that offer a hook, and the wall time of the choice (best
and median of the repeats) for the whole list and for the planner's ``max_poses`` (planned group
by group, stopping once that many are found), with the pipeline runs each made (the whole list's:
every orientation its family makes probable enough and turned at least ``min_turn_deg``), and the
load average (2 cores shared: the best time is the figure least disturbed by others).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

import gbh_drake.core.regrasp as regrasp_module
from gbh_drake.core.params import GbhParams, RegraspParams
from gbh_drake.core.regrasp import choose_regrasp_pose, resting_motion
from gbh_drake.objects import make_object
from gbh_drake.objects.stability import stable_poses


def lying_mesh(name: str):
    """The object's true mesh turned into its least probable stable pose, on the table (z = 0),
    and its stable orientations there (R, probability)."""
    mesh = make_object(name).mesh.copy()
    rests = stable_poses(mesh).poses
    R = np.asarray(rests[-1].R, dtype=float)
    mesh.apply_transform(resting_motion(mesh, R, (0.55, 0.0), 0.0))
    return mesh, [(p.R, p.probability) for p in stable_poses(mesh).poses]


#: Pipeline runs of the last choice (counted by wrapping the module's plan_grasps).
counted = [0]


def _counting(plan):
    def run(*args, **kwargs):
        counted[0] += 1
        return plan(*args, **kwargs)
    return run


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--objects", nargs="+", default=["tape_roll", "mug_classic", "pot"])
    args = parser.parse_args()
    params, regrasp = GbhParams(), RegraspParams()
    regrasp_module.plan_grasps = _counting(regrasp_module.plan_grasps)
    print(f"load average {os.getloadavg()[0]:.1f}; min_turn_deg {regrasp.min_turn_deg}, "
          f"min_probability {regrasp.min_probability}")
    print("| object | orientations | poses offering a hook | asked | pipeline runs | best s "
          "| median s |")
    print("|---|---|---|---|---|---|---|")
    for name in args.objects:
        mesh, orientations = lying_mesh(name)
        xy = 0.5 * (mesh.bounds[0][:2] + mesh.bounds[1][:2])
        for asked in (None, regrasp.max_poses):
            walls, poses = [], []
            for _ in range(args.repeats):
                counted[0] = 0
                start = time.perf_counter()
                poses = choose_regrasp_pose(mesh, orientations, params, xy,
                                            min_turn_deg=regrasp.min_turn_deg,
                                            min_probability=regrasp.min_probability,
                                            max_poses=asked)
                walls.append(time.perf_counter() - start)
            print(f"| {name} | {len(orientations)} | {len(poses)} "
                  f"| {'all' if asked is None else asked} | {counted[0]} "
                  f"| {min(walls):.2f} | {statistics.median(walls):.2f} |")


if __name__ == "__main__":
    main()
