"""Seed an experiment folder with the rows of an earlier run that a change cannot touch, so the
experiment then runs only the others (it resumes: a trial with a row is not run again).

    python tools/keep_rows.py EXPERIMENT.yaml BEFORE/trials.jsonl OUT [--set YAML ...]
        [--keep-source grasps --keep-source scoop_grasps] [--screen SCREEN.jsonl]

A change that adds a tier late in a method's order (the tall scoops of ``gbh_plus``, after its
hooks, scoops and regrasp) changes only the trials that reached that tier: the successes taken
from an earlier tier cannot change. Kept: the successes whose ``grasp_source``, and the source
of every earlier lift that came away empty (``record.attempts``), is one of the
``--keep-source`` values (default: ``grasps``, ``scoop_grasps``: the regrasp's hook is a
``grasps`` success), and the controls on which GbH found no hanging structure (no scoop acts
without one). Everything else is left to run. A kept row keeps its commit (the report
lists each row's) and gets the current task's ``scenario_digest`` (a new field of the scenario
changes every digest, so ``--reuse`` would match none); the EXPERIMENT and ``--set`` overrides
must be those the experiment is then run with. Prints how many rows were kept and how many
trials are left.

``--screen`` (a change of the hangability detector's rules instead of a late tier): kept are
the rows whose trial ``tools/screen_rule.py`` found with the same hanging structures either
way and that took no re-scan (no regrasp, no lift that came away empty: a re-scan meets the
detector again, on a scan the screen never saw).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from gbh_drake.experiment.config import load_experiment, make_tasks
from gbh_drake.experiment.rows import row_key


def unchanged(row: dict, sources: set[str]) -> bool:
    """Whether ``row`` is a trial the late tier cannot change (module docstring)."""
    record = row.get("record") or {}
    if row.get("is_control") and not record.get("n_structures"):
        return True
    earlier = [a.get("source") for a in record.get("attempts") or []]
    return bool(row.get("success")) and record.get("grasp_source") in sources and \
        all(s in sources for s in earlier)


def screened_same(row: dict, screen: dict[tuple, bool]) -> bool:
    """Whether ``row``'s trial had the same hanging structures before and after a detector
    change (``screen``: :func:`gbh_drake.experiment.rows.row_key` to ``same``) and took no
    re-scan."""
    record = row.get("record") or {}
    return bool(screen.get(row_key(row))) and not record.get("regrasps") and \
        not record.get("attempts")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("experiment", type=Path)
    parser.add_argument("before", type=Path, help="the earlier run's trials.jsonl")
    parser.add_argument("out", type=Path, help="the new experiment folder (created)")
    parser.add_argument("--set", action="append", default=[], dest="overrides",
                        help="YAML over the experiment file, as gbh experiment --set")
    parser.add_argument("--keep-source", action="append", dest="sources",
                        help="a grasp_source whose successes are kept (repeatable)")
    parser.add_argument("--screen", type=Path,
                        help="tools/screen_rule.py's rows: keep the trials it found unchanged")
    args = parser.parse_args(argv)
    screen = None
    if args.screen is not None:
        screen = {}
        for line in args.screen.read_text().splitlines():
            r = json.loads(line)
            screen[row_key(r)] = bool(r["same"])
    sources = set(args.sources or ("grasps", "scoop_grasps"))
    tasks = {t.key: t for t in make_tasks(load_experiment(args.experiment,
                                                          overrides=args.overrides))}
    kept = []
    with open(args.before) as f:
        for line in f:
            row = json.loads(line)
            task = tasks.get(row_key(row))
            keep = unchanged(row, sources) if screen is None else screened_same(row, screen)
            if task is not None and keep:
                row["scenario_digest"] = task.digest
                kept.append(row)
    args.out.mkdir(parents=True, exist_ok=True)
    target = args.out / "trials.jsonl"
    if target.exists():
        parser.error(f"{target} exists: seed an empty folder")
    target.write_text("".join(json.dumps(r, sort_keys=True) + "\n" for r in kept))
    print(f"kept {len(kept)} rows; {len(tasks) - len(kept)} of {len(tasks)} trials left to run")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
