"""Runs ``gbh`` (its real ``main``) and prints ``MARK <moment>`` on stderr when a moment of the
run begins, so that a test can send a signal at that moment. Not a test module.

    python signal_driver.py <moment> <gbh arguments...>

Moments: ``import`` (pydrake starts being imported), ``simulate`` (the simulation starts),
``scan`` (the depth scan starts), ``plan`` (the first inverse kinematics of the planner),
``commit`` (the outputs are about to be renamed into place; waits there 2 s, or until the file
named by the environment variable ``GBH_DRIVER_GO`` exists).
"""

import importlib.abc
import os
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
    if moment == "import":
        sys.meta_path.insert(0, _ImportWatcher())
    from gbh_drake.cli import main as gbh_main

    if moment != "import":
        import gbh_drake.outputs
        import gbh_drake.planning.model
        import gbh_drake.run
        import gbh_drake.systems.scanner
        import gbh_drake.trial

        targets = {"simulate": (gbh_drake.trial, "simulate_trial", 0.0),
                   "scan": (gbh_drake.systems.scanner, "scan_object", 0.0),
                   "plan": (gbh_drake.planning.model.PlanningModel, "ik", 0.0),
                   "commit": (gbh_drake.outputs.RunOutputs, "commit", 2.0)}
        owner, name, wait = targets[moment]
        _wrap(owner, name, moment, wait)
    return gbh_main(argv)


if __name__ == "__main__":
    sys.exit(main())
