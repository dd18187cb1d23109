"""What the two passes for objects lying flat cost per scan: the pinch's side pass and the tall
scoops (both beyond the paper, tiers of ``gbh_plus``).

Run:  .venv/bin/python bench/bench_flat.py [--repeats 5]

* **the side pass** (``antipodal.side_pass``, core/antipodal.py): on shapes where the sampler's
  first pass keeps nothing, so the second runs (those of tests/core/test_antipodal.py: a bar
  10 mm thick and a torus ring 13 mm high lying flat; 5000 surface samples, as a mesh input
  gets): the sampler's whole call and the side pass's own share (``timings["side_pass"]``),
  with the pass off and on;
* **the tall scoops** (``scoop.tall``, core/scoop.py): the scoop planning of thick rings lying
  flat (tori with 26 and 40 mm tubes, the object set's tape roll), with the tall scoops off and
  on (the same rules' counts; on adds the hand's own count and a second ranking).

Prints the best and the median wall seconds over the repeats (the object prepared once, not
timed) and the load average: the machine is shared (2 cores).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import trimesh

from gbh_drake.core.antipodal import plan_antipodal_grasps
from gbh_drake.core.params import AntipodalParams, GbhParams, ScoopParams
from gbh_drake.core.pipeline import detect
from gbh_drake.core.scoop import plan_scoops
from gbh_drake.objects import make_object


def on_table(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    mesh = mesh.copy()
    mesh.apply_translation([0.55 - mesh.bounds.mean(axis=0)[0], -mesh.bounds.mean(axis=0)[1],
                            -mesh.bounds[0, 2]])
    return mesh


def timed(call, repeats: int) -> tuple[float, float, object]:
    """Best and median wall seconds of ``call()`` over ``repeats`` runs, and its last result."""
    seconds, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = call()
        seconds.append(time.perf_counter() - start)
    return min(seconds), statistics.median(seconds), result


def side_pass(repeats: int) -> None:
    shapes = {"bar 10 mm": trimesh.creation.box(extents=(0.024, 0.12, 0.010)),
              "ring 13 mm": trimesh.creation.torus(0.016, 0.0065)}
    for name, mesh in shapes.items():
        obj, _ = detect(on_table(mesh), GbhParams(n_points=5000), 0)
        line = [f"side pass  {name:12s}"]
        for on in (False, True):
            params = AntipodalParams(side_pass=on)
            best, median, result = timed(
                lambda p=params, o=obj: plan_antipodal_grasps(o, p, 0), repeats)
            share = result.timings.get("side_pass", 0.0)
            line.append(f"{'on' if on else 'off'}: {len(result.ranked)} grasps, {best:.3f} / "
                        f"{median:.3f} s (the pass {share:.3f} s)")
        print("  ".join(line), flush=True)


def tall_scoops(repeats: int) -> None:
    shapes = {"torus 26 mm": trimesh.creation.torus(major_radius=0.027, minor_radius=0.013),
              "torus 40 mm": trimesh.creation.torus(major_radius=0.04, minor_radius=0.02),
              "tape roll": make_object("tape_roll").mesh}
    for name, mesh in shapes.items():
        obj, structures = detect(on_table(mesh), GbhParams(), 0)
        line = [f"tall scoop {name:12s}"]
        for on in (False, True):
            scoop = ScoopParams(tall=on)
            best, median, result = timed(
                lambda s=scoop, o=obj, h=structures: plan_scoops(o, h, GbhParams(), s), repeats)
            line.append(f"{'on' if on else 'off'}: {len(result.ranked)} scoops, "
                        f"{len(result.ranked_tall)} tall, {best:.3f} / {median:.3f} s")
        print("  ".join(line), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} (2 cores); best / median wall seconds")
    side_pass(args.repeats)
    tall_scoops(args.repeats)


if __name__ == "__main__":
    main()
