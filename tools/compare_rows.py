"""Every trial whose result changed between two experiment runs (same seeds, same poses).

    python tools/compare_rows.py BEFORE/trials.jsonl AFTER/trials.jsonl [--out changes.md]
        [--protocol stable] [--pair gbh-10=gbh-10r ...]

A trial is (object, method, trial index) of one protocol (``--protocol``, default ``stable``;
rows without one are ``stable``); its result is the outcome and, for a success, whether a cage
or a pinch held it. Prints, as Markdown, the successes per method before and after, then one
line per changed trial with both results, gained successes first, the rank of the grasp each
run executed, and where it changed:
``upstream`` when the two runs chose different grasps (the settled pose, the scan or GbH
differed), ``physics`` when they executed the same grasp and the simulation of the pick
differed.

``--pair OLD=NEW`` (repeatable) compares method OLD's trials of BEFORE with method NEW's of
AFTER (one file may be both: ``gbh-10`` and ``gbh-10r`` of one run of
``scenarios/experiment_robust.yaml`` are the same trials with the provisional rules off and on,
docs/robustness.md); the method is then shown as ``OLD=NEW``.
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter
from pathlib import Path


def load(path: Path, protocol: str = "stable") -> dict[tuple, dict]:
    """The rows of ``path`` in ``protocol`` by (object, method, trial), read and checked as the
    runner reads them (a damaged line raises FolderError naming the file and line; a last line
    cut short is left out with a warning)."""
    from gbh_drake.experiment.rows import protocol_of, read_jsonl, row_problem

    rows = {}
    for row in read_jsonl(path, check=row_problem, warn=lambda m: print(f"warning: {m}",
                                                                         file=sys.stderr)):
        if protocol_of(row) == protocol:
            rows[(row["object"], row["method"], int(row["trial"]))] = row
    return rows


def result(row: dict) -> str:
    return f"{row['outcome']} [{row['held_by']}]" if row.get("held_by") else row["outcome"]


#: What GbH (or the sampler) made of the scan, from a row's record: a trial whose choice is the
#: same in both runs changed in the physics of the pick; one whose choice differs changed
#: upstream (the settled pose, the scan, the grasps offered).
CHOICE = ("n_structures", "n_candidates", "grasp_kind", "grasp_rank", "grasp_score")


def choice(row: dict) -> tuple:
    record = row.get("record") or {}
    values = tuple(record.get(name) for name in CHOICE)
    return tuple(round(v, 6) if isinstance(v, float) and v == v else v for v in values)


def where(before: dict, after: dict) -> str:
    """``physics`` when both runs executed the same grasp of the same offer, else ``upstream``."""
    executed = all(((row.get("record") or {}).get("grasp_rank", -1) or 0) >= 0
                   for row in (before, after))
    return "physics" if executed and choice(before) == choice(after) else "upstream"


def rank(row: dict) -> str:
    """The rank of the grasp the trial executed last (0: GbH's or the sampler's best), or '-'
    when none was executed. A ranking that changes which grasps follow the best (GbH's
    distinct grasps) can change a trial's verdict only where a rank above 0 was tried."""
    value = (row.get("record") or {}).get("grasp_rank")
    return "-" if value is None or value < 0 else str(value)


def paired(before: dict[tuple, dict], after: dict[tuple, dict], pairs: list[tuple[str, str]]
           ) -> tuple[dict[tuple, dict], dict[tuple, dict]]:
    """``before`` and ``after`` (rows by (object, method, trial)) restricted to the methods of
    ``pairs`` ((old, new): old's rows of ``before``, new's of ``after``), both renamed
    ``old=new`` so that :func:`compare` pairs them."""
    b, a = {}, {}
    for old, new in pairs:
        name = f"{old}={new}"
        b.update({(o, name, t): r for (o, m, t), r in before.items() if m == old})
        a.update({(o, name, t): r for (o, m, t), r in after.items() if m == new})
    return b, a


def compare(before: dict[tuple, dict], after: dict[tuple, dict]) -> list[str]:
    methods = list(dict.fromkeys(k[1] for k in before))
    lines = ["| method | trials | successes before | after | gained | lost | cage/pinch after |",
             "|---|---|---|---|---|---|---|"]
    common = sorted(set(before) & set(after))
    for m in methods:
        keys = [k for k in common if k[1] == m]
        b = sum(bool(before[k]["success"]) for k in keys)
        a = sum(bool(after[k]["success"]) for k in keys)
        gained = sum(bool(after[k]["success"]) and not before[k]["success"] for k in keys)
        lost = sum(bool(before[k]["success"]) and not after[k]["success"] for k in keys)
        held = Counter(after[k].get("held_by") for k in keys if after[k]["success"])
        lines.append(f"| {m} | {len(keys)} | {b} | {a} | {gained} | {lost} | "
                     f"{held.get('cage', 0)}/{held.get('pinch', 0)} |")
    changed = [k for k in common if result(before[k]) != result(after[k])]
    changed.sort(key=lambda k: (not after[k]["success"] or before[k]["success"],
                                bool(after[k]["success"]) or not before[k]["success"], k))
    lines += ["", f"{len(changed)} of {len(common)} trials changed:", "",
              "| object | method | trial | before | after | where | rank | reason after |",
              "|---|---|---|---|---|---|---|---|"]
    for k in changed:
        reason = after[k]["reason"].replace("|", "/")
        lines.append(f"| {k[0]} | {k[1]} | {k[2]} | {result(before[k])} | {result(after[k])} | "
                     f"{where(before[k], after[k])} | {rank(before[k])} > {rank(after[k])} | "
                     f"{reason} |")
    if changed:
        counts = Counter(where(before[k], after[k]) for k in changed)
        lines += ["", f"where: {counts.get('upstream', 0)} changed upstream (the runs chose "
                  f"different grasps: {', '.join(CHOICE)} differ; a different settled pose or "
                  f"scan), {counts.get('physics', 0)} in the physics of the same grasp; "
                  "rank: the executed grasp's rank before > after ('-': none executed)."]
    missing = sorted(set(before) ^ set(after))
    if missing:
        lines += ["", f"{len(missing)} trials are in only one of the runs."]
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--out", type=Path)
    parser.add_argument("--protocol", default="stable")
    parser.add_argument("--pair", action="append", default=[], metavar="OLD=NEW",
                        help="compare method OLD of before with method NEW of after")
    args = parser.parse_args(argv)
    pairs = [tuple(p.split("=", 1)) for p in args.pair]
    if any(len(p) != 2 or not all(p) for p in pairs):
        print("compare_rows: --pair: OLD=NEW, two method names", file=sys.stderr)
        return 2
    from gbh_drake.experiment.rows import FolderError

    try:
        before, after = load(args.before, args.protocol), load(args.after, args.protocol)
    except FolderError as e:
        print(f"compare_rows: {e}", file=sys.stderr)
        return 2
    if pairs:
        before, after = paired(before, after, pairs)
    text = "\n".join(compare(before, after)) + "\n"
    if args.out:
        args.out.write_text(text)
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
