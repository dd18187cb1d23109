"""One `gbh run` trial per object of the set, at the default scenario's pose, with 10 and 1 views;
writes docs/first_trials.md. An exploratory smoke run, not the paper's experiment.

Usage: python tools/first_trials.py [--out docs/first_trials.md]   (about 10 minutes on 2 cores)
"""

import argparse
import datetime
import os
import tempfile
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

from gbh_drake import REPO_ROOT, SCENARIOS_DIR  # noqa: E402
from gbh_drake.objects import list_objects, make_object  # noqa: E402
from gbh_drake.run import run  # noqa: E402
from gbh_drake.scenario import load_scenario  # noqa: E402

HEADER = """# First trials: one run per object at its default pose

Written by `tools/first_trials.py` on {date}. One `gbh run` trial per object at the default
scenario's pose (x = 0.55 m, yaw 30 deg), seed 0, with 10 views and with 1 view (d2 = 0 in both;
the paper uses d2 = 5 mm for 1 view). It is **not** the paper's experiment (several random poses
per object, the baseline, Table 1), which is still to be built: it shows where the pipeline
stands, failures included.

S: hanging structures found; C: grasp candidates; R: ranked (collision-free, clear of the table,
top 10); rank: which of them was executed (the first with IK solutions; 1 = best).
"""


def trial_rows(views: int, out_root: Path) -> tuple[list[str], int, int]:
    rows, carried, hangable = [], 0, 0
    for name in list_objects():
        overrides = (f"{{object: {{name: {name}}}, scan: {{num_views: {views}}}, "
                     f"settle_time: 0.1, output_dir: {out_root / str(views) / name}}}")
        p = run(load_scenario(SCENARIOS_DIR / "default.yaml", overrides=overrides)).pick
        is_control = make_object(name).is_control
        hangable += not is_control
        carried += p.success and not is_control
        rank = str(p.chosen_rank + 1) if p.chosen_rank >= 0 else "-"
        verdict = ("carried" if p.success else "failed") + f": {p.reason}"
        rows.append(f"| {name}{' (control)' if is_control else ''} | {p.n_structures} | "
                    f"{p.n_candidates} | {p.n_ranked} | {rank} | {p.chosen_kind} | {verdict} |")
        print(rows[-1], flush=True)
    return rows, carried, hangable


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(REPO_ROOT / "docs" / "first_trials.md"))
    args = parser.parse_args()
    text = [HEADER.format(date=datetime.date.today().isoformat())]
    with tempfile.TemporaryDirectory() as tmp:
        for views in (10, 1):
            rows, carried, hangable = trial_rows(views, Path(tmp))
            text.append(f"\n## {views} view{'s' if views > 1 else ''}: {carried} of {hangable} "
                        "objects with hangable parts carried\n")
            text.append("| object | S | C | R | rank | kind | verdict |")
            text.append("|---|---|---|---|---|---|---|")
            text.extend(rows)
    Path(args.out).write_text("\n".join(text) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
