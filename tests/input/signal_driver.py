"""Runs ``gbh`` (its real ``main``) and prints ``MARK <moment>`` on stderr when a moment of the
run begins, so that a test can send a signal at that moment. Not a test module.

    python signal_driver.py <moment> <gbh arguments...>

Moments: ``import`` (pydrake starts being imported), ``simulate`` (the simulation starts),
``scan`` (the depth scan starts), ``plan`` (the first inverse kinematics of the planner),
``replay`` (the replay is about to be written), ``commit`` (the outputs are about to be renamed
into place; waits there 2 s, or until the file named by the environment variable
``GBH_DRIVER_GO`` exists), ``swallow`` (before the simulation, waits 1 s inside a ``try: ...
except BaseException: pass``, as trimesh's import guards do: the interrupt is dropped there),
``row`` (``gbh experiment``: its first row is about to be written; waits there 1 s).
"""

import importlib.abc
import os
import signal
import sys
import time
from pathlib import Path


def mark(moment: str) -> None:
    print(f"MARK {moment}", file=sys.stderr, flush=True)


class _ImportWatcher(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name == "pydrake":
            sys.meta_path.remove(self)
            mark("import")
            time.sleep(0.05)  # the signal lands inside the import
        return None


def _wrap(owner, name, moment, wait=0.0):
    real = getattr(owner, name)
    fired = []

    def wrapper(*args, **kwargs):
        if not fired:
            fired.append(True)
            mark(moment)
            go = os.environ.get("GBH_DRIVER_GO")
            if moment == "swallow":
                try:
                    time.sleep(wait)
                except BaseException:  # noqa: S110  (what a careless library does)
                    pass
                return real(*args, **kwargs)
            if go and wait:
                deadline = time.monotonic() + 120
                while not Path(go).exists() and time.monotonic() < deadline:
                    time.sleep(0.05)
            else:
                time.sleep(wait)
        return real(*args, **kwargs)
    setattr(owner, name, wrapper)


def main() -> int:
    moment, argv = sys.argv[1], sys.argv[2:]
    # As in a terminal, whatever ran the test (a background job ignores SIGINT, nohup SIGHUP).
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
    if moment == "import":
        sys.meta_path.insert(0, _ImportWatcher())
    from gbh_drake.cli import main as gbh_main

    if moment != "import":
        import gbh_drake.experiment.runner
        import gbh_drake.outputs
        import gbh_drake.planning.model
        import gbh_drake.run
        import gbh_drake.systems.scanner
        import gbh_drake.trial

        targets = {"simulate": (gbh_drake.trial, "simulate_trial", 0.0),
                   "swallow": (gbh_drake.trial, "simulate_trial", 1.0),
                   "scan": (gbh_drake.systems.scanner, "scan_object", 0.0),
                   "plan": (gbh_drake.planning.model.PlanningModel, "ik", 0.0),
                   "replay": (gbh_drake.outputs.RunOutputs, "stage", 0.0),
                   "commit": (gbh_drake.outputs.RunOutputs, "commit", 2.0),
                   "row": (gbh_drake.experiment.runner, "_save", 1.0)}
        owner, name, wait = targets[moment]
        _wrap(owner, name, moment, wait)
    return gbh_main(argv)


if __name__ == "__main__":
    sys.exit(main())
