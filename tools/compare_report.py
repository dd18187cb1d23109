"""The report of an experiment folder by two versions of the report code, compared.

    python tools/compare_report.py FOLDER [FOLDER ...] [--ref REF] [--keep DIR]

For each folder (one holding ``trials.jsonl``), renders ``summary.md``, ``trials.csv`` and
``table1.csv`` twice from the same rows, into two scratch copies of the folder (the folder
itself is never written): once with the report as it was at git ``REF`` (default ``main``;
its ``gbh_drake/experiment/report.py``, one module, loaded from ``git show``) and once with
this checkout's :mod:`gbh_drake.experiment.report`. Prints per folder and file: identical, or
what differs (CSV: columns only in one, then per common column the rows whose value differs;
``summary.md``: the sections added, removed and changed, then a unified diff of the changed
ones). ``--keep DIR`` keeps both renderings under ``DIR/<folder name>/{old,new}``. Plots are not
rendered (they are not compared). Exit code 0 whatever the differences (a report, not a test).
"""

from __future__ import annotations

import argparse
import difflib
import importlib.util
import io
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pandas as pd

REPO = Path(__file__).resolve().parents[1]
OLD_MODULE = "gbh_drake/experiment/report.py"
FILES = ("summary.md", "trials.csv", "table1.csv")


def load_old(ref: str):
    """The report module as it was at ``ref`` (a single file then), imported under a private
    name; it imports the rest of gbh_drake from this checkout."""
    source = subprocess.run(["git", "-C", str(REPO), "show", f"{ref}:{OLD_MODULE}"],
                            check=True, capture_output=True, text=True).stdout
    path = Path(tempfile.mkdtemp()) / "old_report.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("old_report", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules["old_report"] = module  # (dataclasses look their module up)
    spec.loader.exec_module(module)
    return module


def render(module, folder: Path, out: Path) -> None:
    """``summary.md``, ``trials.csv``, ``table1.csv`` of ``folder``'s rows by ``module``."""
    out.mkdir(parents=True)
    for name in ("trials.jsonl", "experiment.yaml", "runs.jsonl"):
        if (folder / name).is_file():
            shutil.copy(folder / name, out / name)
    data = module.read_input(out)
    (out / "summary.md").write_text(module.summary_markdown(data, runs=module.read_runs(out)))
    (out / "trials.csv").write_text(module.trials_frame(data).to_csv(index=False))
    (out / "table1.csv").write_text(module.table1_frame(data).to_csv(index=False))


def compare_csv(old: str, new: str) -> list[str]:
    a = pd.read_csv(io.StringIO(old), keep_default_na=False, dtype=str)
    b = pd.read_csv(io.StringIO(new), keep_default_na=False, dtype=str)
    lines = []
    if list(a.columns) != [c for c in b.columns if c in a.columns]:
        lines.append("  columns in another order")
    only_old = [c for c in a.columns if c not in b.columns]
    only_new = [c for c in b.columns if c not in a.columns]
    if only_old:
        lines.append(f"  columns only in the old: {', '.join(only_old)}")
    if only_new:
        lines.append(f"  columns only in the new: {', '.join(only_new)}")
    if len(a) != len(b):
        return [*lines, f"  {len(a)} rows against {len(b)}"]
    for column in (c for c in a.columns if c in b.columns):
        differ = a[column] != b[column]
        if differ.any():
            i = differ.idxmax()
            lines.append(f"  {column}: {differ.sum()} rows differ (first, row {i}: "
                         f"{a[column][i]!r} -> {b[column][i]!r})")
    return lines


def sections(text: str) -> dict[str, list[str]]:
    """The lines of each ``##``/``###`` section of a summary, by heading (in order)."""
    out: dict[str, list[str]] = {}
    heading = "(head)"
    for line in text.splitlines():
        if line.startswith("##"):
            heading = line
            while heading in out:
                heading += " (again)"
        out.setdefault(heading, []).append(line)
    return out


def compare_summary(old: str, new: str) -> list[str]:
    a, b = sections(old), sections(new)
    lines = [f"  section added: {h}" for h in b if h not in a]
    lines += [f"  section removed: {h}" for h in a if h not in b]
    for heading in (h for h in a if h in b and a[h] != b[h]):
        lines.append(f"  section changed: {heading}")
        lines += ["    " + d for d in difflib.unified_diff(a[heading], b[heading], "old", "new",
                                                           n=0, lineterm="")][2:]
    if not lines and old != new:
        lines.append("  the sections' order differs")
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folders", nargs="+", type=Path)
    parser.add_argument("--ref", default="main", help="git ref of the old report (default main)")
    parser.add_argument("--keep", type=Path, default=None, help="keep the renderings here")
    args = parser.parse_args(argv)
    sys.path.insert(0, str(REPO))
    import gbh_drake.experiment.report as new

    old = load_old(args.ref)
    scratch = args.keep or Path(tempfile.mkdtemp())
    for folder in args.folders:
        target = scratch / folder.resolve().name
        if target.exists():
            shutil.rmtree(target)
        render(old, folder, target / "old")
        render(new, folder, target / "new")
        print(f"{folder}:")
        for name in FILES:
            a, b = (target / "old" / name).read_text(), (target / "new" / name).read_text()
            if a == b:
                print(f" {name}: identical")
                continue
            print(f" {name}: differs")
            print("\n".join(compare_summary(a, b) if name.endswith(".md") else
                            compare_csv(a, b)))
    if not args.keep:
        shutil.rmtree(scratch)
    return 0


if __name__ == "__main__":
    sys.exit(main())
