"""Re-simulates committed successes and judges each twice: by the finger rule and by enclosure.

    python tools/rejudge_cage.py ROWS.jsonl EXPERIMENT.yaml [EXPERIMENT.yaml ...]
        [--select suspects|touched|cages] [--limit N] [--out rejudged.jsonl]
        [--trials OBJECT:METHOD:PROTOCOL:TRIAL ...]

Issue 42: the cage test once called an object caged when it was still held at the end with
both fingers within ``monitor.closed_tolerance`` (2 mm) of closed; the monitor now asks what
the loop encloses (:mod:`gbh_drake.core.enclosure`), and a trial whose object touched the table
while held after the lift is ``touched_down``, not a success. The rows do not hold the poses
at the end of the cage test, so the trials are simulated again (``trial_scenario`` of the
experiment file whose ``name`` is the row's ``experiment``; ``pick.set_down: false``: the
verdict is final once the cage test is over), and each run is judged by both rules on the same
simulation (the finger rule from its recorded ``cage_test_held``, ``loop_closed`` and
``table_touch_while_carried``).

``--select``: ``suspects``, committed successes held with the bar out whose fingers ended the
cage test more than 0.2 mm from closed (the finger rule's tolerance decided them); ``touched``,
successes that touched the table while carried; ``cages``, committed cages with the loop
closed (controls, ``--limit`` of them, one per object first); ``--trials``: these trials,
successes or not (whole-trial confirmations). Rows are appended to ``--out``
(a trial already there is skipped); a Markdown table of every trial is printed at the end,
those whose verdict the new rules change first.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

#: m: fingers farther than this from closed at the end of the cage test: the finger rule's
#: tolerance, not the closed loop, decided the cage.
SUSPECT = 0.0002


def finger_rule(verdict: dict, success: bool) -> str:
    """The verdict by the old rules, from a verdict's recorded facts: ``success [cage|pinch]``
    (touching the table while carried did not count) or the outcome."""
    outcome = verdict["outcome"]
    if outcome in ("success", "touched_down"):
        caged = verdict["cage_test_held"] and verdict["loop_closed"]
        return f"success [{'cage' if caged else 'pinch'}]"
    return outcome


def new_rule(verdict: dict) -> str:
    outcome = verdict["outcome"]
    return f"{outcome} [{verdict['held_by']}]" if verdict.get("held_by") else outcome


def committed(row: dict) -> str:
    return f"{row['outcome']} [{row['held_by']}]" if row.get("held_by") else row["outcome"]


def select(rows: list[dict], how: str, limit: int) -> list[dict]:
    from gbh_drake.core.gripper import HOOK_GRIPPER

    chosen = []
    for row in rows:
        v = row["record"]["verdict"]
        if not row["success"]:
            continue
        if how == "suspects" and v["bar_deployed"] and v["cage_test_held"] and \
                v["finger_q_cage_test"] > HOOK_GRIPPER.q_closed + SUSPECT:
            chosen.append(row)
        elif how == "touched" and v["table_touch_while_carried"]:
            chosen.append(row)
        elif how == "cages" and row["held_by"] == "cage" and \
                v["finger_q_cage_test"] <= HOOK_GRIPPER.q_closed + SUSPECT:
            chosen.append(row)
    if how == "cages":  # one per object first, then the rest, in order
        seen, first, rest = set(), [], []
        for row in chosen:
            (rest if row["object"] in seen else first).append(row)
            seen.add(row["object"])
        chosen = first + rest
    return chosen[:limit] if limit else chosen


def key(row: dict) -> tuple:
    return (row["experiment"], row["object"], row["method"], int(row["trial"]),
            row.get("protocol") or "stable")


def rejudge(row: dict, experiments: dict) -> dict:
    from gbh_drake.experiment.config import trial_scenario
    from gbh_drake.outputs import plain
    from gbh_drake.trial import build_trial, simulate_trial

    scenario = trial_scenario(experiments[row["experiment"]], row["object"], row["method"],
                              int(row["trial"]), row.get("protocol") or "stable")
    scenario.pick.set_down = False
    _, record = simulate_trial(build_trial(scenario))
    v = plain(record.to_dict()["verdict"])
    return {"experiment": row["experiment"], "object": row["object"], "method": row["method"],
            "trial": int(row["trial"]), "protocol": row.get("protocol") or "stable",
            "committed": committed(row), "finger_rule": finger_rule(v, record.success),
            "new": new_rule(v), "reason": record.reason, "grasp_kind": record.grasp_kind,
            "grasp_source": record.grasp_source, "verdict": v}


def table(results: list[dict]) -> str:
    results = sorted(results, key=lambda r: (r["finger_rule"] == r["new"], r["object"],
                                             r["method"], r["protocol"], r["trial"]))
    changed = sum(r["finger_rule"] != r["new"] for r in results)
    lines = [f"{changed} of {len(results)} re-simulated trials change verdict "
             "(finger rule -> enclosure and touch-down, same simulation):", "",
             "| object | method | protocol | trial | committed | finger rule | new | gap mm | "
             "material mm | in gap | linked | min clearance cm (phase) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        v = r["verdict"]

        def mm(x):
            return "" if x is None else f"{1000 * x:.1f}"

        low = v.get("min_clearance_after_lift")
        lines.append(
            f"| {r['object']} | {r['method']} | {r['protocol']} | {r['trial']} | "
            f"{r['committed']} | {r['finger_rule']} | {r['new']} | {mm(v.get('loop_gap'))} | "
            f"{mm(v.get('material_thickness'))} | {v.get('material_in_gap')} | "
            f"{v.get('loop_linked')} | "
            f"{'' if low is None else f'{100 * low:.1f}'} ({v.get('min_clearance_phase')}) |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rows")
    parser.add_argument("experiments", nargs="+")
    parser.add_argument("--select", choices=("suspects", "touched", "cages"), default="suspects")
    parser.add_argument("--limit", type=int, default=0)
    parser.add_argument("--out", default="rejudged.jsonl")
    parser.add_argument("--trials", nargs="*", default=None,
                        help="OBJECT:METHOD:PROTOCOL:TRIAL of the rows to run (any outcome)")
    parser.add_argument("--table-only", action="store_true",
                        help="print the table of --out without simulating")
    args = parser.parse_args()

    from gbh_drake.experiment.config import load_experiment

    out = Path(args.out)
    done = [json.loads(line) for line in out.read_text().splitlines()] if out.exists() else []
    if not args.table_only:
        experiments = {}
        for path in args.experiments:
            experiment = load_experiment(path)
            experiments[experiment.name] = experiment
        rows = [json.loads(line) for line in Path(args.rows).read_text().splitlines()
                if line.strip()]
        seen = {(r["experiment"], r["object"], r["method"], r["trial"], r["protocol"])
                for r in done}
        if args.trials is not None:
            wanted = [tuple(t.split(":")) for t in args.trials]
            chosen = [r for w in wanted for r in rows
                      if (r["object"], r["method"], r.get("protocol") or "stable",
                          str(r["trial"])) == w]
        else:
            chosen = select(rows, args.select, args.limit)
        for row in chosen:
            if key(row) in seen or row["experiment"] not in experiments:
                continue
            result = rejudge(row, experiments)
            with out.open("a") as f:
                f.write(json.dumps(result, sort_keys=True) + "\n")
            done.append(result)
            print(f"{result['object']} {result['method']} {result['protocol']} "
                  f"{result['trial']}: {result['committed']} -> {result['finger_rule']} / "
                  f"{result['new']}", flush=True)
    print(table(done))


if __name__ == "__main__":
    main()
