"""Which resting poses of the object set offer no hook grasp, and would setting the object down
in another resting pose (core/regrasp.py) give one? On the true meshes, default GbhParams.

Run:  .venv/bin/python tools/regrasp_potential.py [--objects NAME ...] [--min-probability 0.02]

For each object of the catalog with a hangable part and each of its stable poses (probability
at least ``--min-probability``; yaw 0, on z = 0), runs the pipeline; where it ranks no hook
grasp, lists the resting poses :func:`gbh_drake.core.regrasp.choose_regrasp_pose` offers
(turn, probability, its family's probability, grasps, best score). Prints one line per pose
and the totals, weighted by the poses' probabilities (the share of random drops).
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from gbh_drake.core.params import GbhParams  # noqa: E402
from gbh_drake.core.pipeline import plan_grasps  # noqa: E402
from gbh_drake.core.regrasp import choose_regrasp_pose  # noqa: E402
from gbh_drake.objects import lift_to_table, make_object, stable_poses  # noqa: E402
from gbh_drake.objects.catalog import list_objects  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", nargs="*", default=None)
    parser.add_argument("--min-probability", type=float, default=0.02)
    args = parser.parse_args()
    params = GbhParams()
    names = args.objects or [n for n in list_objects() if make_object(n).hangable_parts]
    stuck = helped = 0.0
    print(f"{'object':<18} {'pose':>4} {'prob':>5} {'grasps':>6}  regrasp poses (turn deg, prob, "
          "family prob, grasps, score)")
    for name in names:
        mesh = make_object(name).mesh
        for k, pose in enumerate(stable_poses(mesh).poses):
            if pose.probability < args.min_probability:
                continue
            X = np.eye(4)
            X[:3, :3] = pose.R
            mesh_W = mesh.copy().apply_transform(lift_to_table(mesh, X))
            ranked = len(plan_grasps(mesh_W, params).ranked)
            line = ""
            if not ranked:
                stuck += pose.probability / len(names)
                rest = [(p.R, p.probability) for p in stable_poses(mesh_W).poses]
                choices = choose_regrasp_pose(mesh_W, rest, params, [0.5, 0.0],
                                              min_probability=args.min_probability)
                helped += pose.probability / len(names) if choices else 0.0
                line = "; ".join(f"{c.turn_deg:.0f}, {c.probability:.3f}, "
                                 f"{c.family_probability:.2f}, {c.grasps}, {c.best_score:.2f}"
                                 for c in choices[:3]) or "none"
            print(f"{name:<18} {k:>4} {pose.probability:5.2f} {ranked:>6}  {line}")
    print(f"share of random drops without a hook grasp: {stuck:.1%}; of which a regrasp pose "
          f"offers one: {helped:.1%} ({len(names)} objects, equal weight)")


if __name__ == "__main__":
    main()
