"""Where each trial's object comes to rest at several plant time steps (docs/time_step.md).

    python tools/settle_convergence.py [--experiment scenarios/experiment.yaml]
        [--protocol stable] [--steps 0.001 0.002 0.004] [--settle-time 1.0]
        [--out settle_stable.jsonl] [--objects mug_classic ...]

For every (object, trial) of the experiment's protocol, the trial's scenario (``gbh-10``'s: the
method does not matter before the pick) is run with ``task: settle`` for ``--settle-time``
simulated seconds at each time step, and the object's pose X_WO at the end is kept. The first
step is the reference: for each other step, the distance (mm) and angle (deg) between the two
rest poses. Rows are appended to ``--out`` as they come (a run can be resumed by deleting
nothing and passing the remaining ``--objects``); the summary is printed at the end.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from gbh_drake import SCENARIOS_DIR


def rest_pose(scenario, time_step: float, settle_time: float) -> tuple[np.ndarray, float]:
    """(4x4 X_WO at the end of the settle, wall s) of ``scenario`` at ``time_step`` (s)."""
    from gbh_drake.trial import build_trial, simulate_trial

    scenario.task = "settle"
    scenario.settle_time = settle_time
    scenario.plant_config.time_step = time_step
    trial = build_trial(scenario)
    start = time.perf_counter()
    simulator, _ = simulate_trial(trial)
    plant = trial.station.plant
    body = plant.GetBodyByName(trial.station.object_name)
    X_WO = plant.EvalBodyPoseInWorld(plant.GetMyContextFromRoot(simulator.get_context()), body)
    return X_WO.GetAsMatrix4(), time.perf_counter() - start


def apart(X_a: np.ndarray, X_b: np.ndarray) -> tuple[float, float]:
    """(mm, deg) between two poses."""
    R = X_a[:3, :3].T @ X_b[:3, :3]
    angle = np.degrees(np.arccos(np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0)))
    return float(np.linalg.norm(X_a[:3, 3] - X_b[:3, 3]) * 1000.0), float(angle)


def summary(rows: list[dict], steps: list[float]) -> str:
    """Markdown: per step against the first, the median and 90th percentile distance and how
    many rest poses are more than 1 mm or 1 deg away, then those trials."""
    ref = str(steps[0])
    lines = ["| step | against | median | 90th percentile | > 1 mm or > 1 deg | wall s per settle |",
             "|---|---|---|---|---|---|"]
    far = {}
    for step in steps[1:]:
        d = np.array([r["apart"][str(step)] for r in rows])
        wall = np.mean([r["wall"][str(step)] for r in rows])
        out = (d[:, 0] > 1.0) | (d[:, 1] > 1.0)
        lines.append(f"| {step * 1e3:g} ms | {float(ref) * 1e3:g} ms | {np.median(d[:, 0]):.3f} mm, "
                     f"{np.median(d[:, 1]):.3f} deg | {np.percentile(d[:, 0], 90):.2f} mm, "
                     f"{np.percentile(d[:, 1], 90):.2f} deg | {int(out.sum())} of {len(rows)} | "
                     f"{wall:.2f} |")
        for r, o in zip(rows, out, strict=True):
            if o:
                far.setdefault((r["object"], r["trial"]), {})[step] = r["apart"][str(step)]
    lines.append(f"| {float(ref) * 1e3:g} ms | | | | | "
                 f"{np.mean([r['wall'][ref] for r in rows]):.2f} |")
    if far:
        lines += ["", "| object | trial | " + " | ".join(f"{s * 1e3:g} ms" for s in steps[1:]) + " |",
                  "|---|---|" + "---|" * (len(steps) - 1)]
        by_key = {(r["object"], r["trial"]): r for r in rows}
        for key in far:
            cells = [f"{by_key[key]['apart'][str(s)][0]:.2f} mm, "
                     f"{by_key[key]['apart'][str(s)][1]:.2f} deg" for s in steps[1:]]
            lines.append(f"| {key[0]} | {key[1]} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiment", default=str(SCENARIOS_DIR / "experiment.yaml"))
    parser.add_argument("--protocol", default="stable")
    parser.add_argument("--steps", nargs="+", type=float, default=[0.001, 0.002, 0.004])
    parser.add_argument("--settle-time", type=float, default=1.0)
    parser.add_argument("--objects", nargs="*", default=None)
    parser.add_argument("--out", default=None, help="rows (JSON lines), appended")
    args = parser.parse_args()

    from gbh_drake.experiment.config import load_experiment, trial_scenario

    experiment = load_experiment(args.experiment)
    out = Path(args.out or f"settle_{args.protocol}.jsonl")
    rows = [json.loads(line) for line in out.read_text().splitlines()] if out.exists() else []
    done = {(r["object"], r["trial"]) for r in rows}
    with out.open("a") as f:
        for name in args.objects or experiment.objects:
            for t in range(experiment.trials):
                if (name, t) in done:
                    continue
                poses, wall = {}, {}
                for step in args.steps:
                    scenario = trial_scenario(experiment, name, experiment.methods[0].name, t,
                                              args.protocol)
                    poses[step], wall[str(step)] = rest_pose(scenario, step, args.settle_time)
                row = {"object": name, "trial": t, "protocol": args.protocol, "wall": wall,
                       "X_WO": {str(s): poses[s].tolist() for s in args.steps},
                       "apart": {str(s): apart(poses[args.steps[0]], poses[s])
                                 for s in args.steps[1:]}}
                print(name, t, {k: [round(x, 3) for x in v] for k, v in row["apart"].items()},
                      flush=True)
                f.write(json.dumps(row) + "\n")
                f.flush()
                rows.append(row)
    print(summary(rows, args.steps))


if __name__ == "__main__":
    main()
