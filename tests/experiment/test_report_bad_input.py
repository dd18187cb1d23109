"""``gbh report`` on rows and files it did not write (issue 43's report classes), through the real
command line: a row's key it cannot place (a ``protocol`` that is a list, a mapping, a number)
and an experiment file asking for more trials than an experiment may have are one line naming
the file, line and field, exit 2, nothing written; any other field of the wrong type, NaN or
infinite, an unknown protocol or outcome is a one-line warning naming the file, line and field
(or is said in the summary), and everything else is still reported."""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import pytest
from test_rows_report import make_row

from gbh_drake.cli import main
from gbh_drake.experiment.rows import ROWS_FILE


@dataclass
class Case:
    id: str
    second: dict | str
    """The second of three rows (a dict, or a line as written)."""
    code: int
    expect: list[str]
    """What stderr says, each a line's start after ``gbh: `` (``{rows}``: the rows' path)."""
    files: dict[str, str] = field(default_factory=dict)
    """Other files of the folder."""
    summary: str = ""
    """Words the summary holds (exit 0)."""


def _row(trial: int = 1, **fields) -> dict:
    row = make_row("kettle", "gbh-10", trial)
    for path, value in fields.items():
        *parents, key = path.split("__")
        target = row
        for name in parents:
            target = target.setdefault(name, {})
        target[key] = value
    return row


def _line(row: dict) -> str:
    """A row as a line, NaN and infinity as Python's json writes them."""
    return json.dumps(row)


WARN = "warning: {rows}: line 2: "
DAMAGED = "damaged experiment folder: {rows}: line 2: "

CASES = [
    # ---- a key the report cannot place: exit 2 --------------------------------------------
    Case("protocol_list", _row(protocol=["stable"]), 2,
         [DAMAGED + "protocol is ['stable'], not a string"]),
    Case("protocol_mapping", _row(protocol={"name": "stable"}), 2,
         [DAMAGED + "protocol is {'name': 'stable'}, not a string"]),
    Case("protocol_number", _row(protocol=3), 2,
         [DAMAGED + "protocol is 3, not a string"]),
    Case("trials_billion", _row(), 2,
         ["damaged experiment folder: {folder}/experiment.yaml: trials: 1 objects x "
          "1000000000 trials x 1 methods x 1 protocols are 1000000000 trials; at most 10000"],
         files={"experiment.yaml": "name: e\nobjects: [kettle]\ntrials: 1000000000\n"
                                   "methods: [{name: gbh-10}]\n"}),
    # ---- a protocol the report has no words for: reported, and said -------------------------
    Case("protocol_unknown_in_rows", _row(protocol="upright"), 0, [],
         summary="Protocol `upright`: the report has no description of this protocol."),
    Case("protocol_unknown_in_file", _row(protocol="upright"), 0, [],
         files={"experiment.yaml": "name: e\nobjects: [kettle]\ntrials: 3\n"
                                   "methods: [{name: gbh-10}]\nprotocols: [stable, upright]\n"},
         summary="## Table 1, protocol `upright`"),
    # ---- a field of the wrong type, NaN or infinite: missing, told --------------------------
    Case("score_nan", _line(_row(grasp_score=float("nan"))), 0,
         [WARN + "grasp_score: expected a finite number, got nan; read as missing"]),
    Case("time_infinite", _line(_row(stage_times__total=float("inf"))), 0,
         [WARN + "stage_times.total: expected a finite number, got inf; read as missing"]),
    Case("rank_text", _row(grasp_rank="first"), 0,
         [WARN + "grasp_rank: expected an integer, got 'first'; read as missing"]),
    Case("refusals_list", _row(refusals=["ik:lift"]), 0,
         [WARN + "refusals: expected a mapping of names to integers, got ['ik:lift']"]),
    Case("record_list", _row(record=[1, 2]), 0,
         [WARN + "record: expected a mapping, got list; its fields read as missing"]),
    Case("verdict_text", _row(record__verdict="held"), 0,
         [WARN + "record.verdict: expected a mapping, got str"]),
    Case("pose_short", _row(pose=[0.5, 0.0]), 0,
         [WARN + "pose: expected 6 finite numbers (x, y, z, roll, pitch, yaw), got [0.5, 0.0]"]),
    Case("control_text", _row(is_control="no"), 0,
         [WARN + "is_control: expected true or false, got 'no'"]),
    Case("tags_text", _row(object_tags="cup"), 0,
         [WARN + "object_tags: expected a list of strings, got 'cup'"]),
    Case("sank_at_text", _row(record__verdict__sank_at="soon"), 0,
         [WARN + "record.verdict.sank_at: expected a finite number, got 'soon'"]),
    Case("outcome_unknown", _row(outcome="exploded", success=False), 0,
         [WARN + "outcome: no cause class for the outcome 'exploded'; cause 'unknown'"],
         summary="| unknown "),
    # ---- rows missing fields (older rows): missing, nothing to tell ------------------------
    Case("only_the_key_fields", {k: _row()[k] for k in ("object", "method", "trial", "seed",
                                                        "outcome", "success", "reason",
                                                        "viewpoints")}, 0, [],
         summary="3 trials"),
    # ---- the runs' log ------------------------------------------------------------------------
    Case("run_wall_text", _row(), 0,
         ["warning: {folder}/runs.jsonl: run 1: wall: expected float, got 'long'"],
         files={"runs.jsonl": '{"started": "today", "trials": 3, "wall": "long"}\n'},
         summary="- today: 3 trials on ? in 0.0 min"),
]


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_report_on_rows_it_did_not_write(case: Case, tmp_path, capsys):
    folder = tmp_path / "exp"
    folder.mkdir()
    second = case.second if isinstance(case.second, str) else json.dumps(case.second)
    lines = [json.dumps(_row(0)), second, json.dumps(_row(2))]
    (folder / ROWS_FILE).write_text("\n".join(lines) + "\n")
    for name, text in case.files.items():
        (folder / name).write_text(text)
    before = (folder / ROWS_FILE).read_bytes()
    assert main(["report", str(folder)]) == case.code
    out, err = capsys.readouterr()
    said = [line[len("gbh: "):] for line in err.splitlines()]
    expect = [e.replace("{rows}", str(folder / ROWS_FILE)).replace("{folder}", str(folder))
              for e in case.expect]
    assert len(said) == len(expect) and "Traceback" not in err, err
    for line, words in zip(said, expect, strict=True):
        assert line.startswith(words), (line, words)
    assert (folder / ROWS_FILE).read_bytes() == before
    summary = folder / "summary.md"
    if case.code:
        assert not summary.exists() and not out
    else:  # every row reported
        text = summary.read_text()
        assert case.summary in text
        assert "| gbh-10 " in text and "Rebuilt from `trials.jsonl`" in text
        assert len((folder / "trials.csv").read_text().splitlines()) == 1 + 3


def test_case_ids_are_unique():
    assert len({c.id for c in CASES}) == len(CASES)


def test_many_bad_rows_are_told_a_few_lines_then_counted(tmp_path, capsys):
    """One line per bad row for the first three of a field, then one line with the rest."""
    folder = tmp_path / "exp"
    folder.mkdir()
    rows = [_row(t, grasp_score="high") for t in range(8)]
    (folder / ROWS_FILE).write_text("".join(json.dumps(r) + "\n" for r in rows))
    assert main(["report", str(folder)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert [e.split(": line ")[1].split(":")[0] for e in err[:3]] == ["1", "2", "3"]
    assert err[3] == f"gbh: warning: {folder / ROWS_FILE}: 5 more rows with a bad grasp_score " \
                     "(each read as missing)"
    assert len(err) == 4


def test_the_saved_experiment_is_bounded_before_anything_is_allocated(tmp_path):
    """``trials: 10**18`` with a few objects is refused at once (it was a MemoryError)."""
    from gbh_drake.experiment.report import read_saved_experiment
    from gbh_drake.experiment.rows import FolderError

    path = tmp_path / "experiment.yaml"
    path.write_text("objects: [a, b]\ntrials: 1000000000000000000\nmethods: [{name: m}]\n")
    with pytest.raises(FolderError, match=r"trials: 2 objects x 1000000000000000000 trials"):
        read_saved_experiment(path)
    path.write_text("objects: [a, b]\ntrials: 5000\nmethods: [{name: m}]\n")
    assert read_saved_experiment(path)["trials"] == 5000  # 10000 trials: the bound itself
