"""Cost per scan of the shape completion and of the view choice (issue 39: target <= 0.5 s each).

For each object (default: a mug, the pot, the teapot, the kettle, the headphones, a box), one
view of it beside the robot (``perception.scenes.build_scene``, yaw 30 deg) is scanned once (not timed); then

* ``completion``: ``perception.completion.complete_scan`` on that one-view scan;
* ``view choice``: ``perception.view_choice.choose_view`` on the scan's first look (the coarse
  model, its completion, its candidate holes, the scores of the 11 candidate views), by the
  ``holes`` score and by the ``material`` score;

each run ``REPEATS`` times after one warm-up. Printed per object: the median and best wall
seconds, the median process CPU seconds (what it costs whatever the machine's load) and the
machine's load average, so figures of a busy hour can be told apart::

    .venv/bin/python bench/bench_oneview.py
    .venv/bin/python bench/bench_oneview.py --objects mug_classic,teapot --repeats 9
"""

import argparse
import os
import statistics
import tempfile
import time
from dataclasses import replace

REPEATS = 5
OBJECTS = ("mug_classic", "pot", "teapot", "kettle", "headphones", "box")
P_WT = (0.55, 0.0, 0.06)


def _timed(fn, repeats: int) -> dict:
    fn()  # warm-up
    wall, cpu = [], []
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    return {"median": statistics.median(wall), "best": min(wall),
            "cpu": statistics.median(cpu)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--objects", default=",".join(OBJECTS))
    parser.add_argument("--repeats", type=int, default=REPEATS)
    args = parser.parse_args()

    from gbh_drake.core.params import CompletionParams
    from gbh_drake.perception.completion import complete_scan
    from gbh_drake.perception.config import ScanConfig
    from gbh_drake.perception.scan import first_look, scan_object
    from gbh_drake.perception.scenes import build_scene
    from gbh_drake.perception.view_choice import choose_view
    from gbh_drake.perception.viewpoints import fit_view_distance

    config = ScanConfig(num_views=1)
    print(f"load average {os.getloadavg()[0]:.1f}; {args.repeats} repeats after a warm-up; "
          "seconds per scan (wall median / best, CPU median)")
    print("| object | completion | view choice (holes) | view choice (material) | scan triangles "
          "| completed triangles |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="bench_oneview_") as model_dir:
        for name in args.objects.split(","):
            scene = build_scene(name, model_dir, yaw_deg=30.0)
            scan = scan_object(scene.query_object, config, P_WT)
            look = first_look(scene.query_object, config, P_WT)
            distance, _ = fit_view_distance(look.radius, config)
            done = complete_scan(scan, CompletionParams())
            completion = _timed(lambda s=scan: complete_scan(s, CompletionParams()),
                                args.repeats)
            by_score = [replace(config, view_choice=how) for how in ("holes", "material")]
            choices = [_timed(lambda lk=look, d=distance, c=c: choose_view(lk, c, lk.centre_W, d),
                              args.repeats) for c in by_score]
            added = len(done.mesh_W.faces) - len(scan.mesh_W.faces)
            print(f"| {name} | {completion['median']:.3f} / {completion['best']:.3f}, CPU "
                  f"{completion['cpu']:.3f} | "
                  + " | ".join(f"{c['median']:.3f} / {c['best']:.3f}, CPU {c['cpu']:.3f}"
                               for c in choices)
                  + f" | {len(scan.mesh_W.faces)} | {added} |", flush=True)
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
