"""Speed of a whole trial: the carry's real-time factor, planning time per grasp, process time.

Prints, for the default scenario (mug_classic, 10 views):

* the real-time factor (simulated / wall seconds, and simulated / CPU seconds of this process)
  of every phase of the pick, the carry's among them (issue 23: >= 2.5 over the whole trial
  and the carry, >= 2 for the dense mesh), for the object set's mug
  and for a dense user mesh (the mug subdivided to ~100k triangles, imported from a file: its
  contact geometry is simplified, its look is not);
* the planning time per grasp from the measured state (median and worst over the grasps tried
  in the default trial and in a few random-pose trials of other objects; target median <= 0.5 s);
* the wall time and peak memory of ``gbh run scenarios/default.yaml`` as a whole process
  (imports, scan, GbH, planning, simulation, replay; issue 23: <= 6 s and <= 600 MB peak
  RSS), over ``--runs`` runs;
* with ``--time-steps 0.004``, the default trial's phases at other plant time steps.

Usage: ``.venv/bin/python bench/bench_trial.py [--runs 2] [--objects kettle teapot]
[--time-steps 0.004]``.
Timings grow with the load of a shared machine: the load average is printed beside them.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from pydrake.systems.analysis import ApplySimulatorConfig, Simulator
from pydrake.systems.framework import EventStatus

from gbh_drake import REPO_ROOT, SCENARIOS_DIR
from gbh_drake.objects import make_object
from gbh_drake.scenario import load_scenario
from gbh_drake.scenario.schema import RandomRestingPose
from gbh_drake.trial import build_trial


def phase_rates(overrides: str = "") -> tuple[list[tuple[str, float, float, float]], list[float]]:
    """(phase, simulated s, wall s, CPU s) of each phase of the default trial (with
    ``overrides``), and the planning seconds of each grasp tried."""
    scenario = load_scenario(SCENARIOS_DIR / "default.yaml", overrides=overrides)
    trial = build_trial(scenario)
    simulator = Simulator(trial.diagram)
    ApplySimulatorConfig(scenario.simulator_config, simulator)
    port = trial.pick.GetOutputPort("status")
    marks = []

    def monitor(context):
        status = port.Eval(trial.pick.GetMyContextFromRoot(context))
        if not marks or marks[-1][0] != status.mode.value:
            marks.append((status.mode.value, context.get_time(), time.perf_counter(),
                          time.process_time()))
        if status.finished and context.get_time() > status.phase_start[status.mode.value] + 0.5:
            return EventStatus.ReachedTermination(trial.pick, "done")
        return EventStatus.Succeeded()

    simulator.set_monitor(monitor)
    simulator.Initialize()
    simulator.AdvanceTo(scenario.max_time)
    context = simulator.get_context()
    marks.append(("end", context.get_time(), time.perf_counter(), time.process_time()))
    rows = [(m, t1 - t0, w1 - w0, c1 - c0)
            for (m, t0, w0, c0), (_, t1, w1, c1) in zip(marks[:-1], marks[1:], strict=True)]
    status = port.Eval(trial.pick.GetMyContextFromRoot(context))
    return rows, list(status.grasp_seconds)


def planning_times(objects: list[str], seeds: int) -> list[float]:
    """Planning seconds of every grasp tried, for ``objects`` at ``seeds`` random poses (the
    trials stop once planned)."""
    from gbh_drake.trial import simulate_trial

    times = []
    for name in objects:
        for seed in range(seeds):
            scenario = load_scenario(SCENARIOS_DIR / "default.yaml",
                                     overrides=f"seed: {seed}\nobject: {{name: {name}}}")
            scenario.object.random_pose = RandomRestingPose()
            trial = build_trial(scenario)
            simulator, _ = simulate_trial(trial, max_time=scenario.settle_time + 0.05)
            status = trial.pick.GetOutputPort("status").Eval(
                trial.pick.GetMyContextFromRoot(simulator.get_context()))
            times += status.grasp_seconds
    return times


def whole_process(runs: int, out: Path, overrides: list[str] = ()) -> list[tuple[float, float]]:
    """(wall s, peak RSS GB) of ``gbh run scenarios/default.yaml`` (with ``overrides``, each
    given as ``--set``) in fresh processes (the peak of that process alone, from ``wait4``)."""
    results = []
    gbh = Path(sys.executable).parent / "gbh"
    for i in range(runs):
        start = time.perf_counter()
        sets = [a for o in overrides for a in ("--set", o)]
        child = subprocess.Popen([str(gbh), "run", str(SCENARIOS_DIR / "default.yaml"), *sets,
                                  "--set", f"output_dir: {out / str(i)}"], stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL, cwd=REPO_ROOT)
        _, status, usage = os.wait4(child.pid, 0)
        wall = time.perf_counter() - start
        child.returncode = os.waitstatus_to_exitcode(status)
        if child.returncode != 0:
            raise SystemExit(f"gbh run exited {child.returncode}")
        results.append((wall, usage.ru_maxrss / 1e6))
    return results


def _print_phases(title: str, rows) -> None:
    print(f"{title}, per phase:  simulated s, wall s, real-time factor (wall / CPU)")
    for name, sim, wall, cpu in rows:
        print(f"  {name:10s} {sim:5.2f} {wall:6.2f}   {sim / max(wall, 1e-9):5.2f} / "
              f"{sim / max(cpu, 1e-9):5.2f}")
    sim = sum(r[1] for r in rows)
    wall = sum(r[2] for r in rows)
    print(f"  {'total':10s} {sim:5.2f} {wall:6.2f}   {sim / wall:5.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--objects", nargs="*", default=["kettle", "teapot", "pot"])
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--out", default="/tmp/gbh_bench_trial")
    parser.add_argument("--process-only", action="store_true",
                        help="only the whole-process runs of gbh run")
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="YAML", help="YAML over the default scenario for the whole-process "
                                             "runs, e.g. 'pick: {set_down: false}' (repeatable)")
    parser.add_argument("--time-steps", nargs="*", type=float, default=[],
                        help="also the default trial at these plant time steps (s), e.g. 0.004")
    args = parser.parse_args()
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    print(f"load average {os.getloadavg()[0]:.1f}, {os.cpu_count()} cores")

    # First, while this process is small: a child's peak RSS counts the pages it shares with
    # this process between fork and exec, so measured later it would report this one's size.
    results = whole_process(args.runs, Path(args.out), args.overrides)
    sets = "".join(f" --set {o!r}" for o in args.overrides)
    print(f"gbh run scenarios/default.yaml{sets} as a process: " + ", ".join(
        f"{w:.1f} s" for w, _ in results) + f"; peak RSS {max(r for _, r in results):.2f} GB")
    if args.process_only:
        return
    rows, default_grasps = phase_rates()
    _print_phases("default trial (mug_classic)", rows)
    for step in args.time_steps:
        _print_phases(f"default trial at a {step * 1e3:g} ms step",
                      phase_rates(f"plant_config: {{time_step: {step}}}")[0])
    dense = Path(args.out) / "dense_mug.obj"
    dense.parent.mkdir(parents=True, exist_ok=True)
    mesh = make_object("mug_classic").mesh.subdivide().subdivide().subdivide()
    mesh.export(dense)
    dense_rows, _ = phase_rates(f"object: {{name: '', mesh: {dense}, density: 800}}")
    _print_phases(f"dense user mesh ({len(mesh.faces)} triangles)", dense_rows)

    times = default_grasps + planning_times(args.objects, args.seeds)
    print(f"planning per grasp from the measured state: median {statistics.median(times):.3f} s, "
          f"worst {max(times):.3f} s over {len(times)} grasps (default + "
          f"{', '.join(args.objects)} x {args.seeds} random poses)")
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
