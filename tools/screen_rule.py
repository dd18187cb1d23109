"""Which trials of an experiment can a change of the hangability detector's rules touch?

    python tools/screen_rule.py EXPERIMENT.yaml OUT.jsonl --before "{hang_segment_seen: false}"
        [--methods gbh-10 gbh+ ...] [--protocols stable natural] [--objects NAME ...]
        [--set YAML ...]

For every trial of the given methods (default: every method that runs GbH), the trial runs until
its HangabilityDetector has a result (its scan, as the trial takes it), and the detector's rules
are applied to that scan twice: with the trial's own ``gbh`` parameters (the code as it is) and
with ``--before`` (YAML over the ``gbh`` section: the rules as they were). A trial whose
hanging structures are the same either way runs the same until a re-scan, so its earlier row
stands (``tools/keep_rows.py --screen OUT.jsonl`` keeps it when it took no re-scan); the others
must run again. Trials whose scenarios differ only after the detector (the grasp method's later
tiers, the pick, the monitor) share one screen: methods with the same scan and detector (and
robot: the gripper is in the views) are screened once. One row per (object, method, trial,
protocol) is appended to OUT (``same``, the structures' counts before and after); rows already
in OUT are not screened again.
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import functools
import hashlib
import importlib.util
import json
from pathlib import Path

import numpy as np

#: Scenario fields that act only after the hangability detector: trials that differ only in
#: these share the detector's input and output.
AFTER_DETECTION = ("antipodal", "scoop", "regrasp", "pick", "monitor", "visualization")


def share_key(scenario) -> str:
    """The scenario as YAML without :data:`AFTER_DETECTION` (the grasp method's name kept only
    for what it changes before the detector: the completion, the robot's gripper)."""
    from pydrake.common.yaml import yaml_dump_typed

    from gbh_drake.method_spec import method_spec
    from gbh_drake.scenario.schema import Scenario

    scenario = copy.deepcopy(scenario)
    defaults = Scenario()
    for name in AFTER_DETECTION:
        setattr(scenario, name, copy.deepcopy(getattr(defaults, name)))
    scenario.source_path = scenario.output_dir = ""
    spec = method_spec(scenario.grasp_method)
    scenario.grasp_method = "gbh_completed" if spec.name == "gbh_completed" else "gbh"
    return yaml_dump_typed(scenario) + f"\ngripper: {spec.gripper}\n"


def same_structures(a, b) -> bool:
    """Whether two lists of hanging structures are the same (positions, axes, clearances)."""
    return len(a) == len(b) and all(
        np.array_equal(np.asarray(s.c), np.asarray(t.c)) and
        np.array_equal(np.asarray(s.v), np.asarray(t.v)) and s.clearance == t.clearance
        for s, t in zip(a, b, strict=True))


@functools.cache
def _sweep_thresholds():
    """tools/sweep_thresholds.py as a module (its ``scanned_trial``)."""
    spec = importlib.util.spec_from_file_location(
        "sweep_thresholds", Path(__file__).with_name("sweep_thresholds.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def screen(scenario, before: dict) -> dict:
    """The detector's structures on ``scenario``'s scan, now and with ``before`` (a dict of
    GbhParams fields). The trial is simulated until its scan is taken, as the threshold
    sweeps do (``tools/sweep_thresholds.py``)."""
    from gbh_drake.core.pipeline import detect_reported
    from gbh_drake.core.results import GbhInputError
    from gbh_drake.experiment.config import trial_scenario_yaml
    from gbh_drake.systems.hangability_detector import HangabilityDetector

    _, trial, simulator, _ = _sweep_thresholds().scanned_trial(trial_scenario_yaml(scenario),
                                                               scenario.source_path)
    detector = next(s for s in trial.source.systems.values()
                    if isinstance(s, HangabilityDetector))
    context = detector.GetMyContextFromRoot(simulator.get_context())
    scan = detector.get_input_port(0).Eval(context)
    out = {"now": detector.get_output_port(0).Eval(context).structures}
    if getattr(scan, "empty", False):
        return {"same": True, "n_now": 0, "n_before": 0}
    try:
        _, out["before"], _ = detect_reported(scan.mesh_W, dataclasses.replace(
            detector.params, **before), detector.seed, scan.free_space)
    except GbhInputError:
        out["before"] = []
    return {"same": same_structures(out["now"], out["before"]), "n_now": len(out["now"]),
            "n_before": len(out["before"])}


def main(argv: list[str] | None = None) -> int:
    import yaml

    from gbh_drake.experiment.config import load_experiment, trial_scenario
    from gbh_drake.method_spec import method_spec

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiment", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--before", required=True, help="YAML over gbh: the rules as they were")
    parser.add_argument("--methods", nargs="*")
    parser.add_argument("--protocols", nargs="*")
    parser.add_argument("--objects", nargs="*")
    parser.add_argument("--set", action="append", default=[], dest="overrides")
    args = parser.parse_args(argv)
    before = yaml.safe_load(args.before) or {}
    experiment = load_experiment(args.experiment, overrides=args.overrides)
    methods = args.methods or [m.name for m in experiment.methods]
    done: dict[tuple, dict] = {}
    if args.out.exists():
        for line in args.out.read_text().splitlines():
            row = json.loads(line)
            done[(row["object"], row["method"], row["trial"], row["protocol"])] = row
    shared: dict[str, dict] = {r["key"]: r for r in done.values() if "key" in r}
    with args.out.open("a") as f:
        for trial in range(experiment.trials):
            for protocol in args.protocols or experiment.protocols:
                for name in args.objects or experiment.objects:
                    for method in methods:
                        if (name, method, trial, protocol) in done:
                            continue
                        scenario = trial_scenario(experiment, name, method, trial, protocol)
                        if not method_spec(scenario.grasp_method).hooks:
                            continue
                        key = share_key(scenario)
                        digest = hashlib.sha256(key.encode()).hexdigest()
                        result = shared.get(digest) or screen(scenario, before)
                        row = {"object": name, "method": method, "trial": trial,
                               "protocol": protocol, "key": digest,
                               **{k: result[k] for k in ("same", "n_now", "n_before")}}
                        shared[digest] = row
                        f.write(json.dumps(row) + "\n")
                        f.flush()
                        print(name, method, trial, protocol, "same" if row["same"] else
                              f"CHANGED {row['n_before']} -> {row['n_now']}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
