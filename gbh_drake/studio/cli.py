"""``gbh studio [SCENARIO]``: the interactive Meshcat page (:mod:`gbh_drake.studio.controls`).

The argument parser (:func:`add_subcommand`) and the command (:func:`run_command`); the work is
:class:`~gbh_drake.studio.session.Session`'s (the trial's systems) and
:class:`~gbh_drake.studio.controls.Studio`'s (the page).
"""

from __future__ import annotations

import argparse

DESCRIPTION = """\
An interactive Meshcat page over one trial of the scenario (the same systems as gbh run): choose
the object (the scenario's, the built-in set, the objects of --objects manifests, --mesh files),
its pose (x, y, yaw, a stable resting orientation by index or -1: drawn from the seed), the
number of views, the grasp method, GbH's preset and the seed; then press Reset (place it and let
it settle), Scan (the cameras and the fused scan; Free space: what they saw free round it),
Detect (hanging structures, what each collision rule removed, the ranked grasps), move the rank
slider (one grasp at a time, open and closed, its score's terms, whether the planner would
execute it, the refused candidates nearest to it with their rule) and Execute (the pick of that
grasp from the scan, live; the verdict in the page). The scenario each placement runs is printed
as gbh run --set text. docs/studio.md."""

EPILOG = """\
examples:
  gbh studio                                      # the default scenario's mug
  gbh studio --objects scenarios/object_sets/own.yaml --mesh my_cup.obj --port 7001
The page is served until Ctrl-C (SIGINT) or SIGTERM (exit 0); an unusable scenario, manifest or
mesh given here exits 2 (one line naming the file and the field); one chosen in the page is said
in the page."""


def add_subcommand(sub, scenario_arg) -> None:
    """Adds ``gbh studio`` to the ``gbh`` parser's subcommands; ``scenario_arg(parser)`` adds
    the scenario and ``--set`` arguments (``gbh run``'s)."""
    p = sub.add_parser("studio", help="an interactive Meshcat page: choose an object and its "
                                      "pose, scan, detect, step through the grasps, execute one",
                       description=DESCRIPTION, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    scenario_arg(p)
    p.add_argument("--objects", dest="sets", action="append", default=[], metavar="SET.yaml",
                   help="also offer the objects of this object set's manifest (may be repeated)")
    p.add_argument("--mesh", dest="meshes", action="append", default=[], metavar="FILE",
                   help="also offer this mesh file (metres, z up; may be repeated)")
    p.add_argument("--port", type=int, default=None,
                   help="the Meshcat server's port (default: the first free from 7000)")


def run_command(args, parser) -> int:
    """Runs ``gbh studio`` with parsed ``args`` until Ctrl-C or SIGTERM (then 0)."""
    from gbh_drake import interrupts
    from gbh_drake.scenario import load_scenario
    from gbh_drake.studio.choices import object_choices
    from gbh_drake.studio.controls import Studio
    from gbh_drake.studio.session import Session
    from gbh_drake.viz.meshcat_server import local_meshcat

    if args.port is not None and not 0 < args.port < 65536:
        parser.error(f"--port {args.port}: a port is 1-65535")
    base = load_scenario(args.scenario, overrides=args.overrides)
    if base.simulator_config.target_realtime_rate == 0:
        base.simulator_config.target_realtime_rate = 1.0  # watchable, as gbh run --meshcat
    objects = object_choices(base, args.sets, args.meshes)
    session = Session(base, objects)
    for index, choice in enumerate(objects):  # a mesh file that cannot be used: exit 2 now
        if choice.config.mesh:
            session.asset(index)
    meshcat = session.meshcat = local_meshcat(args.port)
    studio = Studio(session, meshcat)
    print(f"gbh studio: {meshcat.web_url()}  (open it in a browser; Ctrl-C ends it)", flush=True)
    try:
        studio.reset()  # the scenario's object, placed and settled
        studio.run()
    except KeyboardInterrupt:  # SIGINT, SIGTERM, SIGHUP: the way out of the page
        interrupts.forget()
        print(flush=True)
    return 0
