"""Resume and report on damaged experiment folders: a last line cut short by a killed writer is
dropped with a warning (its trial runs again); any other damage is one line naming the file and
line, exit 2, and nothing already written is lost or changed."""

import json
import sys
from pathlib import Path

import pytest

from gbh_drake.cli import main
from gbh_drake.experiment.rows import ROWS_FILE, FolderError, RowStore, row_key

sys.path.insert(0, str(Path(__file__).parents[1] / "experiment"))
from test_rows_report import make_row  # noqa: E402

SHORT = Path(__file__).parents[1] / "experiment" / "short_experiment.yaml"


def _folder(tmp_path, tail: bytes = b"", middle: bytes | None = None) -> Path:
    folder = tmp_path / "exp"
    folder.mkdir()
    rows = [json.dumps(make_row("box", "gbh-10", t)).encode() for t in range(2)]
    if middle is not None:
        rows.insert(1, middle)
    (folder / ROWS_FILE).write_bytes(b"\n".join(rows) + b"\n" + tail)
    return folder


@pytest.mark.parametrize("middle, words", [
    (b"garbage", "line 2: not a JSON line"),
    (b'{"object": "caf\xe9"}', "line 2: not UTF-8 text (byte 0xe9)"),
    (b"42", "line 2: not a row (a JSON object), got int"),
    (json.dumps({"object": "box", "method": "gbh-10", "trial": 5}).encode(),
     "line 2: a row without seed, outcome, success, reason, viewpoints"),
    (json.dumps(dict(make_row("box", "gbh-10", 5), trial="five")).encode(),
     "line 2: trial is 'five', not an integer"),
])
def test_report_refuses_a_damaged_row_naming_its_line(tmp_path, capsys, middle, words):
    folder = _folder(tmp_path, middle=middle)
    before = (folder / ROWS_FILE).read_bytes()
    assert main(["report", str(folder)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"gbh: damaged experiment folder: {folder / ROWS_FILE}: {words}"), err
    assert (folder / ROWS_FILE).read_bytes() == before
    assert not (folder / "summary.md").exists()


@pytest.mark.parametrize("name, text, words", [
    ("experiment.yaml", b"objects: [\n", "line 2: not valid YAML"),
    ("experiment.yaml", b"objects: 5\n", "objects: expected a list of names, got 5"),
    ("experiment.yaml", b"- a\n", "not a mapping of fields"),
    ("experiment.yaml", b"trials: caf\xe9\n", "not UTF-8 text"),
    ("experiment.yaml", b"methods: [{paper: x}]\n", "methods[0]: expected a method with a name"),
    ("runs.jsonl", b'{"trials": 1}\nnot json\n{"trials": 2}\n', "line 2: not a JSON line"),
    ("runs.jsonl", b"[1, 2]\n", "line 1: not a run (a JSON object)"),
])
def test_report_refuses_a_damaged_definition_or_log(tmp_path, capsys, name, text, words):
    folder = _folder(tmp_path)
    (folder / name).write_bytes(text)
    assert main(["report", str(folder)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"gbh: damaged experiment folder: {folder / name}: {words}"), err
    assert (folder / name).read_bytes() == text and not (folder / "summary.md").exists()


def test_a_cut_last_row_is_left_out_with_a_warning_by_the_report(tmp_path, capsys):
    folder = _folder(tmp_path, tail=b'{"object": "box", "meth')
    before = (folder / ROWS_FILE).read_bytes()
    assert main(["report", str(folder)]) == 0
    err = capsys.readouterr().err
    assert f"gbh: warning: {folder / ROWS_FILE}: line 3 was cut short (an interrupted write)" \
        in err and "Traceback" not in err
    assert (folder / ROWS_FILE).read_bytes() == before  # a report never changes the rows
    assert (folder / "summary.md").is_file()


def test_resume_drops_a_cut_last_row_and_runs_its_trial_again(tmp_path):
    folder = _folder(tmp_path, tail=b'{"object": "box", "method": "gbh-10", "tri')
    warned = []
    rows = RowStore(folder).load(repair=True, warn=warned.append)
    assert [r["trial"] for r in rows] == [0, 1]
    assert warned == [f"{folder / ROWS_FILE}: line 3 was cut short (an interrupted write): "
                      "dropped"]
    assert (folder / ROWS_FILE).read_bytes().endswith(b"}\n")  # the next row has its own line
    assert len(RowStore(folder).load()) == 2


def test_resume_refuses_a_damaged_middle_row_and_runs_nothing(tmp_path, capsys):
    folder = _folder(tmp_path, middle=b"{garbage")
    before = sorted(p.name for p in folder.iterdir()), (folder / ROWS_FILE).read_bytes()
    assert main(["experiment", str(SHORT), "--out", str(folder), "--no-progress"]) == 2
    out, err = capsys.readouterr()
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"gbh: damaged experiment folder: {folder / ROWS_FILE}: line 2: "
                          "not a JSON line"), err
    assert (sorted(p.name for p in folder.iterdir() if p.name != ".gbh.lock"),
            (folder / ROWS_FILE).read_bytes()) == before


@pytest.mark.parametrize("field, value, words", [
    ("protocol", ["stable"], "line 2: protocol is ['stable'], not a string"),
    ("protocol", {"name": "natural"}, "line 2: protocol is {'name': 'natural'}, not a string"),
    ("scenario_digest", 5, "line 2: scenario_digest is 5, not a string"),
    ("replay", ["a.html"], "line 2: replay is ['a.html'], not a string"),
])
def test_resume_refuses_a_row_with_a_field_of_another_type_naming_its_line(
        tmp_path, capsys, field, value, words):
    """A row gbh did not write (a list where the protocol is: the finished-trial set cannot key
    it) is refused before anything runs, naming the file and line; nothing is changed."""
    folder = _folder(tmp_path, middle=json.dumps({**make_row("box", "gbh-10", 5),
                                                  field: value}).encode())
    before = sorted(p.name for p in folder.iterdir()), (folder / ROWS_FILE).read_bytes()
    assert main(["experiment", str(SHORT), "--out", str(folder), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"gbh: damaged experiment folder: {folder / ROWS_FILE}: {words}; the "
                          "file is damaged: fix or remove that line"), err
    assert (sorted(p.name for p in folder.iterdir() if p.name != ".gbh.lock"),
            (folder / ROWS_FILE).read_bytes()) == before


def test_a_row_without_a_protocol_or_with_null_is_stable(tmp_path):
    folder = _folder(tmp_path, middle=json.dumps({**make_row("box", "gbh-10", 5),
                                                  "protocol": None}).encode())
    assert [row_key(r)[3] for r in RowStore(folder).load()] == ["stable"] * 3


def test_the_store_raises_on_damage_not_at_the_end(tmp_path):
    folder = _folder(tmp_path, middle=b"", tail=b"oops\n")  # garbage with its newline: not cut
    with pytest.raises(FolderError, match=r"line 4: not a JSON line"):
        RowStore(folder).load(repair=True)


def test_report_into_a_folder_it_cannot_write(tmp_path, capsys, monkeypatch):
    """A read-only folder (root writes anywhere: the refusal is simulated)."""
    import gbh_drake.experiment.report as report
    from gbh_drake.outputs import OutputError

    folder = _folder(tmp_path)
    before = (folder / ROWS_FILE).read_bytes()

    def denied(path, data):
        raise OutputError(path, "could not write it (read-only file system)")
    monkeypatch.setattr(report, "write_atomically", denied)
    assert main(["report", str(folder)]) == 2
    err = capsys.readouterr().err
    assert err == f"gbh: cannot write outputs: {folder / 'summary.md'}: could not write it " \
                  "(read-only file system)\n"
    assert (folder / ROWS_FILE).read_bytes() == before
