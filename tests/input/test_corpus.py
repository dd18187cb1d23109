"""Every case of the bad-input corpus through the real command line: exit code 2, one line on
stderr naming the file, the field and its line, nothing written (see input_corpus.py)."""


import pytest
from input_corpus import CASES, Case, check_refusal, write_case

from gbh_drake.cli import main


def _write_case(case: Case, folder):
    """The case's files in ``folder`` (``@DIR@`` in a text: that folder)."""
    return write_case(case, folder, {"@DIR@": str(folder)})


def expected_prefix(case: Case, path) -> str:
    origin = f"{path}{case.origin}"
    if not case.field:
        where = f"line {case.line}" if case.line else ""
        return f"gbh: invalid scenario: {origin}: {where}"
    line = f" (line {case.line})" if case.line else ""
    return f"gbh: invalid scenario: {origin}: {case.field}{line}: "


def test_case_ids_are_unique():
    ids = [c.id for c in CASES]
    assert len(ids) == len(set(ids))


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_input(case: Case, tmp_path, capsys):
    path = _write_case(case, tmp_path)
    check_refusal(case, main, ["run", str(path)], capsys, expected_prefix(case, path),
                  tmp_path / "output")


def test_missing_file(tmp_path, capsys):
    assert main(["run", str(tmp_path / "nope.yaml")]) == 2
    assert capsys.readouterr().err == f"gbh: invalid scenario: {tmp_path / 'nope.yaml'}: " \
                                      "scenario file not found\n"


def test_folder_instead_of_file(tmp_path, capsys):
    assert main(["run", str(tmp_path)]) == 2
    assert "is a folder, not a scenario file" in capsys.readouterr().err


def test_fifo_is_not_read(tmp_path, capsys):
    import os

    os.mkfifo(tmp_path / "pipe.yaml")  # reading it would block forever
    assert main(["run", str(tmp_path / "pipe.yaml")]) == 2
    assert "is not a regular file" in capsys.readouterr().err


def test_symlink_loop(tmp_path, capsys):
    (tmp_path / "a.yaml").symlink_to(tmp_path / "b.yaml")
    (tmp_path / "b.yaml").symlink_to(tmp_path / "a.yaml")
    assert main(["run", str(tmp_path / "a.yaml")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"gbh: invalid scenario: {tmp_path / 'a.yaml'}: cannot read") and \
        err.count("\n") == 1


def test_deep_block_nesting(tmp_path, capsys):
    path = tmp_path / "deep.yaml"
    path.write_text("".join("  " * i + "a:\n" for i in range(700)))  # 490 kB
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "nested deeper than 40 levels: not a scenario" in err


def test_unreadable_file(tmp_path, capsys, monkeypatch):
    """A file we may not read (root reads anything: the refusal is simulated)."""
    import pathlib

    path = tmp_path / "secret.yaml"
    path.write_text("seed: 1\n")
    real = pathlib.Path.read_bytes

    def denied(self):
        if self == path:
            raise PermissionError(13, "Permission denied", str(self))
        return real(self)
    monkeypatch.setattr(pathlib.Path, "read_bytes", denied)
    assert main(["run", str(path)]) == 2
    assert capsys.readouterr().err == f"gbh: invalid scenario: {path}: cannot read the " \
                                      "scenario file (Permission denied)\n"


def test_diagram_reports_a_bad_scenario_the_same_way(tmp_path, capsys):
    path = tmp_path / "bad.yaml"
    path.write_text("seed: seven\n")
    assert main(["diagram", str(path), "--out", str(tmp_path / "d")]) == 2
    assert capsys.readouterr().err == f"gbh: invalid scenario: {path}: seed (line 1): expected " \
                                      "an integer, got 'seven'\n"
    assert not (tmp_path / "d").exists()
