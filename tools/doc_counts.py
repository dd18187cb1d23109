"""The counts the documentation states about the committed experiment, recounted from its rows.

Run:  .venv/bin/python tools/doc_counts.py            # list every marked count: stated, rows
      .venv/bin/python tools/doc_counts.py --write    # rewrite the stale ones in place

The README and the pages under docs/ state counts of the reference experiment
(docs/experiment/trials.jsonl). Each stated count is marked with the name of the query that
recounts it, ``<!-- n: NAME -->VALUE<!-- /n -->`` (the comments do not show on GitHub or in the
site), and Table 1 is generated whole between ``<!-- table1 -->`` and ``<!-- end table1 -->``.
:data:`COUNTS` holds the queries, each a few lines of pandas over the rows
(:func:`read_rows`); the classifications the report makes (a trial's reach class, how a success
was taken, which trials no rigid loop reaches) are the report's own functions, not copies.
``tests/docs/test_counts.py`` fails when a stated count differs from its rows, so a rerun of the
experiment cannot leave the prose stale: rerun this with ``--write`` and reread the sentences.
"""

from __future__ import annotations

import argparse
import itertools
import re
import sys
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from gbh_drake.experiment.report import held_how, out_of_the_loops_reach, reach_class
from gbh_drake.experiment.stats import holm, mcnemar, wilson

ROOT = Path(__file__).resolve().parents[1]
ROWS = ROOT / "docs" / "experiment" / "trials.jsonl"


def pages() -> list[Path]:
    """The README and every page under docs/ (the pages whose counts may be marked)."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
MARK = re.compile(r"<!-- n: (?P<name>[a-z0-9_]+) -->(?P<value>.*?)<!-- /n -->")
TABLE_START, TABLE_END = "<!-- table1 -->", "<!-- end table1 -->"

#: The methods of Table 1, in its order, with the paper's figure beside each.
METHODS = {
    "gbh-10": ("GbH, 10 views (`gbh-10`)", "68/75 = 90.7 %"),
    "gbh-1": ("GbH, 1 view (`gbh-1`, d2 = 5 mm)", "54/75 = 72.0 %"),
    "antipodal": ("antipodal baseline, bar folded (`antipodal`)", "GraspNet: 23/75 = 30.7 %"),
    "gbh+fallback": ("GbH + antipodal fallback (`gbh+fallback`)", "-"),
    "gbh+": ("GbH, scoop, regrasp, fallback, one retry (`gbh+`)", "-"),
}
#: The methods that run GbH (the controls' "no structure" count is over these).
GBH_METHODS = ("gbh-10", "gbh-1", "gbh+fallback", "gbh+")
PROTOCOLS = ("stable", "natural")


def read_rows(path: Path = ROWS) -> pd.DataFrame:
    """The experiment's rows, one per trial, with a ``protocol`` (older rows: stable)."""
    rows = pd.read_json(path, lines=True)
    rows["protocol"] = rows.get("protocol", pd.Series(dtype=str)).fillna("stable")
    return rows


def _record(rows: pd.DataFrame, key: str) -> pd.Series:
    return rows["record"].map(lambda r: (r or {}).get(key))


def _verdict(rows: pd.DataFrame, key: str) -> pd.Series:
    return rows["record"].map(lambda r: ((r or {}).get("verdict") or {}).get(key))


def _of(rows: pd.DataFrame, method: str, protocol: str, *, hangable: bool = True) -> pd.DataFrame:
    mine = rows[(rows["method"] == method) & (rows["protocol"] == protocol)]
    return mine[~mine["is_control"]] if hangable else mine


def _dicts(rows: pd.DataFrame) -> list[dict]:
    return rows.to_dict("records")


def _held(rows: pd.DataFrame, how: str) -> int:
    return int((rows["success"] & (rows["held_by"] == how)).sum())


def _p(p: float) -> str:
    """A p-value as the prose gives it: two significant digits below 0.01, else two decimals."""
    return f"{p:.1g}" if p < 0.01 else f"{p:.2f}"


def paired(rows: pd.DataFrame, protocol: str) -> dict[tuple[str, str], tuple]:
    """Every pair of Table 1's methods on the poses both ran in ``protocol`` (objects with
    hangable parts): (McNemar result, Holm-adjusted p over the protocol's pairs)."""
    mine = rows[(rows["protocol"] == protocol) & ~rows["is_control"]]
    outcome = {(r.object, r.method, r.trial): bool(r.success) for r in mine.itertuples()}
    tests = {}
    for a, b in itertools.combinations(METHODS, 2):
        poses = sorted((o, t) for o, m, t in outcome if m == a and (o, b, t) in outcome)
        tests[(a, b)] = mcnemar([outcome[(o, a, t)] for o, t in poses],
                                [outcome[(o, b, t)] for o, t in poses])
    adjusted = holm([t.p_value for t in tests.values()])
    return {pair: (t, q) for (pair, t), q in zip(tests.items(), adjusted, strict=True)}


def _holm(a: str, b: str, protocol: str) -> Callable[[pd.DataFrame], str]:
    return lambda rows: _p(paired(rows, protocol)[(a, b)][1])


def _discordant(a: str, b: str, protocol: str) -> Callable[[pd.DataFrame], str]:
    """``n01 vs n10``: the pairs only ``b`` carried against those only ``a`` carried."""
    def count(rows):
        test = paired(rows, protocol)[(a, b)][0]
        return f"{test.n01} vs {test.n10}"
    return count


def _rate(k: int, n: int) -> str:
    lo, hi = wilson(k, n)
    return f"{k}/{n} = {100.0 * k / n:.1f} % [{100.0 * lo:.1f}, {100.0 * hi:.1f}]"


def table1(rows: pd.DataFrame) -> str:
    """Table 1 per protocol: successes with Wilson 95 % intervals, cage / pinch, the paper's."""
    lines = ["| Method | stable (Wilson 95 %) | cage / pinch | natural (Wilson 95 %) | cage / pinch "
             "| Paper (real robot, 15 objects x 5) |", "|---|---|---|---|---|---|"]
    for method, (label, paper) in METHODS.items():
        cells = []
        for protocol in PROTOCOLS:
            mine = _of(rows, method, protocol)
            cells += [_rate(int(mine["success"].sum()), len(mine)),
                      f"{_held(mine, 'cage')} / {_held(mine, 'pinch')}"]
        lines.append(f"| {label} | " + " | ".join(cells) + f" | {paper} |")
    return "\n".join(lines)


def _success(method: str, protocol: str) -> Callable[[pd.DataFrame], str]:
    return lambda rows: str(int(_of(rows, method, protocol)["success"].sum()))


def _reach(method: str, protocol: str, klass: str) -> Callable[[pd.DataFrame], str]:
    def count(rows):
        mine = _of(rows, method, protocol)
        no_grasp = mine[mine["outcome"] == "no_grasp_found"]
        if klass == "no_grasp":
            return str(len(no_grasp))
        return str(sum(reach_class(r) == klass for r in _dicts(no_grasp)))
    return count


def _reachable(method: str, protocol: str) -> Callable[[pd.DataFrame], str]:
    """Successes among the trials a loop can reach (all but the no-grasp ones out of reach)."""
    def count(rows):
        mine = _dicts(_of(rows, method, protocol))
        kept = [r for r in mine if not (r["outcome"] == "no_grasp_found"
                                        and reach_class(r) == "out of reach")]
        return _rate(sum(bool(r["success"]) for r in kept), len(kept))
    return count


def _unreached(method: str, protocol: str, what: str) -> Callable[[pd.DataFrame], str]:
    """Among the trials no rigid loop reaches as the object lies: ``trials``, ``carried``,
    ``caged``, or the successes taken in one way (:func:`held_how`)."""
    def count(rows):
        mine = [r for r in _dicts(_of(rows, method, protocol)) if out_of_the_loops_reach(r)]
        carried = [r for r in mine if r["success"]]
        if what == "trials":
            return str(len(mine))
        if what == "carried":
            return str(len(carried))
        if what == "caged":
            return str(sum(r["held_by"] == "cage" for r in carried))
        return str(sum(held_how(r) == what for r in carried))
    return count


def _released(method: str, protocol: str) -> Callable[[pd.DataFrame], str]:
    """``k of n``: the successes whose object was let go on the table at the place."""
    def count(rows):
        carried = _of(rows, method, protocol)
        carried = carried[carried["success"]]
        return f"{int(_verdict(carried, 'released_on_table').fillna(False).sum())} of {len(carried)}"
    return count


def _controls(rows: pd.DataFrame, methods=GBH_METHODS) -> pd.DataFrame:
    return rows[rows["is_control"] & rows["method"].isin(methods)]


def _controls_carried(method: str, protocol: str) -> Callable[[pd.DataFrame], str]:
    """``k of n``: the control trials (nothing to hang by) ``method`` carried."""
    def count(rows):
        mine = _of(rows, method, protocol, hangable=False)
        mine = mine[mine["is_control"]]
        return f"{int(mine['success'].sum())} of {len(mine)}"
    return count


def _retried(rows: pd.DataFrame) -> pd.DataFrame:
    return rows[_record(rows, "attempts").map(bool)]


def _unseen_lift(method: str, protocol: str) -> Callable[[pd.DataFrame], str]:
    """``k of n``: the executed hooks whose lift the unseen space next to the scan raised."""
    def count(rows):
        mine = _of(rows, method, protocol)
        hooks = mine[mine["grasp_kind"].isin(("parallel", "vertical", "scoop"))]
        notes = _record(mine, "plan_notes").map(
            lambda ns: any(str(n).startswith("the lift allows for unseen space") for n in ns or []))
        return f"{int(notes.sum())} of {len(hooks)}"
    return count


def _no_true_part(method: str, protocol: str) -> Callable[[pd.DataFrame], str]:
    """Successes held by a pinch of material that is no true hangable part."""
    def count(rows):
        mine = _of(rows, method, protocol)
        return str(int((mine["success"] & (mine["held_by"] == "pinch")
                        & (_record(mine, "grasped_true_part") == False)).sum()))  # noqa: E712
    return count


#: Every count the pages may state, by name: a function of the rows giving the stated text.
COUNTS: dict[str, Callable[[pd.DataFrame], str]] = {
    "rows": lambda rows: str(len(rows)),
    "objects": lambda rows: str(rows["object"].nunique()),
    "hangable_objects": lambda rows: str(rows.loc[~rows["is_control"], "object"].nunique()),
    "controls": lambda rows: str(rows.loc[rows["is_control"], "object"].nunique()),
    "commits": lambda rows: str(rows["commit"].nunique()),
    "controls_gbh_rows": lambda rows: str(len(_controls(rows))),
    "controls_gbh_structures": lambda rows: str(int(
        (_record(_controls(rows), "n_structures") > 0).sum())),
    "controls_gbh_hooked": lambda rows: str(int((_controls(rows)["success"] & (
        _controls(rows)["held_by"] == "cage")).sum())),
    "retried": lambda rows: str(len(_retried(rows))),
    "retried_carried": lambda rows: str(int(_retried(rows)["success"].sum())),
    "unseen_lift_gbh10_stable": _unseen_lift("gbh-10", "stable"),
    "unseen_lift_gbh1_stable": _unseen_lift("gbh-1", "stable"),
}
for _p_ in PROTOCOLS:
    for _m in METHODS:
        COUNTS[f"success_{_m}_{_p_}"] = _success(_m, _p_)
    COUNTS[f"released_gbh10_{_p_}"] = _released("gbh-10", _p_)
    COUNTS[f"controls_carried_plus_{_p_}"] = _controls_carried("gbh+", _p_)
    COUNTS[f"p_gbh10_antipodal_{_p_}"] = _holm("gbh-10", "antipodal", _p_)
    COUNTS[f"p_gbh1_antipodal_{_p_}"] = _holm("gbh-1", "antipodal", _p_)
    COUNTS[f"p_fallback_plus_{_p_}"] = _holm("gbh+fallback", "gbh+", _p_)
    COUNTS[f"pairs_fallback_plus_{_p_}"] = _discordant("gbh+fallback", "gbh+", _p_)
    COUNTS[f"reachable_gbh10_{_p_}"] = _reachable("gbh-10", _p_)
    COUNTS[f"no_true_part_gbh1_{_p_}"] = _no_true_part("gbh-1", _p_)
    for _k, _name in (("no_grasp", "no_grasp"), ("out of reach", "out_of_reach"),
                      ("lost in the scan", "lost_in_scan"),
                      ("candidate set missed", "candidates_missed")):
        COUNTS[f"{_name}_gbh10_{_p_}"] = _reach("gbh-10", _p_, _k)
    for _m, _short in (("gbh+", "plus"), ("gbh-10", "gbh10"), ("gbh+fallback", "fallback")):
        for _what in ("trials", "carried", "caged"):
            COUNTS[f"unreached_{_short}_{_what}_{_p_}"] = _unreached(_m, _p_, _what)
    for _what, _name in (("hook", "hook"), ("scoop", "scoop"), ("regrasp, hook", "regrasp_hook"),
                         ("regrasp, fallback pinch", "regrasp_pinch"),
                         ("fallback pinch", "fallback_pinch")):
        COUNTS[f"unreached_plus_{_name}_{_p_}"] = _unreached("gbh+", _p_, _what)


def _held_by(method: str, obj: str, how: str) -> Callable[[pd.DataFrame], str]:
    """``k of n``: ``method``'s trials of ``obj`` (both protocols) carried and held by ``how``
    (``cage`` or ``pinch``)."""
    def count(rows):
        mine = rows[(rows["method"] == method) & (rows["object"] == obj)]
        return f"{_held(mine, how)} of {len(mine)}"
    return count


for _obj in ("clothes_hanger", "key_ring", "scissors", "tape_roll"):
    for _how in ("cage", "pinch"):
        COUNTS[f"plus_{_obj}_{_how}"] = _held_by("gbh+", _obj, _how)


def stated(text: str) -> list[tuple[str, str]]:
    """(name, stated value) of every marked count in ``text``, in order."""
    return [(m["name"], m["value"]) for m in MARK.finditer(text)]


def recount(text: str, rows: pd.DataFrame) -> str:
    """``text`` with every marked count and Table 1 as the rows give them."""
    text = MARK.sub(lambda m: f"<!-- n: {m['name']} -->{COUNTS[m['name']](rows)}<!-- /n -->", text)
    if TABLE_START in text:
        start = text.index(TABLE_START) + len(TABLE_START)
        text = text[:start] + "\n" + table1(rows) + "\n" + text[text.index(TABLE_END):]
    return text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="rewrite the stale counts in place")
    args = parser.parse_args(argv)
    rows = read_rows()
    stale = 0
    for page in pages():
        text = page.read_text()
        if not stated(text) and TABLE_START not in text:
            continue
        for name, value in stated(text):
            now = COUNTS[name](rows)
            stale += now != value
            print(f"{page.relative_to(ROOT)}: {name}: {value}" +
                  ("" if now == value else f"  -> the rows: {now}"))
        if args.write and recount(text, rows) != text:
            page.write_text(recount(text, rows))
    return 0 if args.write or not stale else 1


if __name__ == "__main__":
    sys.exit(main())
