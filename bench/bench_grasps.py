"""Time ``gbh grasps`` (issue 38's targets): on a 20k-triangle mesh <= 1.0 s after import, from
10 depth images 640x480 <= 2.5 s, the whole process <= 3.5 s.

Run:  .venv/bin/python bench/bench_grasps.py [--repeat 3]

The inputs are made once (not timed) from the sample views ``tests/scan_grasps/data/mug_views``
(the mug, 10 noisy 640x480 views of a simulated 16-bit sensor): ``views10/``, its 10 views alone
(no first look, no table given: fitted, as a camera's images come), and ``mesh20k.ply``, the
scan they fuse to, decimated to 20,000 triangles. Then, each case in a fresh process:

* ``in process``: the imports ``gbh grasps`` needs (pydrake, Open3D, trimesh, scipy, the
  package), timed, then ``gbh_drake.grasps(input)`` once (``first``: the first call also loads
  what the libraries load on first use, e.g. Embree's ray scene) and ``--repeat`` times more
  (``warm``: best and median); the steps of the first call from ``result.timings``;
* ``process``: ``gbh grasps INPUT --out FILE`` as a command, wall seconds (best, median).

Prints CPU seconds beside the wall seconds (what the work costs whatever else runs) and the load
average: the machine is shared (2 cores); figures move by a third from one hour to the next.
``OMP_NUM_THREADS=1`` (exported before running it) keeps Open3D's TSDF from spinning threads
against other processes, as the experiment's workers and bench_scan.py's second column do.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
SAMPLE = REPO / "tests" / "scan_grasps" / "data" / "mug_views"
TARGETS = {"mesh20k.ply": 1.0, "views10": 2.5}
PROCESS_TARGET = 3.5
IMPORTS = """
import time
t = time.perf_counter()
import pydrake.all, open3d, trimesh, scipy.spatial, scipy.ndimage
import gbh_drake.scan_grasps.api, gbh_drake.perception.scan, gbh_drake.core.pipeline
imports = time.perf_counter() - t
"""


def make_inputs(folder: Path) -> None:
    """``views10/`` and ``mesh20k.ply`` (see the module docstring)."""
    import shutil

    import yaml

    from gbh_drake.core.simplify import simplified
    from gbh_drake.scan_grasps.inputs import load_input
    from gbh_drake.scan_grasps.run_export import scan_ply

    views = folder / "views10"
    views.mkdir()
    data = yaml.safe_load((SAMPLE / "views.yaml").read_text())
    for key in ("first_look", "table", "gbh", "scan", "seed"):
        data.pop(key, None)
    for view in data["views"]:
        shutil.copy(SAMPLE / view["depth"], views / view["depth"])
    (views / "views.yaml").write_text(yaml.safe_dump(data))
    scan = load_input(SAMPLE).scan
    mesh = simplified(scan.mesh_W, 20_000)
    (folder / "mesh20k.ply").write_bytes(scan_ply(mesh, __import__("numpy").eye(4)))
    print(f"inputs: {len(data['views'])} views of {data['intrinsics']['width']}x"
          f"{data['intrinsics']['height']}; mesh of {len(mesh.faces)} triangles")


def in_process(path: Path, repeat: int) -> dict:
    """Runs in a child: imports, then grasps() 1 + repeat times."""
    code = IMPORTS + f"""
import json, gbh_drake
times, cpu, steps = [], [], None
for i in range({repeat} + 1):
    t, c = time.perf_counter(), time.process_time()
    result = gbh_drake.grasps({str(path)!r})
    times.append(time.perf_counter() - t)
    cpu.append(time.process_time() - c)
    steps = steps or result.timings
print(json.dumps({{"imports": imports, "times": times, "cpu": cpu, "steps": steps,
                  "grasps": len(result.grasps), "faces": len(result.scan.mesh_W.faces)}}))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env={**os.environ, "PYTHONPATH": str(REPO)})
    return json.loads(out.stdout.strip().splitlines()[-1])


def process(path: Path, repeat: int, out: Path) -> tuple[list[float], list[float]]:
    """Wall and CPU seconds (user + system, the child's) of ``gbh grasps`` runs."""
    import resource

    walls, cpus = [], []
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "gbh_drake.cli", "grasps", str(path), "--out",
                        str(out)], stdout=subprocess.DEVNULL, check=True,
                       env={**os.environ, "PYTHONPATH": str(REPO)})
        walls.append(time.perf_counter() - t)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    return walls, cpus


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"load average at start {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        make_inputs(folder)
        for name, target in TARGETS.items():
            r = in_process(folder / name, args.repeat)
            first, warm = r["times"][0], r["times"][1:]
            steps = ", ".join(f"{k} {v:.2f}" for k, v in r["steps"].items())
            print(f"{name}: imports {r['imports']:.2f} s; grasps() first {first:.2f} s (CPU "
                  f"{r['cpu'][0]:.2f} s), warm best {min(warm):.2f} s, median "
                  f"{statistics.median(warm):.2f} s (CPU median "
                  f"{statistics.median(r['cpu'][1:]):.2f} s; target <= {target} s after import);"
                  f" {r['grasps']} grasps on {r['faces']} triangles; first call's steps (s): "
                  f"{steps}")
            walls, cpus = process(folder / name, args.repeat, folder / "out.json")
            print(f"{name}: gbh grasps as a process best {min(walls):.2f} s, median "
                  f"{statistics.median(walls):.2f} s, CPU median {statistics.median(cpus):.2f} s "
                  f"(target <= {PROCESS_TARGET} s)")
    print(f"load average at end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
