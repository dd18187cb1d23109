"""Time the reach search (gbh_drake.core.reach) on objects of the object set at their stable poses.

Run:  .venv/bin/python bench/bench_reach.py [--objects mug_classic key_ring ...] [--poses 3]

For each object and each of its ``--poses`` most probable stable poses (the mesh on the table
z = 0, as a trial draws it, yaw 0), detects the structures on the true mesh (default GbhParams,
seed 0), runs the pipeline (how many grasps it ranks) and the reach search without a time budget
(as a trial's reach analysis runs it: ``experiment.reach.BUDGET_S``, rows stay deterministic;
``--budget S`` cuts it as ``search_reach``'s default would), and prints one line per case: the
classification, the best table margin (mm), the poses generated and counted and the search's
seconds. Then the median and the max seconds per search, single-threaded
(OMP_NUM_THREADS=1, as a trial worker), with the load average: on a shared machine the figures
grow with it.
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")  # before numpy/open3d: a trial worker's setting

import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import trimesh  # noqa: E402

from gbh_drake.core.params import GbhParams  # noqa: E402
from gbh_drake.core.pipeline import detect, plan_grasps  # noqa: E402
from gbh_drake.core.reach import search_reach  # noqa: E402
from gbh_drake.experiment.reach import BUDGET_S  # noqa: E402
from gbh_drake.objects import lift_to_table, make_object, stable_poses  # noqa: E402

#: Flat objects, mugs (upright and on their handle), a kettle, a basket, a tape roll.
DEFAULT_OBJECTS = ("key_ring", "scissors", "clothes_hanger", "mug_classic", "pybullet_mug",
                   "mug_large", "teacup", "kettle", "basket", "tape_roll")


def posed_mesh(name: str, k: int) -> tuple[trimesh.Trimesh, float] | None:
    """Object ``name``'s mesh at its k-th most probable stable pose on z = 0 (yaw 0), and the
    pose's probability; None when it has fewer poses."""
    mesh = make_object(name).mesh
    poses = stable_poses(mesh).poses
    if k >= len(poses):
        return None
    X = np.eye(4)
    X[:3, :3] = poses[k].R
    X = lift_to_table(mesh, X)
    return mesh.copy().apply_transform(X), poses[k].probability


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", nargs="*", default=list(DEFAULT_OBJECTS))
    parser.add_argument("--poses", type=int, default=3, help="stable poses per object")
    parser.add_argument("--budget", type=float, default=BUDGET_S,
                        help="wall seconds per search (default: none, as a trial)")
    args = parser.parse_args()
    params = GbhParams()
    seconds = []
    print(f"{'object':<16} {'pose':>4} {'prob':>5} {'ranked':>6} {'reach':<13} {'margin mm':>9} "
          f"{'poses':>6} {'counted':>7} {'s':>5}")
    for name in args.objects:
        for k in range(args.poses):
            posed = posed_mesh(name, k)
            if posed is None:
                break
            mesh, probability = posed
            obj, structures = detect(mesh, params, 0)
            ranked = len(plan_grasps(obj, params).ranked)
            t = time.perf_counter()
            r = search_reach(obj, structures, params, budget_s=args.budget)
            seconds.append(time.perf_counter() - t)
            print(f"{name:<16} {k:>4} {probability:5.2f} {ranked:>6} {r.classification:<13} "
                  f"{1e3 * r.best_margin:9.1f} {r.poses:>6} {r.evaluated:>7} {seconds[-1]:5.2f}")
    print(f"{len(seconds)} searches: median {statistics.median(seconds):.2f} s, max "
          f"{max(seconds):.2f} s per search (single-threaded; load average "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores)")


if __name__ == "__main__":
    main()
