"""What the scoop, the regrasp and the retry (beyond the paper) add to a trial, in seconds.

For each capability, one trial of the experiment's own poses is run twice, without the
capability and with it (same seed, pose and scan):

* the scoop: ``key_ring`` lying flat (protocol ``natural``, trial 0): GbH finds no grasp;
  ``gbh_scoop`` scoops it;
* the regrasp: ``mug_classic`` resting on its side (protocol ``stable``, trial 0): GbH finds no
  grasp; ``gbh_regrasp`` sets it upright, scans it again and hooks it;
* the retry: ``spray_bottle`` upright (protocol ``natural``, trial 2), by ``gbh_plus`` without a
  retry (``pick.max_retries: 0``: its hook after a regrasp comes away empty) and with its one
  retry (the hand opens, goes home, the bottle is scanned again and the fallback pinches it).

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


def _method(name: str):
    def change(scenario: Scenario) -> str:
        scenario.grasp_method = name
        return name
    return change


def _no_retry(scenario: Scenario) -> str:
    scenario.pick.max_retries = 0
    return f"{scenario.grasp_method} (max_retries 0)"


def _as_is(scenario: Scenario) -> str:
    return scenario.grasp_method


#: (capability, object, protocol, trial, the experiment's method, the change to its scenario
#: without the capability, with it; each returns the run's label)
CASES = (("scoop", "key_ring", "natural", 0, "gbh-10", _as_is, _method("gbh_scoop")),
         ("regrasp", "mug_classic", "stable", 0, "gbh-10", _as_is, _method("gbh_regrasp")),
         ("retry", "spray_bottle", "natural", 2, "gbh+", _no_retry, _as_is))


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
    for capability, name, protocol, trial, method, without, with_it in CASES:
        base = trial_scenario(SCENARIOS_DIR / "experiment.yaml", name, method, trial, protocol)
        rows = []
        for change in (without, with_it):
            scenario = copy.deepcopy(base)
            label = change(scenario)
            runs = [timed(scenario) for _ in range(args.runs)]
            rows.append((label, runs[0][0], runs[0][1], statistics.median(r[2] for r in runs)))
        (l0, o0, s0, w0), (l1, o1, s1, w1) = rows
        print(f"{capability:8s} {name} ({protocol} t{trial}): {l0} {o0}, {s0:.1f} s simulated, "
              f"{w0:.1f} s wall; {l1} {o1}, {s1:.1f} s simulated, {w1:.1f} s wall; "
              f"adds {s1 - s0:+.1f} s simulated, {w1 - w0:+.1f} s wall")


if __name__ == "__main__":
    main()
