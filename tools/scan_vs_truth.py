"""How each trial's scan compares with the true object: does anything else get into it?

    python tools/scan_vs_truth.py [--experiment scenarios/experiment.yaml] [--method gbh-10]
        [--protocol stable] [--max-time 1.5] [--out scan_vs_truth.jsonl] [--objects tote_bag ...]

For every (object, trial) of the experiment's protocol, the trial of ``--method`` runs until its
scan is taken (at most ``--max-time`` simulated seconds: the scan waits for the object to be
still), and its mesh (W) is compared with the object's true mesh at its pose then: how far the
scan's top lies above the true top, and the share of the scan's vertices more than 1 cm from
the true surface. A scan whose top is well above the object's has fused something else into it
(the robot's hand hanging above a tall object at its home pose). Rows are appended to ``--out``;
the trials whose scan top is more than 5 mm above the truth are printed at the end.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from gbh_drake import SCENARIOS_DIR

#: A scan top this far (m) above the true top means something else was fused into the scan.
ABOVE = 0.005
#: Vertices this far (m) from the true surface count as off it.
OFF = 0.01


def compare(scenario, max_time: float) -> dict:
    """The scan of ``scenario``'s trial against its true object (see the module docstring)."""
    import trimesh

    from gbh_drake.trial import build_trial, simulate_trial

    trial = build_trial(scenario)
    simulator, _ = simulate_trial(trial, max_time=max_time)
    context = simulator.get_context()
    scan = trial.scanner.get_output_port(0).Eval(trial.scanner.GetMyContextFromRoot(context))
    plant = trial.station.plant
    X_WO = plant.EvalBodyPoseInWorld(plant.GetMyContextFromRoot(context),
                                     plant.GetBodyByName(trial.station.object_name))
    truth = trial.station.asset.mesh.copy()
    truth.apply_transform(X_WO.GetAsMatrix4())
    row = {"scanned": not scan.empty, "message": scan.message}
    if scan.empty or len(scan.mesh_W.vertices) == 0:
        return row
    v = np.asarray(scan.mesh_W.vertices)
    v = v[:: max(1, len(v) // 4000)]
    _, d, _ = trimesh.proximity.closest_point(truth, v)
    return {**row, "scan_top": float(scan.mesh_W.vertices[:, 2].max()),
            "true_top": float(truth.vertices[:, 2].max()), "off_share": float(np.mean(d > OFF)),
            "off_max_mm": float(d.max() * 1000.0), "radius": float(scan.object_radius),
            "view_distance": float(scan.view_distance)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiment", default=str(SCENARIOS_DIR / "experiment.yaml"))
    parser.add_argument("--method", default="gbh-10")
    parser.add_argument("--protocol", default="stable")
    parser.add_argument("--max-time", type=float, default=1.5)
    parser.add_argument("--objects", nargs="*", default=None)
    parser.add_argument("--out", default="scan_vs_truth.jsonl")
    args = parser.parse_args()

    from gbh_drake.experiment.config import load_experiment, trial_scenario

    experiment = load_experiment(args.experiment)
    rows = []
    with Path(args.out).open("a") as f:
        for name in args.objects or experiment.objects:
            for t in range(experiment.trials):
                scenario = trial_scenario(experiment, name, args.method, t, args.protocol)
                row = {"object": name, "trial": t, "method": args.method,
                       "protocol": args.protocol, **compare(scenario, args.max_time)}
                f.write(json.dumps(row) + "\n")
                f.flush()
                rows.append(row)
    above = [r for r in rows if r["scanned"] and r["scan_top"] - r["true_top"] > ABOVE]
    print(f"{len(rows)} trials, {sum(not r['scanned'] for r in rows)} not scanned by "
          f"{args.max_time} s, {len(above)} with the scan's top more than {ABOVE * 1000:g} mm "
          "above the object's:")
    for r in above:
        print(f"  {r['object']} t{r['trial']}: scan top {r['scan_top']:.3f} m, true "
              f"{r['true_top']:.3f} m, {100 * r['off_share']:.0f} % of its vertices more than "
              f"{OFF * 100:g} cm off the object")


if __name__ == "__main__":
    main()
