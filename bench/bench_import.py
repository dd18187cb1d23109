"""Time what a user waits for before anything runs: ``import gbh_drake.systems`` and a validation
error from ``gbh run`` on a scenario with a misspelt key (issue 23's targets: <= 1 s, <= 1.5 s),
and the task list ``gbh experiment`` builds before its first trial (scenarios/experiment.yaml).

Run:  .venv/bin/python bench/bench_import.py [--repeat 3]

Each case runs in a fresh process (``--repeat`` times); prints the best and the median wall
seconds and the largest peak RSS (MB, from the child's rusage), with the load average.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

GBH = Path(sys.executable).with_name("gbh")


def timed(argv: list[str]) -> tuple[float, float]:
    """Wall seconds and peak RSS (MB) of one run of ``argv`` (a fresh process each)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t = time.perf_counter()
    subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    wall = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return wall, max(peak, before) / 1024.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        bad = Path(tmp) / "bad.yaml"
        bad.write_text("seeed: 3\n")
        cases = {"import gbh_drake.systems": [sys.executable, "-c", "import gbh_drake.systems"],
                 "gbh run (misspelt key)": [str(GBH), "run", str(bad)]}
        for name, argv in cases.items():
            runs = [timed(argv) for _ in range(args.repeat)]
            walls = [w for w, _ in runs]
            print(f"{name:<26} best {min(walls):.2f} s, median {statistics.median(walls):.2f} s, "
                  f"peak RSS <= {max(m for _, m in runs):.0f} MB")
    task_list()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")


def task_list() -> None:
    """Seconds to build the shipped experiment's task list (one YAML dump per method, object
    and protocol, the seed set for the other trials), and what dumping every trial would take."""
    import copy

    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.experiment.config import (
        _set_trial,
        experiment_objects,
        load_experiment,
        make_tasks,
        method_scenarios,
        trial_scenario_yaml,
    )

    experiment = load_experiment(SCENARIOS_DIR / "experiment.yaml")
    scenarios = method_scenarios(experiment)
    start = time.perf_counter()
    tasks = make_tasks(experiment, scenarios=scenarios)
    objects = {o.name: o for o in experiment_objects(experiment)}
    built = time.perf_counter() - start
    sample = tasks[:: max(1, len(tasks) // 50)]
    start = time.perf_counter()
    for task in sample:
        scenario = copy.deepcopy(scenarios[task.method])
        _set_trial(scenario, experiment, objects[task.object], task.trial, task.protocol)
        trial_scenario_yaml(scenario)
    each = (time.perf_counter() - start) / len(sample)
    print(f"task list of scenarios/experiment.yaml: {len(tasks)} tasks in {built:.1f} s "
          f"(a full dump per trial would take about {each * len(tasks):.0f} s)")


if __name__ == "__main__":
    main()
