"""Throughput of the experiment: trials per minute with 1 and 2 local workers, and the projected
wall time of the paper's 225-trial table (15 objects x 5 trials x 3 methods; target <= 10 min
on 2 cores).

Runs a few whole trials (the full horizon, replays of failures kept, as ``gbh experiment``
does) of scenarios/experiment.yaml's paper methods, once with each number of
workers, into temporary folders. The wall time includes starting the workers (spawned
interpreters importing pydrake, open3d...), as a real run's does.

Usage: ``.venv/bin/python bench/bench_experiment.py [--objects mug_classic watering_can]
[--methods gbh-10 gbh-1 antipodal] [--workers 1 2]``. Timings grow with the load of a shared
machine: the load average is printed beside them.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

from gbh_drake import SCENARIOS_DIR
from gbh_drake.experiment.config import load_experiment
from gbh_drake.experiment.rows import RowStore
from gbh_drake.experiment.runner import run_experiment

#: The paper's table: 15 objects x 5 trials x 3 methods.
TABLE_TRIALS = 15 * 5 * 3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiment", default=str(SCENARIOS_DIR / "experiment.yaml"))
    parser.add_argument("--objects", nargs="+", default=["mug_classic", "watering_can"])
    parser.add_argument("--methods", nargs="+", default=["gbh-10", "gbh-1", "antipodal"])
    parser.add_argument("--workers", nargs="+", type=int, default=[1, 2])
    args = parser.parse_args()

    experiment = load_experiment(args.experiment, overrides=(
        f"objects: [{', '.join(args.objects)}]\ntrials: 1\n"))
    experiment.methods = [experiment.method(name) for name in args.methods]
    n = len(args.objects) * len(args.methods)
    print(f"{n} trials ({', '.join(args.objects)} x {', '.join(args.methods)}), full horizon; "
          f"{os.cpu_count()} CPUs")
    rates = {}
    for workers in args.workers:
        with tempfile.TemporaryDirectory() as tmp:
            load = os.getloadavg()[0]
            start = time.perf_counter()
            run_experiment(experiment, out=Path(tmp), workers=workers, progress=False,
                           log=lambda _: None)
            wall = time.perf_counter() - start
            rows = RowStore(Path(tmp)).load()
        per_trial = [r["stage_times"]["total"] for r in rows]
        outcomes = ", ".join(sorted(f"{r['method']}:{r['outcome']}" for r in rows))
        rates[workers] = 60.0 * n / wall
        print(f"{workers} worker{'s' if workers > 1 else ' '}: {n} trials in {wall:6.1f} s "
              f"= {rates[workers]:5.2f} trials/min (per trial in its worker: median "
              f"{statistics.median(per_trial):.1f} s, max {max(per_trial):.1f} s; load "
              f"average {load:.1f} at the start)")
        print(f"           outcomes: {outcomes}")
    best = max(rates, key=rates.get)
    minutes = TABLE_TRIALS / rates[best]
    print(f"projected wall time of the {TABLE_TRIALS}-trial table with {best} worker"
          f"{'s' if best > 1 else ''}: {minutes:.1f} min (target <= 10 min on 2 cores)")


if __name__ == "__main__":
    main()
