"""tools/compare_rows.py: a changed trial is told apart as changed in the physics of the same
grasp or upstream of it (another grasp offered or chosen), and unchanged trials are not listed."""

import importlib.util
from pathlib import Path

TOOL = Path(__file__).parents[2] / "tools" / "compare_rows.py"
spec = importlib.util.spec_from_file_location("compare_rows", TOOL)
compare_rows = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare_rows)


def row(outcome: str, rank: int = 0, score: float = 0.9, structures: int = 2, **extra) -> dict:
    success = outcome == "success"
    return {"outcome": outcome, "success": success, "held_by": "cage" if success else "",
            "reason": outcome, "record": {"n_structures": structures, "n_candidates": 100,
                                          "grasp_kind": "parallel", "grasp_rank": rank,
                                          "grasp_score": score}, **extra}


def test_where_a_trial_changed():
    assert compare_rows.where(row("success"), row("not_lifted")) == "physics"
    assert compare_rows.where(row("success"), row("not_lifted", rank=1)) == "upstream"
    assert compare_rows.where(row("success"), row("success", structures=3)) == "upstream"
    assert compare_rows.rank(row("success", rank=3)) == "3"
    assert compare_rows.rank(row("no_grasp_found", rank=-1)) == "-"
    # No grasp executed in either run: what was offered or planned differed, not a pick.
    assert compare_rows.where(row("no_reachable_grasp", rank=-1),
                              row("no_grasp_found", rank=-1)) == "upstream"


def test_only_changed_trials_are_listed_with_where_they_changed():
    before = {("mug", "gbh-10", 0): row("success"), ("mug", "gbh-10", 1): row("success"),
              ("can", "gbh-10", 0): row("no_grasp_found", rank=-1)}
    after = {("mug", "gbh-10", 0): row("not_lifted"), ("mug", "gbh-10", 1): row("success"),
             ("can", "gbh-10", 0): row("no_grasp_found", rank=-1)}
    lines = compare_rows.compare(before, after)
    assert "| gbh-10 | 3 | 2 | 1 | 0 | 1 | 1/0 |" in lines
    assert "1 of 3 trials changed:" in lines
    changed = [line for line in lines if line.startswith("| mug |") or line.startswith("| can |")]
    assert changed == ["| mug | gbh-10 | 0 | success [cage] | not_lifted | physics | 0 > 0 | "
                       "not_lifted |"]
    assert any(line.startswith("where: 0 changed upstream") and "1 in the physics" in line
               for line in lines)


def test_rows_are_read_as_the_runner_reads_them(tmp_path, capsys):
    """A damaged line is one line naming the file and line (exit 2), not a traceback; a row of
    another protocol is left out, one whose protocol is a list refused."""
    import json

    good = {"object": "mug", "method": "gbh-10", "trial": 0, "seed": 1, "viewpoints": 10,
            **row("success")}
    path = tmp_path / "trials.jsonl"
    path.write_text(json.dumps(good) + "\n" + json.dumps({**good, "protocol": "natural"}) + "\n")
    assert list(compare_rows.load(path)) == [("mug", "gbh-10", 0)]
    path.write_text(json.dumps(good) + "\n" + json.dumps({**good, "protocol": ["natural"]}) + "\n")
    assert compare_rows.main([str(path), str(path)]) == 2
    err = capsys.readouterr().err
    assert err == (f"compare_rows: {path}: line 2: protocol is ['natural'], not a string; the file "
                   "is damaged: fix or remove that line\n")


def test_a_pair_compares_two_methods_of_the_same_trials():
    """``--pair gbh-10=gbh-10r``: one run's gbh-10 against its gbh-10r, trial by trial; the
    other methods are left out."""
    rows = {("mug", "gbh-10", 0): row("not_lifted"), ("mug", "gbh-10r", 0): row("success"),
            ("mug", "gbh+r", 0): row("success")}
    before, after = compare_rows.paired(rows, rows, [("gbh-10", "gbh-10r")])
    assert list(before) == list(after) == [("mug", "gbh-10=gbh-10r", 0)]
    lines = compare_rows.compare(before, after)
    assert "| gbh-10=gbh-10r | 1 | 0 | 1 | 1 | 0 | 1/0 |" in lines
