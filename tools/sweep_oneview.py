"""One view, completed and chosen: pre-execution counts over the scans of ``oneview_scans.py``.

For every trial scanned by ``tools/oneview_scans.py`` (the view GbH-1 takes, the first look,
every candidate view), GbH's three stages run on one scan per variant, and per variant the
script counts over the trials of each set (each scans folder given: the own set's and the
external set's) and, with several, over all of them (as ``tools/sweep_thresholds.py`` does):

* ``part found``: trials with a hanging structure on a true hangable part (c within half the
  part's clear diameter + 2 cm of its centre), of the trials of objects with parts;
* ``top on part`` / ``top on a false part``: whose best ranked grasp hooks a true part / a
  structure that is no true part (what the planner tries first);
* ``false structures``: structures not on a true part, over all trials;
* ``controls with a grasp``: control trials with a ranked grasp (a control hooked on a false
  structure needs one);
* ``view moved``: trials whose chosen view is not the fixed one.

Variants (``--variants``, comma-separated):

* ``fixed``: the fixed view, as GbH-1 (the trial's own GbH parameters);
* ``completed``: the fixed view completed (``perception.completion.complete_scan``);
* ``chosen``: the view ``perception.view_choice.choose_view`` picks from the first look;
* ``chosen_completed``: that view, completed;
* ``oracle``: the best candidate view for the ground truth (an upper bound, not a method).

``--sweep confidence=0.7,0.8,0.9`` (or ``min_explained=...``, ``erode=coarse,none``) repeats the
completed variants for each value of that ``CompletionParams`` field. Usage::

    python tools/sweep_oneview.py /tmp/ov1 --variants fixed,completed,chosen,chosen_completed \\
        --sweep confidence=0.8,0.9,0.95
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import pickle
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

VARIANTS = ("fixed", "completed", "chosen", "chosen_completed", "oracle")
COMPLETED = ("completed", "chosen_completed")


def _counts(scan, record, params, seed) -> dict:
    """GbH on ``scan``: the counts of one trial (see the module docstring)."""
    import numpy as np

    from gbh_drake.core.pipeline import plan_grasps
    from gbh_drake.core.results import GbhInputError

    out = {"structures": 0, "false": 0, "part_found": False, "top_on_part": False,
           "top_false": False, "ranked": 0, "gbh_s": 0.0}
    if scan.empty or len(scan.mesh_W.faces) == 0:
        return out

    def on_part(c) -> bool:
        return any(np.linalg.norm(np.asarray(c) - center) <= 0.5 * clear + 0.02
                   for center, _, clear in record["parts"])

    start = time.perf_counter()
    try:
        result = plan_grasps(scan.mesh_W, params, seed=seed, free_space=scan.free_space)
    except GbhInputError:
        return out
    found = [on_part(s.c) for s in result.structures]
    ranked = [on_part(g.structure.c) for g in result.ranked]
    out.update(structures=len(found), false=len(found) - sum(found), part_found=any(found),
               top_on_part=bool(ranked and ranked[0]), top_false=bool(ranked and not ranked[0]),
               ranked=len(ranked), gbh_s=time.perf_counter() - start)
    return out


def _trial_task(args):
    """The rows (one per variant and value) of one trial's scans."""
    path, variants, sweep = args
    from gbh_drake.core.params import CompletionParams
    from gbh_drake.perception.completion import complete_scan
    from gbh_drake.perception.view_choice import choose_view
    from gbh_drake.perception.viewpoints import fit_view_distance

    record = pickle.loads(Path(path).read_bytes())
    params, seed = record["gbh"], record["seed"]
    config, look = record["scan_config"], record["look"]
    key = Path(path).stem.split("__")
    base = {"set": Path(path).parent.parent.name, "object": key[0], "protocol": key[1],
            "trial": int(key[2]),
            "control": record["control"], "has_parts": bool(record["parts"])}
    rows = []
    chosen_index, choice_s = 0, 0.0
    if {"chosen", "chosen_completed"} & set(variants) and look is not None and look.found:
        distance, _ = fit_view_distance(look.radius, config)
        choice = choose_view(look, config, look.centre_W, distance)
        chosen_index, choice_s = choice.index, choice.seconds
    candidates = record["candidates"]
    if isinstance(candidates, list):  # all candidate views, by index
        candidates = dict(enumerate(candidates))
    scans = {"fixed": record["fixed"], "chosen": candidates[chosen_index]}
    name, values = sweep if sweep else ("confidence", [CompletionParams().confidence])
    for variant in variants:
        if variant == "oracle":
            counts = {i: _counts(s, record, params, seed) for i, s in candidates.items()}
            best = max(counts, key=lambda i: (counts[i]["top_on_part"], -counts[i]["top_false"]))
            rows.append({**base, "variant": variant, "value": None, "view": best,
                         **counts[best]})
            continue
        source = "chosen" if variant.startswith("chosen") else "fixed"
        view = chosen_index if source == "chosen" else 0
        for value in (values if variant in COMPLETED else [None]):
            scan = scans[source]
            extra = {"view": view, "choice_s": choice_s if source == "chosen" else 0.0}
            if variant in COMPLETED:
                completion = dataclasses.replace(CompletionParams(), **{name: value})
                start = time.perf_counter()
                scan = complete_scan(scan, completion, seed)
                extra["completion_s"] = time.perf_counter() - start
                extra["completed"] = getattr(scan.free_space, "completion", None) is not None
            rows.append({**base, "variant": variant, "value": value, **extra,
                         **_counts(scan, record, params, seed)})
    return rows


def table(rows: list[dict], name: str = "value") -> list[str]:
    """The Markdown table of the rows: one line per (variant, value) and set (the scans'
    folder), and with more than one set one for all of them (``all``)."""
    import statistics

    lines = [f"| variant | {name} | set | part found | top on part | top on a false part | "
             "false structures | controls with a grasp | view moved | median GbH s |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    sets = sorted({r.get("set", "") for r in rows})
    groups: dict = {}
    for r in rows:
        for s in ([r.get("set", ""), "all"] if len(sets) > 1 else [r.get("set", "")]):
            groups.setdefault((r["variant"], json.dumps(r["value"]), s), []).append(r)
    order = [*sets, "all"]
    values = list(dict.fromkeys(k[1] for k in groups))  # as swept, not as text sorts them
    for (variant, value, set_name), group in sorted(
            groups.items(), key=lambda kv: (VARIANTS.index(kv[0][0]), values.index(kv[0][1]),
                                            order.index(kv[0][2]))):
        parts = [r for r in group if r["has_parts"]]
        ctrl = [r for r in group if r["control"]]
        lines.append(
            f"| {variant} | {value} | {set_name} | "
            f"{sum(r['part_found'] for r in parts)}/{len(parts)} | "
            f"{sum(r['top_on_part'] for r in parts)}/{len(parts)} | "
            f"{sum(r['top_false'] for r in parts)}/{len(parts)} | "
            f"{sum(r['false'] for r in group)} | {sum(r['ranked'] > 0 for r in ctrl)}/{len(ctrl)}"
            f" | {sum(r['view'] != 0 for r in group)}/{len(group)} | "
            f"{statistics.median(r['gbh_s'] for r in group):.2f} |")
    return lines


def _value(text: str):
    try:
        return float(text)
    except ValueError:
        return text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scans", nargs="+", help="folders written by oneview_scans.py")
    parser.add_argument("--variants", default="fixed,completed,chosen,chosen_completed")
    parser.add_argument("--sweep", default="", metavar="NAME=V1,V2",
                        help="a CompletionParams field and its values")
    parser.add_argument("--out", default="", help="write rows.jsonl and README.md here")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    variants = args.variants.split(",")
    unknown = set(variants) - set(VARIANTS)
    if unknown:
        parser.error(f"unknown variants {sorted(unknown)} (known: {', '.join(VARIANTS)})")
    sweep = None
    if args.sweep:
        name, values = args.sweep.split("=", 1)
        sweep = (name, [_value(v) for v in values.split(",")])
    paths = sorted(str(p) for folder in args.scans for p in Path(folder, "scans").glob("*.pkl"))
    start = time.perf_counter()
    rows = []
    with ProcessPoolExecutor(args.workers) as pool:
        for i, trial_rows in enumerate(pool.map(_trial_task, [(p, variants, sweep)
                                                              for p in paths])):
            rows += trial_rows
            if (i + 1) % 20 == 0:
                print(f"{i + 1}/{len(paths)} ({time.perf_counter() - start:.0f} s)",
                      file=sys.stderr, flush=True)
    text = "\n".join(table(rows, sweep[0] if sweep else "value"))
    print(text)
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        with open(out / "rows.jsonl", "w") as f:
            for r in rows:
                f.write(json.dumps(r) + "\n")
        (out / "README.md").write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
