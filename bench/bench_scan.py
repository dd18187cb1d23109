"""Time and peak memory of a scan (render + fusion) of the default mug, 1 and 10 views.

Each case runs in a fresh Python process so that memory figures do not mix, once with Open3D's
default OpenMP threads and once with ``OMP_NUM_THREADS=1`` (faster on a busy machine, where
OpenMP threads spin against other processes):
``.venv/bin/python bench/bench_scan.py`` prints a table; ``--case NAME`` runs one case and prints
its figures as JSON. Figures: ``cold`` is the first scan in the process (renderer warm-up
included), ``warm`` the median and ``best`` the least of the next repeats (the machine may be
shared: the best is the least disturbed); ``maxrss`` the process's peak resident memory
(getrusage, includes Drake, Open3D and the station), ``scan_rss`` how much the scans raised it
above the level reached before scanning, ``py_peak`` the peak of Python/numpy allocations during
one scan (tracemalloc; Open3D's C++ buffers are not seen by it).
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the package, run from anywhere

CASES = {
    "1 view": {"num_views": 1},
    "10 views": {"num_views": 10},
    "10 views + noise": {"num_views": 10, "noise": True},
}
REPEATS = 5
TIMES = ("cold_s", "warm_s", "best_s", "render_s", "fuse_s")


def _maxrss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB


def run_case(name: str) -> dict:
    """Builds the station (not timed), then scans REPEATS + 1 times."""
    import numpy as np
    from pydrake.systems.framework import DiagramBuilder

    from gbh_drake.perception.config import ScanConfig
    from gbh_drake.perception.scan import scan_object
    from gbh_drake.scenario import Scenario
    from gbh_drake.station import add_station

    builder = DiagramBuilder()
    # The renderer reads the object's mesh from model_dir while the bench runs.
    model_dir = tempfile.TemporaryDirectory(prefix="bench_scan_")
    station = add_station(builder, Scenario(), model_dir=model_dir.name)
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    query_object = station.scene_graph.get_query_output_port().Eval(
        station.scene_graph.GetMyContextFromRoot(context))
    height = station.object_asset.mesh.bounds[1, 2]
    p_WT = station.X_WO_initial @ np.array([0.0, 0.0, 0.5 * height])
    config = ScanConfig(**CASES[name])

    rss_before = _maxrss_mb()
    times, results = [], []
    for _ in range(REPEATS + 1):
        start = time.perf_counter()
        results.append(scan_object(query_object, config, p_WT))
        times.append(time.perf_counter() - start)
    rss_after = _maxrss_mb()
    tracemalloc.start()
    scan_object(query_object, config, p_WT)
    py_peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    last = results[-1]
    return {
        "case": name, "object": station.object_asset.name, "cold_s": times[0],
        "warm_s": statistics.median(times[1:]), "best_s": min(times[1:]),
        "render_s": statistics.median(r.timing["render"] for r in results[1:]),
        "fuse_s": statistics.median(r.timing["fuse"] for r in results[1:]),
        "maxrss_mb": rss_after, "scan_rss_mb": rss_after - rss_before, "py_peak_mb": py_peak,
        "faces": len(last.mesh_W.faces), "points": len(last.p_WQ), "empty": last.empty,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", choices=list(CASES), help="run one case, print JSON")
    args = parser.parse_args()
    if args.case:
        print(json.dumps(run_case(args.case)))
        return
    print(f"{os.cpu_count()} cpus, load average {os.getloadavg()[0]:.2f}; "
          f"{REPEATS} warm repeats; 640x480, voxel 2.5 mm")
    header = (f"{'case':22} {'cold s':>7} {'warm s':>7} {'best s':>7} {'render':>7} {'fuse':>7} "
              f"{'maxrss MB':>9} {'scan +MB':>8} {'py MB':>6} {'faces':>6}")
    print(header)
    for name, omp in [(name, omp) for omp in ("", "1") for name in CASES]:
        env = {k: v for k, v in os.environ.items() if k != "OMP_NUM_THREADS"}  # OpenMP default
        if omp:
            env["OMP_NUM_THREADS"] = omp
        out = subprocess.run([sys.executable, __file__, "--case", name], capture_output=True,
                             text=True, check=True, env=env)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        label = name + (" omp=1" if omp else "")
        print(f"{label:22} " + " ".join(f"{r[k]:7.3f}" for k in TIMES)
              + f" {r['maxrss_mb']:9.0f} {r['scan_rss_mb']:8.0f} {r['py_peak_mb']:6.0f}"
              f" {r['faces']:6d}")
    print(f"object: {r['object']}; load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
