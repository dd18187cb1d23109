"""The ``gbh`` command line.

    gbh run [SCENARIO.yaml] [--meshcat] [--set YAML]   simulate a scenario (default: scenarios/default.yaml)
    gbh diagram [SCENARIO.yaml]                        write the station's and the trial's diagrams
    gbh objects list                                   the object set: sizes, masses, hangable parts
    gbh objects build [--out DIR]                      write every object's Drake model (models/objects/)
"""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

from gbh_drake import REPO_ROOT, SCENARIOS_DIR
from gbh_drake.scenario import ScenarioError, load_scenario

DEFAULT_SCENARIO = SCENARIOS_DIR / "default.yaml"


def _scenario_arg(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scenario", nargs="?", default=str(DEFAULT_SCENARIO),
                        help="scenario YAML file (default: scenarios/default.yaml)")
    parser.add_argument("--set", dest="overrides", default="", metavar="YAML",
                        help="YAML text applied over the file, e.g. --set 'seed: 3'")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="gbh", description="Grasping by Hanging in Drake")
    sub = parser.add_subparsers(dest="command", required=True)

    p_run = sub.add_parser("run", help="simulate a scenario and write its Meshcat replay")
    _scenario_arg(p_run)
    p_run.add_argument("--meshcat", action="store_true",
                       help="serve the live Meshcat view and wait for Enter before exiting")

    p_diag = sub.add_parser("diagram", help="write the station's and the trial's Graphviz diagrams")
    _scenario_arg(p_diag)
    p_diag.add_argument("--out", default=str(REPO_ROOT / "diagrams"), help="output folder")

    p_obj = sub.add_parser("objects", help="the object set")
    p_obj.add_argument("action", choices=["list", "build"])
    p_obj.add_argument("--out", default=None, help="output folder of build (default models/objects)")

    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    if args.command == "objects":
        return _objects(args.action, args.out)
    try:
        scenario = load_scenario(args.scenario, overrides=args.overrides)
    except ScenarioError as e:
        print(f"gbh: invalid scenario: {e}", file=sys.stderr)
        return 2
    try:
        if args.command == "run":
            return _run(scenario, live=args.meshcat)
        return _diagram(scenario, Path(args.out))
    except (ValueError, FileNotFoundError) as e:  # bad object files and the like
        print(f"gbh: {e}", file=sys.stderr)
        return 2


def _run(scenario, *, live: bool) -> int:
    from gbh_drake.run import run
    from gbh_drake.viz.meshcat_server import local_meshcat

    meshcat = local_meshcat()
    if live:
        print(f"Meshcat: {meshcat.web_url()}  (open it now to watch live)")
        if scenario.simulator_config.target_realtime_rate == 0:
            scenario.simulator_config.target_realtime_rate = 1.0  # watchable speed
    summary = run(scenario, meshcat=meshcat)
    print(summary.to_text())
    if live and sys.stdin.isatty():
        input("Press Enter to exit (the Meshcat page keeps the recording until then) ")
    return 0


def _objects(action: str, out: str | None) -> int:
    from gbh_drake.modeling.object_set import (
        OBJECT_MODELS_DIR,
        build_object_models,
        describe_object_set,
    )

    if action == "list":
        print("\n".join(describe_object_set()))
        return 0
    for model in build_object_models(Path(out) if out else OBJECT_MODELS_DIR):
        print(f"wrote {model.sdf} ({model.mass * 1000:.0f} g)")
    return 0


def _diagram(scenario, out: Path) -> int:
    from gbh_drake.diagrams import write_diagram
    from gbh_drake.trial import build_trial

    trial = build_trial(scenario)
    written = [*write_diagram(trial.station, out, "station", max_depth=1),
               *write_diagram(trial.diagram, out, "trial", max_depth=1)]
    for path in written:
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
