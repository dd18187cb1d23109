"""The ``gbh`` command line.

    gbh run [SCENARIO.yaml] [--meshcat [--port N] [--keep-open S]] [--set YAML] [--save-views]
                                                       simulate a scenario (default: the packaged
                                                       scenarios/default.yaml)
    gbh grasps INPUT [--table-z Z] [--html FILE] ...   ranked grasps for a mesh, point cloud or
                                                       depth images you have (in the robot's base
                                                       frame)
    gbh studio [SCENARIO.yaml] [--objects SET.yaml] [--mesh FILE] [--port N]
                                                       an interactive Meshcat page: choose an
                                                       object and its pose, scan, detect, step
                                                       through the grasps, execute one
    gbh diagram [SCENARIO.yaml] [--out DIR]            write the station's and the trial's diagrams
                                                       (default output/diagrams/)
    gbh objects list [--set SET.yaml] [--csv|--json]   an object set: sizes, masses, hangable parts
    gbh objects fetch [--set SET.yaml]                 download the sets' third-party meshes (PyPI)
    gbh objects build [--out DIR]                      write every object's Drake model (models/objects/)
    gbh experiment EXPERIMENT.yaml [--workers N] [--ray ADDRESS]   objects x trials x methods (Table 1)
    gbh report DIR                                     rebuild an experiment's tables and plot

``gbh --verbose ...`` also prints Drake's INFO messages (kept out by default).

Exit codes: 0 done; 2 bad input (a scenario, mesh or output folder that cannot be used: one line
``gbh: <what>: <file>: <field> (line N): <problem>`` on stderr, see docs/errors.md); 130 after
Ctrl-C (SIGINT), 143 after SIGTERM (one line; unfinished outputs are discarded); 1 and a
traceback for anything else: that is a bug. Heavy modules are imported inside the commands, so
an interrupt during start-up is handled like any other.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import json
import logging
import os
import sys
from pathlib import Path

from gbh_drake import SCENARIOS_DIR, __version__, interrupts
from gbh_drake.experiment import cli as experiment_cli
from gbh_drake.scan_grasps import cli as grasps_cli
from gbh_drake.studio import cli as studio_cli

#: What ``gbh run`` and ``gbh diagram`` read without a file (the checkout's or the installed
#: package's); relative paths in it resolve against its own folder, as in any scenario file.
DEFAULT_SCENARIO = SCENARIOS_DIR / "default.yaml"
#: Where ``gbh diagram`` writes, under the current folder (the tracked ``diagrams/`` of the
#: checkout are redrawn with ``gbh diagram --out diagrams``).
DEFAULT_DIAGRAMS = Path("output") / "diagrams"


def _scenario_arg(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scenario", nargs="?", default=str(DEFAULT_SCENARIO),
                        help="scenario YAML file (default: the packaged scenarios/default.yaml)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="YAML",
                        help="YAML text applied over the file, e.g. --set 'seed: 3' (may be "
                             "repeated: applied in order). A relative path in it (output_dir, "
                             "object.mesh) is relative to the current folder; one in the file, "
                             "to the file's folder")


#: Known input errors: (module, class, what the one line says). A module not imported yet
#: raised none of its errors (its import is not paid for to find out).
INPUT_ERRORS = (
    ("gbh_drake.outputs", "OutputError", "cannot write outputs"),
    ("gbh_drake.scenario", "ScenarioError", "invalid scenario"),
    ("gbh_drake.objects.mesh_io", "MeshImportError", "invalid mesh"),
    ("gbh_drake.objects.sets", "ObjectSetError", "invalid object set"),
    ("gbh_drake.scan_grasps.errors", "GraspsInputError", "invalid input"),
)


def _input_error(error: BaseException) -> str | None:
    """The one-line message of a known input error (:data:`INPUT_ERRORS`), None for anything
    else (a bug)."""
    for module, name, what in INPUT_ERRORS:
        loaded = sys.modules.get(module)
        if loaded is not None and isinstance(error, getattr(loaded, name)):
            return f"{what}: {error}"
    return None


def _handles_errors(command):
    """Wraps ``main``: known input errors -> one line and exit 2; SIGINT, SIGTERM, SIGHUP -> one
    line and 130, 143, 129 (:mod:`gbh_drake.interrupts`: whatever became of the exception, and
    any error raised while a signal was pending is the signal's doing); a closed stdout (``|
    head``) -> quiet exit 141; stdout on a full device (``> /dev/full``) -> one line, exit 2;
    anything else propagates (a bug: traceback, exit 1)."""

    @functools.wraps(command)
    def wrapper(argv: list[str] | None = None) -> int:
        with interrupts.handled(), _guarded_stdout() as stdout:
            try:
                code = command(argv)
                sys.stdout.flush()  # a full device fails here, not in Python's exit
            except SystemExit as e:  # argparse's --help, --version and usage errors
                if stdout.failed is None:
                    raise
                _say(f"cannot write outputs: {stdout.failed}")  # (argparse swallowed it)
                return 2 if e.code in (0, None) else e.code
            except KeyboardInterrupt:
                return _interrupted()
            except BrokenPipeError:  # the reader of our stdout went away
                _quiet_stdout()
                return 141
            except Exception as e:
                if interrupts.received() is not None:  # e.g. an import the signal broke
                    return _interrupted()
                message = _input_error(e)
                if message is None:
                    raise
                _say(message)
                return 2
            if interrupts.received() is not None:  # the signal's exception was swallowed
                return _interrupted()
            if stdout.failed is not None:  # a write error some library swallowed
                _say(f"cannot write outputs: {stdout.failed}")
                return 2
            return code

    return wrapper


def _interrupted() -> int:
    """Says which signal ended the command (unless the command said it: ``gbh experiment``);
    returns its exit code."""
    if not interrupts.said():
        _say(f"{interrupts.describe()}; unfinished outputs were discarded")
    return interrupts.exit_code()


class _Stdout:
    """sys.stdout, whose write errors (a full device: ``gbh run > /dev/full``) are an
    :class:`~gbh_drake.outputs.OutputError` naming stdout; a closed pipe stays a
    ``BrokenPipeError``."""

    def __init__(self, stream):
        self._stream = stream
        self.failed = None
        """The :class:`~gbh_drake.outputs.OutputError` of the first write that failed."""

    def __getattr__(self, name):
        return getattr(self._stream, name)

    def _guard(self, call, *args):
        try:
            return call(*args)
        except BrokenPipeError:
            raise
        except OSError as e:
            from gbh_drake.outputs import OutputError, reason

            _quiet_stdout()
            self.failed = self.failed or OutputError("stdout", f"could not write it ({reason(e)})")
            raise self.failed from None

    def write(self, text):
        return self._guard(self._stream.write, text)

    def writelines(self, lines):
        return self._guard(self._stream.writelines, lines)

    def flush(self):
        return self._guard(self._stream.flush)


@contextlib.contextmanager
def _guarded_stdout():
    real = sys.stdout
    sys.stdout = guarded = _Stdout(real)
    try:
        yield guarded
    finally:
        if sys.stdout.__class__ is _Stdout:
            sys.stdout = real


def _quiet_stdout() -> None:
    """Points stdout at /dev/null (what is left in its buffer goes there: Python's flush at
    exit must not fail again)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    os.close(devnull)


def _say(message: str) -> None:
    print(f"gbh: {' '.join(message.split())}", file=sys.stderr, flush=True)


@_handles_errors
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="gbh", description="Grasping by Hanging in Drake")
    parser.add_argument("--version", action="version", version=f"gbh_drake {__version__}")
    parser.add_argument("--verbose", action="store_true",
                        help="also print Drake's INFO messages (Meshcat's URL, context "
                             "allocation)")
    sub = parser.add_subparsers(dest="command", required=True)

    p_run = sub.add_parser("run", help="simulate a scenario and write its Meshcat replay")
    _scenario_arg(p_run)
    p_run.add_argument("--meshcat", action="store_true",
                       help="serve the live Meshcat view (its URL is printed), then the replay "
                            "there, and keep it open until Enter or Ctrl-C (SIGINT) or SIGTERM "
                            "(in any process: without a terminal, stdin's end waits for the "
                            "signal)")
    p_run.add_argument("--keep-open", type=float, default=None, metavar="SECONDS",
                       help="with --meshcat: keep the view open this many seconds after the "
                            "run instead (Ctrl-C ends it sooner)")
    p_run.add_argument("--port", type=int, default=None,
                       help="the live Meshcat server's port (default: the first free from 7000)")
    p_run.add_argument("--save-views", action="store_true",
                       help="also write the scan's depth images (16-bit PNG) and views.yaml "
                            "into <output>/views/ (gbh grasps reads them back)")
    grasps_cli.add_subcommand(sub)  # gbh grasps
    studio_cli.add_subcommand(sub, _scenario_arg)  # gbh studio

    p_diag = sub.add_parser("diagram", help="write the station's and the trial's Graphviz diagrams")
    _scenario_arg(p_diag)
    p_diag.add_argument("--out", default=str(DEFAULT_DIAGRAMS),
                        help=f"output folder (default {DEFAULT_DIAGRAMS})")

    p_obj = sub.add_parser("objects", help="object sets: list them, fetch their meshes, build "
                                           "the built-in set's models")
    p_obj.add_argument("action", choices=["list", "fetch", "build"])
    p_obj.add_argument("--set", dest="sets", action="append", default=[], metavar="SET.yaml",
                       help="an object set's manifest (default: list the built-in set; fetch "
                            "the shipped sets' meshes); may be repeated")
    fmt = p_obj.add_mutually_exclusive_group()
    fmt.add_argument("--csv", action="store_true", help="list as CSV")
    fmt.add_argument("--json", action="store_true", help="list as JSON")
    p_obj.add_argument("--out", default=None, help="output folder of build (default models/objects)")
    experiment_cli.add_subcommands(sub)  # gbh experiment, gbh report

    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    if args.command == "run" and args.port is not None and not 0 < args.port < 65536:
        parser.error(f"--port {args.port}: a port is 1-65535")
    if args.command == "run" and args.keep_open is not None and (
            not args.meshcat or not 0 <= args.keep_open < float("inf")):
        parser.error(f"--keep-open {args.keep_open}: seconds >= 0, with --meshcat")
    if args.command == "objects":
        return _objects(args)
    if args.command in experiment_cli.COMMANDS:
        return experiment_cli.run_command(args)
    if args.command == "grasps":
        quiet_drake(verbose=args.verbose)
        return grasps_cli.run_command(args, parser)
    if args.command == "studio":
        quiet_drake(verbose=args.verbose)
        return studio_cli.run_command(args, parser)
    from gbh_drake.objects.mesh_io import quiet_mesh_warnings
    from gbh_drake.scenario import load_scenario

    # A mesh's warnings (size, mass, repairs) are said once, in the run's summary (or in the
    # refusal of an absurd size), not also as log lines while the scenario is checked.
    with quiet_mesh_warnings():
        scenario = load_scenario(args.scenario, overrides=args.overrides)
        quiet_drake(verbose=args.verbose)
        if args.command == "run":
            return _run(scenario, live=args.meshcat, port=args.port, save_views=args.save_views,
                        keep_open=args.keep_open)
        return _diagram(scenario, Path(args.out))


def quiet_drake(*, verbose: bool = False) -> None:
    """Keeps Drake's INFO messages ("Meshcat listening ...", "Allocating contexts ...") out of
    the output unless ``verbose``: its warnings and errors still show. (pydrake's import sets
    the level of its ``drake`` logger, so this imports it first.)"""
    import pydrake.common  # noqa: F401

    logging.getLogger("drake").setLevel(logging.INFO if verbose else logging.WARNING)


def _run(scenario, *, live: bool, port: int | None = None, save_views: bool = False,
         keep_open: float | None = None) -> int:
    from gbh_drake.run import run
    from gbh_drake.viz.meshcat_server import keep_open as keep_serving
    from gbh_drake.viz.meshcat_server import local_meshcat

    # The replay is drawn in Meshcat after the run; its server's URL is said only for a live
    # view (the trial is then drawn as it runs, and the replay replaces it).
    meshcat = local_meshcat(port if live else None)
    if live:
        print(f"Meshcat: {meshcat.web_url()}  (open it now to watch live)", flush=True)
        if scenario.simulator_config.target_realtime_rate == 0:
            scenario.simulator_config.target_realtime_rate = 1.0  # watchable speed
    summary = run(scenario, meshcat=meshcat, save_views=save_views, live=live)
    print(summary.to_text(), flush=True)
    if live:  # the run is complete: leaving the view is not an interruption
        keep_serving(meshcat.web_url(), keep_open)
    # A trial whose physics failed before its verdict has no outcome: say so by the exit code.
    return 1 if summary.record.outcome == "error" else 0


def _objects(args) -> int:
    from gbh_drake.modeling.object_set import (
        OBJECT_MODELS_DIR,
        build_object_models,
        describe_lines,
        describe_set,
    )

    if args.action == "fetch":
        from gbh_drake.objects.fetch_sets import main as fetch

        return fetch([str(p) for p in args.sets or _shipped_sets()])
    if args.action == "list":
        from gbh_drake.objects.mesh_io import quiet_mesh_warnings

        with quiet_mesh_warnings():  # each object's warnings are in its row, not also logged
            rows = [row for path in args.sets or [None] for row in describe_set(path)]
        if args.json:
            print(json.dumps(rows, indent=1))
        elif args.csv:
            import csv

            writer = csv.DictWriter(sys.stdout, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows({k: "; ".join(map(str, v)) if isinstance(v, list) else v
                              for k, v in r.items()} for r in rows)
        else:
            print("\n".join(describe_lines(rows)))
        for row in rows:  # listed, and said as the input errors they are
            if row["error"]:
                _say(f"invalid object set: {row['error']}")
        return 2 if any(row["error"] for row in rows) else 0
    out = args.out
    from gbh_drake.outputs import replace_contents

    folder = Path(out) if out else OBJECT_MODELS_DIR
    # Built in a staging folder, then each object's folder replaces the old one: an interrupted
    # or failed build leaves the previous models whole.
    for model in replace_contents(folder, build_object_models):
        sdf = Path(model.sdf)  # <staging>/<object>/<object>.sdf, now in <folder>/<object>/
        print(f"wrote {folder.resolve() / sdf.parent.name / sdf.name} ({model.mass * 1000:.0f} g)")
    return 0


def _shipped_sets() -> list[Path]:
    """The object sets shipped with gbh_drake (scenarios/object_sets/)."""
    from gbh_drake import SCENARIOS_DIR

    return sorted((SCENARIOS_DIR / "object_sets").glob("*.yaml"))


def _diagram(scenario, out: Path) -> int:
    from gbh_drake.diagrams import write_diagram
    from gbh_drake.outputs import OutputError, prepare_folder
    from gbh_drake.trial import build_trial

    out = prepare_folder(out, min_free=2**20)
    trial = build_trial(scenario)
    try:
        written = [*write_diagram(trial.station, out, "station", max_depth=1),
                   *write_diagram(trial.diagram, out, "trial", max_depth=1)]
    except OSError as e:
        raise OutputError(e.filename or out, f"could not write it ({e.strerror or e})") from None
    for path in written:
        print(f"wrote {path}")
    if not any(p.suffix == ".svg" for p in written):
        print("Graphviz's dot is not installed: only the .dot files were written (install "
              "graphviz, e.g. apt-get install graphviz, or render them with any Graphviz)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
