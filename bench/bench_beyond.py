"""What the scoop and the regrasp (beyond the paper) add to a trial, in seconds.

For each capability, one trial of the experiment's own poses is run twice, by GbH alone and by
the method that adds the capability (same seed, pose and scan):

* the scoop: ``key_ring`` lying flat (protocol ``natural``, trial 0): GbH finds no grasp;
  ``gbh_scoop`` scoops it;
* the regrasp: ``mug_classic`` resting on its side (protocol ``stable``, trial 0): GbH finds no
  grasp; ``gbh_regrasp`` sets it upright, scans it again and hooks it.

Prints each run's outcome, simulated seconds, wall seconds (the whole trial: build, scan, GbH,
planning, simulation) and the differences. Usage:
``.venv/bin/python bench/bench_beyond.py [--runs 1]``. The load average is printed beside them.
"""

from __future__ import annotations

import argparse
import copy
import os
import statistics
import time

from gbh_drake import SCENARIOS_DIR
from gbh_drake.experiment.config import trial_scenario
from gbh_drake.scenario import Scenario
from gbh_drake.trial import record_trial

CASES = (("scoop", "key_ring", "natural", "gbh_scoop"),
         ("regrasp", "mug_classic", "stable", "gbh_regrasp"))


def timed(scenario: Scenario) -> tuple[str, float, float]:
    start = time.perf_counter()
    record = record_trial(scenario).record
    held = f" [{record.held_by}]" if record.held_by else ""
    return f"{record.outcome}{held}", record.sim_time, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=1)
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} (2 cores)")
    for capability, name, protocol, method in CASES:
        base = trial_scenario(SCENARIOS_DIR / "experiment.yaml", name, "gbh-10", 0, protocol)
        rows = {}
        other = copy.deepcopy(base)
        other.grasp_method = method
        for label, scenario in (("gbh", base), (method, other)):
            runs = [timed(scenario) for _ in range(args.runs)]
            rows[label] = (runs[0][0], runs[0][1], statistics.median(r[2] for r in runs))
        (o0, s0, w0), (o1, s1, w1) = rows["gbh"], rows[method]
        print(f"{capability:8s} {name} ({protocol} t0): gbh {o0}, {s0:.1f} s simulated, "
              f"{w0:.1f} s wall; {method} {o1}, {s1:.1f} s simulated, {w1:.1f} s wall; "
              f"adds {s1 - s0:+.1f} s simulated, {w1 - w0:+.1f} s wall")


if __name__ == "__main__":
    main()
