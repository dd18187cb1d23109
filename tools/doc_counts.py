"""The counts the documentation states about the committed experiment, recounted from its rows.

Run:  .venv/bin/python tools/doc_counts.py            # list every marked count: stated, rows
      .venv/bin/python tools/doc_counts.py --write    # rewrite the stale ones in place

The README and the pages under docs/ state counts of the reference experiment
(docs/experiment/trials.jsonl). Each stated count is marked with the name of the query that
recounts it, ``<!-- n: NAME -->VALUE<!-- /n -->`` (the comments do not show on GitHub or in the
site), and Table 1 is generated whole between ``<!-- table1 -->`` and ``<!-- end table1 -->``.
:data:`COUNTS` holds the queries, each a line or two of pandas over the report's own typed frame
of the rows (:func:`gbh_drake.experiment.report.frame_of`: its columns ``reach_class``,
``held_how``, ``borderline_success``, ``lift_raised``... are the report's classifications, not
copies). ``tests/docs/test_counts.py`` fails when a stated count differs from its rows, so a
rerun of the experiment cannot leave the prose stale: rerun this with ``--write`` and reread the
sentences.
"""

from __future__ import annotations

import argparse
import itertools
import re
import sys
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from gbh_drake.experiment.report import frame_of, out_of_the_loops_reach
from gbh_drake.experiment.rows import read_jsonl
from gbh_drake.experiment.stats import holm, mcnemar, wilson

ROOT = Path(__file__).resolve().parents[1]
ROWS = ROOT / "docs" / "experiment" / "trials.jsonl"
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

Count = Callable[[pd.DataFrame], str]


def pages() -> list[Path]:
    """The README and every page under docs/ (the pages whose counts may be marked)."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def read_rows(path: Path = ROWS) -> pd.DataFrame:
    """The experiment's rows as the report reads them: one typed row per trial."""
    return frame_of(read_jsonl(path), source=str(path))


def _of(frame: pd.DataFrame, method: str, protocol: str, *, hangable: bool = True) -> pd.DataFrame:
    mine = frame[(frame.method == method) & (frame.protocol == protocol)]
    return mine[~mine.is_control] if hangable else mine


def _held(frame: pd.DataFrame, how: str) -> int:
    return int((frame.success & (frame.held_by == how)).sum())


def _k_of_n(k, n) -> str:
    return f"{int(k)} of {int(n)}"


def _rate(k: int, n: int) -> str:
    lo, hi = wilson(k, n)
    return f"{k}/{n} = {100.0 * k / n:.1f} % [{100.0 * lo:.1f}, {100.0 * hi:.1f}]"


def _p(p: float) -> str:
    """A p-value as the prose gives it: one significant digit below 0.01, else two decimals."""
    return f"{p:.1g}" if p < 0.01 else f"{p:.2f}"


def paired(frame: pd.DataFrame, protocol: str) -> dict[tuple[str, str], tuple]:
    """Every pair of Table 1's methods on the poses both ran in ``protocol`` (objects with
    hangable parts): (McNemar result, Holm-adjusted p over the protocol's pairs)."""
    mine = frame[(frame.protocol == protocol) & ~frame.is_control]
    outcome = {(r.object, r.method, r.trial): bool(r.success) for r in mine.itertuples()}
    tests = {}
    for a, b in itertools.combinations(METHODS, 2):
        poses = sorted((o, t) for o, m, t in outcome if m == a and (o, b, t) in outcome)
        tests[(a, b)] = mcnemar([outcome[(o, a, t)] for o, t in poses],
                                [outcome[(o, b, t)] for o, t in poses])
    adjusted = holm([t.p_value for t in tests.values()])
    return {pair: (t, q) for (pair, t), q in zip(tests.items(), adjusted, strict=True)}


def table1(frame: pd.DataFrame) -> str:
    """Table 1 per protocol: successes with Wilson 95 % intervals, cage / pinch, the paper's."""
    lines = ["| Method | stable (Wilson 95 %) | cage / pinch | natural (Wilson 95 %) | cage / pinch "
             "| Paper (real robot, 15 objects x 5) |", "|---|---|---|---|---|---|"]
    for method, (label, paper) in METHODS.items():
        cells = []
        for protocol in PROTOCOLS:
            mine = _of(frame, method, protocol)
            cells += [_rate(int(mine.success.sum()), len(mine)),
                      f"{_held(mine, 'cage')} / {_held(mine, 'pinch')}"]
        lines.append(f"| {label} | " + " | ".join(cells) + f" | {paper} |")
    return "\n".join(lines)


def _holm(a: str, b: str, protocol: str) -> Count:
    return lambda f: _p(paired(f, protocol)[(a, b)][1])


def _discordant(a: str, b: str, protocol: str) -> Count:
    """``n01 vs n10``: the pairs only ``b`` carried against those only ``a`` carried."""
    def count(f):
        test = paired(f, protocol)[(a, b)][0]
        return f"{test.n01} vs {test.n10}"
    return count


def _reach(method: str, protocol: str, klass: str | None) -> Count:
    """The no-grasp trials (``klass`` None) or those of one reach class."""
    def count(f):
        no_grasp = _of(f, method, protocol).query("outcome == 'no_grasp_found'")
        return str(len(no_grasp) if klass is None else int((no_grasp.reach_class == klass).sum()))
    return count


def _reachable(method: str, protocol: str) -> Count:
    """Successes among the trials a loop can reach (all but the no-grasp ones out of reach)."""
    def count(f):
        mine = _of(f, method, protocol)
        kept = mine[~((mine.outcome == "no_grasp_found") & (mine.reach_class == "out of reach"))]
        return _rate(int(kept.success.sum()), len(kept))
    return count


def _unreached(method: str, protocol: str, what: str) -> Count:
    """Among the trials no rigid loop reaches as the object lies: ``trials``, ``carried``,
    ``caged``, or the successes taken in one way (the report's ``held_how``)."""
    def count(f):
        mine = _of(f, method, protocol)
        mine = mine[out_of_the_loops_reach(mine)]
        carried = mine[mine.success]
        return str({"trials": len(mine), "carried": len(carried),
                    "caged": _held(mine, "cage")}.get(what, int((carried.held_how == what).sum())))
    return count


def _controls(f: pd.DataFrame, methods=GBH_METHODS) -> pd.DataFrame:
    return f[f.is_control & f.method.isin(methods)]


def _controls_carried(method: str, protocol: str) -> Count:
    """``k of n``: the control trials (nothing to hang by) ``method`` carried."""
    def count(f):
        mine = _of(f, method, protocol, hangable=False).query("is_control")
        return _k_of_n(mine.success.sum(), len(mine))
    return count


def _released(method: str, protocol: str) -> Count:
    """``k of n``: the successes whose object was let go on the table at the place."""
    def count(f):
        carried = _of(f, method, protocol).query("success")
        return _k_of_n(carried.released_on_table.fillna(False).sum(), len(carried))
    return count


def _lift_raised(method: str, protocol: str) -> Count:
    """``k of n``: the executed hooks whose lift the unseen space next to the scan raised."""
    def count(f):
        mine = _of(f, method, protocol)
        hooks = mine.grasp_kind.isin(("parallel", "vertical", "scoop"))
        return _k_of_n(mine.lift_raised.sum(), hooks.sum())
    return count


def _no_true_part(method: str, protocol: str) -> Count:
    """Successes held by a pinch of material that is no true hangable part."""
    def count(f):
        mine = _of(f, method, protocol)
        return str(int((mine.success & (mine.held_by == "pinch")
                        & mine.grasped_true_part.eq(False)).sum()))
    return count


def _held_by(method: str, obj: str, how: str) -> Count:
    """``k of n``: ``method``'s trials of ``obj`` (both protocols) carried and held by ``how``."""
    def count(f):
        mine = f[(f.method == method) & (f.object == obj)]
        return _k_of_n(_held(mine, how), len(mine))
    return count


#: Every count the pages may state, by name: a function of the rows' frame giving the text.
COUNTS: dict[str, Count] = {
    "rows": lambda f: str(len(f)),
    "objects": lambda f: str(f.object.nunique()),
    "hangable_objects": lambda f: str(f.loc[~f.is_control, "object"].nunique()),
    "controls": lambda f: str(f.loc[f.is_control, "object"].nunique()),
    "commits": lambda f: str(f.commit.nunique()),
    "controls_gbh_rows": lambda f: str(len(_controls(f))),
    "controls_gbh_structures": lambda f: str(int((_controls(f).n_structures > 0).sum())),
    "retried": lambda f: str(int((f.attempts > 0).sum())),
    "retried_carried": lambda f: str(int(((f.attempts > 0) & f.success).sum())),
    "borderline": lambda f: _k_of_n(f.borderline_success.sum(), f.success.sum()),
    "borderline_touched": lambda f: str(int(
        (f.borderline_success & f.table_touch_while_carried.fillna(False)).sum())),
    "unseen_lift_gbh10_stable": _lift_raised("gbh-10", "stable"),
    "unseen_lift_gbh1_stable": _lift_raised("gbh-1", "stable"),
}
for _p_ in PROTOCOLS:
    for _m in METHODS:
        COUNTS[f"success_{_m}_{_p_}"] = (lambda m, p: lambda f: str(int(
            _of(f, m, p).success.sum())))(_m, _p_)
    COUNTS[f"released_gbh10_{_p_}"] = _released("gbh-10", _p_)
    COUNTS[f"controls_carried_plus_{_p_}"] = _controls_carried("gbh+", _p_)
    COUNTS[f"p_gbh10_antipodal_{_p_}"] = _holm("gbh-10", "antipodal", _p_)
    COUNTS[f"p_gbh1_antipodal_{_p_}"] = _holm("gbh-1", "antipodal", _p_)
    COUNTS[f"p_fallback_plus_{_p_}"] = _holm("gbh+fallback", "gbh+", _p_)
    COUNTS[f"pairs_fallback_plus_{_p_}"] = _discordant("gbh+fallback", "gbh+", _p_)
    COUNTS[f"reachable_gbh10_{_p_}"] = _reachable("gbh-10", _p_)
    COUNTS[f"no_true_part_gbh1_{_p_}"] = _no_true_part("gbh-1", _p_)
    for _k, _name in ((None, "no_grasp"), ("out of reach", "out_of_reach"),
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
for _obj in ("clothes_hanger", "key_ring", "scissors", "tape_roll"):
    for _how in ("cage", "pinch"):
        COUNTS[f"plus_{_obj}_{_how}"] = _held_by("gbh+", _obj, _how)


def stated(text: str) -> list[tuple[str, str]]:
    """(name, stated value) of every marked count in ``text``, in order."""
    return [(m["name"], m["value"]) for m in MARK.finditer(text)]


def recount(text: str, frame: pd.DataFrame) -> str:
    """``text`` with every marked count and Table 1 as the rows give them."""
    text = MARK.sub(lambda m: f"<!-- n: {m['name']} -->{COUNTS[m['name']](frame)}<!-- /n -->", text)
    if TABLE_START in text:
        start = text.index(TABLE_START) + len(TABLE_START)
        text = text[:start] + "\n" + table1(frame) + "\n" + text[text.index(TABLE_END):]
    return text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="rewrite the stale counts in place")
    args = parser.parse_args(argv)
    frame = read_rows()
    stale = 0
    for page in pages():
        text = page.read_text()
        if not stated(text) and TABLE_START not in text:
            continue
        for name, value in stated(text):
            now = COUNTS[name](frame)
            print(f"{page.relative_to(ROOT)}: {name}: {value}" +
                  ("" if now == value else f"  -> the rows: {now}"))
        new = recount(text, frame)
        stale += new != text
        if args.write and new != text:
            page.write_text(new)
    return 0 if args.write or not stale else 1


if __name__ == "__main__":
    sys.exit(main())
