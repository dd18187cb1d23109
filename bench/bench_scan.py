"""Time and peak memory of a scan (first look, render, segmentation, fusion, cap) of the mug
beside the robot, 1 and 10 views; and, with ``--objects``, a scan of every object of the set.

Each case runs in a fresh Python process so that memory figures do not mix, once with Open3D's
default OpenMP threads and once with ``OMP_NUM_THREADS=1`` (faster on a busy machine, where
OpenMP threads spin against other processes):
``.venv/bin/python bench/bench_scan.py`` prints a table; ``--case NAME`` runs one case and prints
its figures as JSON. Figures: ``cold`` is the first scan in the process (renderer warm-up
included), ``warm`` the median and ``best`` the least of the next repeats (the machine may be
shared: the best is the least disturbed), ``cpu`` the median CPU seconds of the process per warm
scan (what the scan costs whatever the load); the stages are medians of the result's ``timing``;
``maxrss`` the process's peak resident memory (getrusage, includes Drake, Open3D and the scene),
``scan_rss`` how much the scans raised it above the level reached before scanning, ``py_peak``
the peak of Python/numpy allocations during one scan (tracemalloc; Open3D's C++ buffers are not
seen by it).

``--objects`` (OMP_NUM_THREADS=1 advised) scans every object of ``list_objects()`` at (0.55, 0, 0)
m, yaw 30 deg, beside the robot, with 10 views aimed from the nominal target (0.55, 0, 0.06), and
prints the scan's time, triangles, warnings, cap and the number of hanging structures the GbH core
finds on it.
"""

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

CASES = {
    "1 view": {"num_views": 1},
    "10 views": {"num_views": 10},
    "10 views + noise": {"num_views": 10, "noise": True},
}
REPEATS = 5
TIMES = ("cold_s", "warm_s", "best_s", "cpu_s")
STAGES = ("first_look", "render", "segment", "fuse", "cap")
#: The nominal scan target (the scenario's default).
P_WT = (0.55, 0.0, 0.06)


def _maxrss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB


def run_case(name: str) -> dict:
    """Builds the scene (not timed), then scans REPEATS + 1 times."""
    from gbh_drake.perception.config import ScanConfig
    from gbh_drake.perception.scan import scan_object
    from gbh_drake.perception.scenes import build_scene

    # The renderer reads the object's mesh from model_dir while the bench runs.
    model_dir = tempfile.TemporaryDirectory(prefix="bench_scan_")
    scene = build_scene("mug_classic", model_dir.name)
    config = ScanConfig(**CASES[name])

    rss_before = _maxrss_mb()
    times, cpu, results = [], [], []
    for _ in range(REPEATS + 1):
        start, start_cpu = time.perf_counter(), time.process_time()
        results.append(scan_object(scene.query_object, config, P_WT))
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    rss_after = _maxrss_mb()
    tracemalloc.start()
    scan_object(scene.query_object, config, P_WT)
    py_peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    last = results[-1]
    stages = {stage: statistics.median(r.timing.get(stage, 0.0) for r in results[1:])
              for stage in STAGES}
    return {
        "case": name, "object": scene.name, "cold_s": times[0],
        "warm_s": statistics.median(times[1:]), "best_s": min(times[1:]),
        "cpu_s": statistics.median(cpu[1:]), **stages,
        "maxrss_mb": rss_after, "scan_rss_mb": rss_after - rss_before, "py_peak_mb": py_peak,
        "faces": len(last.mesh_W.faces), "points": len(last.p_WQ), "empty": last.empty,
    }


def run_objects() -> None:
    """Scans every object of the set and runs the GbH core on each scan."""
    import numpy as np

    from gbh_drake.core.pipeline import plan_grasps
    from gbh_drake.objects import list_objects
    from gbh_drake.perception.config import ScanConfig
    from gbh_drake.perception.scan import scan_object
    from gbh_drake.perception.scenes import build_scene

    print(f"{os.cpu_count()} cpus, load average {os.getloadavg()[0]:.2f}; 10 views, objects at "
          f"(0.55, 0, 0) m, yaw 30 deg, target {list(P_WT)}; times: second scan")
    print(f"{'object':18} {'wall s':>6} {'cpu s':>6} {'faces':>7} {'dist m':>6} "
          f"{'capped/open':>11} {'structures':>10}  warnings")
    config = ScanConfig()
    with tempfile.TemporaryDirectory(prefix="bench_scan_") as model_dir:
        for name in list_objects():
            scene = build_scene(name, Path(model_dir) / name, yaw_deg=30.0)
            scan_object(scene.query_object, config, P_WT)  # warm-up
            start, start_cpu = time.perf_counter(), time.process_time()
            result = scan_object(scene.query_object, config, P_WT)
            wall, cpu = time.perf_counter() - start, time.process_time() - start_cpu
            structures = (len(plan_grasps(result.mesh_W).structures)
                          if len(result.mesh_W.faces) else 0)
            cap = f"{result.cap.capped_regions}/{result.cap.open_holes}"
            print(f"{name:18} {wall:6.2f} {cpu:6.2f} {len(result.mesh_W.faces):7d} "
                  f"{result.view_distance:6.2f} {cap:>11} {structures:10d}  "
                  f"{'; '.join(result.warnings) or result.message or '-'}", flush=True)
            del scene
    print(f"load average after: {os.getloadavg()[0]:.2f}; "
          f"numpy {np.__version__}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", choices=list(CASES), help="run one case, print JSON")
    parser.add_argument("--objects", action="store_true",
                        help="scan every object of the set and count GbH's structures")
    args = parser.parse_args()
    if args.objects:
        run_objects()
        return
    if args.case:
        print(json.dumps(run_case(args.case)))
        return
    print(f"{os.cpu_count()} cpus, load average {os.getloadavg()[0]:.2f}; "
          f"{REPEATS} warm repeats; 640x480, voxel 2.5 mm")
    header = (f"{'case':22} {'cold s':>7} {'warm s':>7} {'best s':>7} {'cpu s':>7} "
              + " ".join(f"{s[:7]:>7}" for s in STAGES)
              + f" {'maxrss MB':>9} {'scan +MB':>8} {'py MB':>6} {'faces':>6}")
    print(header)
    for name, omp in [(name, omp) for omp in ("", "1") for name in CASES]:
        env = {k: v for k, v in os.environ.items() if k != "OMP_NUM_THREADS"}  # OpenMP default
        if omp:
            env["OMP_NUM_THREADS"] = omp
        out = subprocess.run([sys.executable, __file__, "--case", name], capture_output=True,
                             text=True, check=True, env=env)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        label = name + (" omp=1" if omp else "")
        print(f"{label:22} " + " ".join(f"{r[k]:7.3f}" for k in TIMES + STAGES)
              + f" {r['maxrss_mb']:9.0f} {r['scan_rss_mb']:8.0f} {r['py_peak_mb']:6.0f}"
              f" {r['faces']:6d}")
    print(f"object: {r['object']} (beside the robot); load average after: "
          f"{os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
