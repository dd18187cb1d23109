"""Time of RRT-Connect (with shortcutting) and of single collision checks, kettle on the table.

Run:  .venv/bin/python bench/bench_plan.py [--goals 10]

Goals are drawn with a fixed seed among collision-free arm configurations whose straight
joint-space edge from the home configuration collides (so every case needs the planner).
Prints per-plan times (median, worst), waypoints, failures, and the cost of one check.
"""

import argparse
import os
import statistics
import time

import numpy as np

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.objects import make_object
from gbh_drake.planning.model import HandPose, PlanningModel
from gbh_drake.planning.rrt import plan_rrt_connect
from gbh_drake.scenario import Scenario

OPEN = HandPose(HOOK_GRIPPER.q_open)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--goals", type=int, default=10)
    args = parser.parse_args()
    scenario = Scenario()
    kettle = make_object("kettle").mesh.copy()
    kettle.apply_translation([0.45, 0.0, 0.0])
    t = time.perf_counter()
    model = PlanningModel(scenario.directives, obstacles=[kettle])
    build = time.perf_counter() - t
    q0 = np.asarray(scenario.robot.q_home)
    t = time.perf_counter()
    for _ in range(1000):
        model.free(q0, OPEN)
    check_us = (time.perf_counter() - t) * 1e3
    rng = np.random.default_rng(3)
    times, lengths, failures = [], [], 0
    while len(times) + failures < args.goals:
        q1 = rng.uniform(model.arm_lower, model.arm_upper)
        if not model.free(q1, OPEN) or model.edge_free(q0, q1, OPEN):
            continue
        t = time.perf_counter()
        path = plan_rrt_connect(model, q0, q1, OPEN, seed=0)
        if path is None:
            failures += 1
            continue
        times.append(time.perf_counter() - t)
        lengths.append(len(path))
    print(f"{os.cpu_count()} cpus, load average {os.getloadavg()[0]:.2f}")
    print(f"planning model build: {build * 1e3:.0f} ms; one collision check: {check_us:.0f} us")
    if times:
        print(f"RRT-Connect + shortcuts over {len(times)} blocked goals: median "
              f"{statistics.median(times) * 1e3:.0f} ms, worst {max(times) * 1e3:.0f} ms, "
              f"{statistics.median(lengths):.0f} waypoints (median); {failures} not found")
    else:
        print(f"no plan found for {failures} goals")


if __name__ == "__main__":
    main()
