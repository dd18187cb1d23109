"""What Meshcat costs a trial: the default trial with and without it, advanced in turns.

An experiment records every trial (any may fail and want its replay), so the visualizers
(``ApplyVisualizationConfig``'s illustration, contact and inertia publishers, recording on) run in
all of them. Two copies of the default trial are built in this process, one with a Meshcat and
one without, then advanced ``--chunk`` simulated seconds at a time in turns (the order
alternating), so that both meet the same load. Prints the wall seconds of each over t = 1 s to the
end and their ratio (with / without: 1 means free).

Usage: ``.venv/bin/python bench/bench_meshcat.py [--chunk 0.25] [--end 11.6]``.
"""

from __future__ import annotations

import argparse
import os
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chunk", type=float, default=0.25)
    parser.add_argument("--end", type=float, default=11.6)
    args = parser.parse_args()

    from pydrake.systems.analysis import ApplySimulatorConfig, Simulator

    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.scenario import load_scenario
    from gbh_drake.trial import build_trial
    from gbh_drake.viz.meshcat_server import local_meshcat

    print(f"load average {os.getloadavg()[0]:.1f}, {os.cpu_count()} cores")
    scenario = load_scenario(SCENARIOS_DIR / "default.yaml")
    meshcat = local_meshcat()
    simulators = {}
    for name, with_meshcat in (("without", None), ("with", meshcat)):
        trial = build_trial(scenario, meshcat=with_meshcat)
        simulator = Simulator(trial.diagram)
        ApplySimulatorConfig(scenario.simulator_config, simulator)
        simulator.Initialize()
        simulator.AdvanceTo(1.0)
        simulators[name] = simulator
    meshcat.StartRecording()
    wall = dict.fromkeys(simulators, 0.0)
    t, turn = 1.0, 0
    while t < args.end:
        t, turn = min(t + args.chunk, args.end), turn + 1
        for name in (list(simulators) if turn % 2 else list(simulators)[::-1]):
            start = time.perf_counter()
            simulators[name].AdvanceTo(t)
            wall[name] += time.perf_counter() - start
    print(f"default trial, t = 1 to {args.end} s: {wall['with']:.2f} s of wall with Meshcat, "
          f"{wall['without']:.2f} s without; ratio {wall['with'] / wall['without']:.3f}")


if __name__ == "__main__":
    main()
