"""Output faults of ``gbh run`` and ``gbh experiment``: a folder name too long, stdout on a full
device, ``--out`` naming a file, a folder that cannot be made, a full disk, a lock path that is a
folder, a method name too long for a file name, and a replay that cannot be written (its row is
kept, saying why). Each is one line ``gbh: cannot write outputs: <path>: <reason>`` (or the
experiment file's field and line) and exit 2, or the row written; never a traceback."""

from __future__ import annotations

import errno
import json
import subprocess
import sys
from collections import namedtuple
from pathlib import Path

import pytest

import gbh_drake.trial as trial_module
from gbh_drake import outputs
from gbh_drake.cli import main
from gbh_drake.experiment import runner
from gbh_drake.experiment.rows import ROWS_FILE, RowStore

sys.path.insert(0, str(Path(__file__).parents[1] / "experiment"))
from test_rows_report import make_row  # noqa: E402

SHORT = Path(__file__).parents[1] / "experiment" / "short_experiment.yaml"
SETTLE = "task: settle\nsettle_time: 0.02\n"


@pytest.fixture
def no_trials(monkeypatch):
    """Any trial that starts fails the test: these faults must be found before."""
    def forbidden(*args, **kwargs):
        raise AssertionError("a trial was built")
    monkeypatch.setattr(trial_module, "build_trial", forbidden)
    monkeypatch.setattr(runner, "local_results", forbidden)


def _one_line(capsys, start: str) -> str:
    _, err = capsys.readouterr()
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(start), err
    return err


def _experiment(*args: str) -> int:
    return main(["experiment", str(SHORT), "--workers", "1", "--no-progress", *args])


def test_run_output_folder_name_too_long(tmp_path, capsys, no_trials):
    scenario = tmp_path / "s.yaml"
    scenario.write_text(SETTLE)
    out = tmp_path / ("a" * 300)
    assert main(["run", str(scenario), "--set", f"output_dir: {out}"]) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {out}: cannot be used as a folder (a name in "
                      "the path is too long: at most 255 bytes)")


def test_experiment_out_name_too_long(tmp_path, capsys, no_trials):
    out = tmp_path / ("b" * 300)
    assert _experiment("--out", str(out)) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {out}: cannot be used as a folder")


@pytest.mark.parametrize("command", [["objects", "list"], ["--version"], ["--help"],
                                     ["run", "--help"]])
def test_stdout_on_a_full_device(command):
    """``gbh objects list > /dev/full``: one line, exit 2 (not a traceback at exit); so are
    argparse's ``--help`` and ``--version``, which print and exit inside parse_args, swallowing
    the write error (it is said all the same)."""
    with open("/dev/full", "w") as full:
        done = subprocess.run([sys.executable, "-m", "gbh_drake.cli", *command], stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr
    assert done.stderr.splitlines()[-1] == ("gbh: cannot write outputs: stdout: could not write "
                                            "it (no space left on the disk)")


def test_stdout_write_error_in_process(tmp_path, capsys, monkeypatch):
    import io

    class Full(io.StringIO):
        def write(self, text):
            raise OSError(errno.ENOSPC, "No space left on device")

        def fileno(self):
            return open("/dev/null", "w").fileno()  # noqa: SIM115
    monkeypatch.setattr(sys, "stdout", Full())
    from gbh_drake.modeling import object_set
    monkeypatch.setattr(object_set, "describe_object_set", lambda: ["a", "b"])
    assert main(["objects", "list"]) == 2
    assert capsys.readouterr().err == ("gbh: cannot write outputs: stdout: could not write it "
                                       "(no space left on the disk)\n")


def test_experiment_out_is_a_file(tmp_path, capsys, no_trials):
    out = tmp_path / "f"
    out.write_text("not a folder")
    assert _experiment("--out", str(out)) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {out}: is a file, not a folder")
    assert out.read_text() == "not a folder"


def test_experiment_out_cannot_be_made(tmp_path, capsys, no_trials):
    """As on a read-only mount (/proc refuses new folders even to root)."""
    assert _experiment("--out", "/proc/gbh_experiment") == 2
    _one_line(capsys, "gbh: cannot write outputs: /proc/gbh_experiment: cannot create the folder")


def test_experiment_out_not_writable(tmp_path, capsys, no_trials, monkeypatch):
    """A folder on a read-only mount (root writes anywhere else: os.access says no, as it does
    there)."""
    out = tmp_path / "ro"
    out.mkdir()
    monkeypatch.setattr(outputs.os, "access", lambda p, mode: str(p) != str(out))
    assert _experiment("--out", str(out)) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {out}: the folder is not writable")
    assert list(out.iterdir()) == []


def test_experiment_full_disk_at_start(tmp_path, capsys, no_trials, monkeypatch):
    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(outputs.shutil, "disk_usage", lambda p: usage(10**9, 10**9, 4096))
    out = tmp_path / "e"
    assert _experiment("--out", str(out)) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {out}: only 0.0 MB free on its disk")
    assert list(out.iterdir()) == []


def test_experiment_lock_path_is_a_folder(tmp_path, capsys, no_trials):
    out = tmp_path / "e"
    (out / outputs.LOCK_NAME).mkdir(parents=True)
    assert _experiment("--out", str(out)) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {out / outputs.LOCK_NAME}: is a folder, not "
                      "gbh's lock file; remove it")
    assert [p.name for p in out.iterdir()] == [outputs.LOCK_NAME]


def test_method_name_too_long_for_a_file_name(tmp_path, capsys, no_trials):
    spec = tmp_path / "e.yaml"
    spec.write_text(f"base: {SHORT.parent / '../../scenarios/default.yaml'}\nobjects: [box]\n"
                    f"methods:\n  - {{name: {'m' * 300}}}\n")
    out = tmp_path / "e"
    assert main(["experiment", str(spec), "--out", str(out), "--no-progress"]) == 2
    _one_line(capsys, f"gbh: invalid experiment: {spec}: methods[0].name (line 4): at most 80 "
                      "bytes (it names files")
    assert not out.exists()


# ---- a failure's replay that cannot be written: the row is kept ----------------------------------


def _failed_row():
    row = make_row("mug_classic", "gbh-10", 0, outcome="dropped")
    row["replay"] = ""
    return row


def test_a_replay_on_a_full_disk_keeps_its_row(tmp_path, monkeypatch):
    folder = tmp_path / "e"
    folder.mkdir()
    real_fsync = outputs.os.fsync
    replay_fds = []

    def fsync(fd):
        if Path(f"/proc/self/fd/{fd}").resolve().name.endswith(".html"):
            replay_fds.append(fd)
            raise OSError(errno.ENOSPC, "No space left on device")
        return real_fsync(fd)
    monkeypatch.setattr(outputs.os, "fsync", fsync)
    warned = []
    runner._save(folder, RowStore(folder), _failed_row(), "<html></html>", warn=warned.append)
    assert replay_fds
    rows = RowStore(folder).load()
    assert len(rows) == 1 and rows[0]["replay"] == ""
    assert rows[0]["replay_error"] == (f"{folder}/replays/mug_classic__gbh-10__0.html: could "
                                       "not write it (no space left on the disk)")
    assert len(warned) == 1 and "its replay was not kept" in warned[0]
    assert list((folder / "replays").iterdir()) == []  # no partial replay


def test_a_replay_folder_that_is_a_file_keeps_its_row(tmp_path):
    folder = tmp_path / "e"
    folder.mkdir()
    (folder / "replays").write_text("not a folder")
    warned = []
    runner._save(folder, RowStore(folder), _failed_row(), "<html></html>", warn=warned.append)
    rows = RowStore(folder).load()
    assert len(rows) == 1 and rows[0]["replay"] == "" and "replay_error" in rows[0]


def test_a_replay_written_comes_after_its_row(tmp_path):
    folder = tmp_path / "e"
    folder.mkdir()
    runner._save(folder, RowStore(folder), _failed_row(), "<html></html>", warn=print)
    (row,) = [json.loads(line) for line in (folder / ROWS_FILE).read_text().splitlines()]
    assert row["replay"] == "replays/mug_classic__gbh-10__0.html" and "replay_error" not in row
    assert (folder / row["replay"]).read_text() == "<html></html>"
    assert not list(folder.rglob(".gbh-tmp-*"))


def test_a_row_that_cannot_be_appended_is_one_line(tmp_path):
    folder = tmp_path / "e"
    (folder / ROWS_FILE).mkdir(parents=True)  # the rows' file is a folder
    with pytest.raises(outputs.OutputError, match="could not append the row of trial"):
        runner._save(folder, RowStore(folder), _failed_row(), "<html></html>", warn=print)
    assert not list(folder.rglob(".gbh-tmp-*"))  # the staged replay went with it
