"""Paired A/B of the default trial's simulation between two checkouts, advanced in turns.

On a shared VM the same run is a third faster or slower from one hour to the next; two runs one
after the other compare hours, not versions. Here two processes, one per checkout, build the
default trial (with ``--set`` overrides), then advance it ``--chunk`` simulated seconds at a time,
in turns (the order alternating), so that both meet the same load. Prints each one's real-time
factor (simulated / wall and / CPU seconds) over ``--start`` to ``--end`` and the ratio of their
wall times (B / A: below 1, B is faster).

Usage: ``.venv/bin/python bench/bench_ab.py A_CHECKOUT B_CHECKOUT [--runs 2]`` (a checkout:
a folder holding ``gbh_drake/``, e.g. a ``git worktree`` of another commit).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time


def worker(overrides: list[str]) -> None:
    """Builds the default trial, then advances to each time read from stdin, printing the wall
    and CPU seconds it took."""
    from pydrake.systems.analysis import ApplySimulatorConfig, Simulator

    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.scenario import load_scenario
    from gbh_drake.trial import build_trial

    scenario = load_scenario(SCENARIOS_DIR / "default.yaml", overrides=overrides)
    trial = build_trial(scenario)
    simulator = Simulator(trial.diagram)
    ApplySimulatorConfig(scenario.simulator_config, simulator)
    simulator.Initialize()
    print("ready", flush=True)
    for line in sys.stdin:
        wall, cpu = time.perf_counter(), time.process_time()
        simulator.AdvanceTo(float(line))
        print(time.perf_counter() - wall, time.process_time() - cpu, flush=True)


def _start(checkout: str, overrides: list[str]) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(checkout), OMP_NUM_THREADS="1")
    sets = [a for o in overrides for a in ("--set", o)]
    child = subprocess.Popen([sys.executable, __file__, "--worker", *sets], env=env, text=True,
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL)
    if child.stdout.readline().strip() != "ready":
        raise SystemExit(f"the trial in {checkout} did not build")
    return child


def _advance(child: subprocess.Popen, t: float) -> tuple[float, float]:
    child.stdin.write(f"{t}\n")
    child.stdin.flush()
    wall, cpu = (float(x) for x in child.stdout.readline().split())
    return wall, cpu


def paired_run(a: str, b: str, start: float, end: float, chunk: float,
               overrides: list[str]) -> list[tuple[float, float]]:
    """(wall s, CPU s) of A and B over ``start``..``end``, advanced in turns."""
    children = [_start(a, overrides), _start(b, overrides)]
    for child in children:
        _advance(child, start)
    totals = [[0.0, 0.0], [0.0, 0.0]]
    t, turn = start, 0
    while t < end - 1e-9:
        t = min(t + chunk, end)
        for k in ((0, 1) if turn % 2 == 0 else (1, 0)):
            wall, cpu = _advance(children[k], t)
            totals[k][0] += wall
            totals[k][1] += cpu
        turn += 1
    for child in children:
        child.stdin.close()
        child.wait()
    return [tuple(x) for x in totals]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("a", nargs="?")
    parser.add_argument("b", nargs="?")
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--start", type=float, default=1.0,
                        help="simulated s to reach before timing (default 1: after the scan)")
    parser.add_argument("--end", type=float, default=11.7, help="simulated s (default: the "
                                                                 "default trial's end)")
    parser.add_argument("--chunk", type=float, default=0.25)
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="YAML")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        worker(args.overrides)
        return
    if not (args.a and args.b):
        parser.error("give two checkouts, A and B")
    print(f"load average {os.getloadavg()[0]:.1f}, {os.cpu_count()} cores; A = {args.a}, "
          f"B = {args.b}; simulated {args.start:g} to {args.end:g} s")
    sim = args.end - args.start
    for _ in range(args.runs):
        (wa, ca), (wb, cb) = paired_run(args.a, args.b, args.start, args.end, args.chunk,
                                        args.overrides)
        print(f"A {sim / wa:.2f}x (CPU {sim / ca:.2f}x), B {sim / wb:.2f}x (CPU {sim / cb:.2f}x):"
              f" wall B/A {wb / wa:.3f}")


if __name__ == "__main__":
    main()
