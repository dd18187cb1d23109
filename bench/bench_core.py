"""Time each stage of the GbH core on a 10-view-scan-sized mug (~30k triangles).

Run:  .venv/bin/python bench/bench_core.py [--repeats 7]

Prints, per stage, the best and the median wall time over the repeats, and the median CPU time of
this process (all its threads), and the collision stage again without the loop's material rule
(``loop_must_enclose``: what that rule costs). On a shared machine the wall times grow with the load average
(printed too); the best wall time and the CPU time are the figures least disturbed by others.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import statistics

import trimesh

from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.objects import make_object

STAGES = ("sampling", "hangability", "synthesis", "collision", "scoring")


def scan_sized_mug() -> trimesh.Trimesh:
    """The object set's mug_classic (1.6k triangles) subdivided twice: 26k triangles, about what
    a 10-view TSDF scan of a mug gives (23k)."""
    return make_object("mug_classic").mesh.subdivide().subdivide()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    mesh = scan_sized_mug()
    params = GbhParams()
    plan_grasps(mesh, params)  # warm-up: imports, Embree and BLAS initialisation
    runs = [plan_grasps(mesh, params) for _ in range(args.repeats)]
    last = runs[-1]
    print(f"mesh: {len(mesh.faces)} triangles, {params.n_points} points; "
          f"{len(last.structures)} structures, {len(last.candidates)} candidates, "
          f"{len(last.ranked)} ranked; load average {os.getloadavg()[0]:.2f} on "
          f"{os.cpu_count()} cores")
    print(f"{'stage':<12} {'best ms':>8} {'median ms':>10} {'cpu ms':>8}")
    for name in (*STAGES, "total"):
        wall = [_ms(r.timings, name) for r in runs]
        cpu = [_ms(r.cpu_timings, name) for r in runs]
        print(f"{name:<12} {min(wall):8.1f} {statistics.median(wall):10.1f} "
              f"{statistics.median(cpu):8.1f}")
    off = dataclasses.replace(params, loop_must_enclose=False)
    wall = [_ms(plan_grasps(mesh, off).timings, "collision") for _ in range(args.repeats)]
    loops = sum(c.loop_material >= 0 for c in last.candidates)
    print(f"{'collision, no loop rule':<12} {min(wall):8.1f} {statistics.median(wall):10.1f}"
          f"   (with it: {loops} loops checked)")


def _ms(timings: dict[str, float], name: str) -> float:
    """Milliseconds of one stage, or of all stages for ``"total"``."""
    return 1e3 * (sum(timings.values()) if name == "total" else timings[name])


if __name__ == "__main__":
    main()
