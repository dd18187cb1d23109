"""Output faults of ``gbh run`` and ``gbh experiment``: a folder name too long, stdout on a full
device, ``--out`` naming a file, a folder that cannot be made, a full disk, a lock path that is a
folder, a method name too long for a file name, and a replay that cannot be written (its row is
kept, saying why). Each is one line ``gbh: cannot write outputs: <path>: <reason>`` (or the
experiment file's field and line) and exit 2, or the row written; never a traceback."""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import subprocess
import sys
from collections import namedtuple
from pathlib import Path

import pytest

import gbh_drake.trial as trial_module
from gbh_drake import outputs
from gbh_drake.cli import main
from gbh_drake.experiment import runner
from gbh_drake.experiment.rows import ROWS_FILE, RowStore, row_key

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


@pytest.fixture
def small_disk(tmp_path):
    """``make(size)``: a tmpfs of ``size`` (e.g. ``"1m"``) mounted on a folder of ``tmp_path``,
    a disk that really fills (root only: skipped where it cannot be mounted)."""
    mounted = []

    def make(size: str) -> Path:
        disk = tmp_path / f"disk{len(mounted)}"
        disk.mkdir()
        if os.geteuid() != 0 or shutil.which("mount") is None:
            pytest.skip("mounting a small tmpfs needs root")
        done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size},mode=0755", "tmpfs",
                               str(disk)], capture_output=True, text=True)
        if done.returncode != 0:
            pytest.skip(f"cannot mount a tmpfs here: {done.stderr.strip()}")
        mounted.append(disk)
        return disk

    yield make
    for disk in mounted:
        subprocess.run(["umount", "-l", str(disk)], check=False)


def fill(disk: Path, leave: int) -> None:
    """Fills ``disk`` until ``leave`` bytes are free (a file of zeros, ``filler``)."""
    free = shutil.disk_usage(disk).free
    with open(disk / "filler", "wb") as f:
        f.write(b"\0" * max(free - leave, 0))


def test_a_replay_that_fills_the_disk_keeps_its_row_and_the_experiment_goes_on(small_disk):
    """On a real 1 MB disk with 100 kB left: the row is written first; the replay (600 kB)
    fails on the full disk with a warning naming it, leaves nothing half-written; the next
    trial's row is written; the final sort says in the row why its replay is not there."""
    folder = small_disk("1m") / "e"
    folder.mkdir()
    fill(folder.parent, 100_000)
    store, warned = RowStore(folder), []
    runner._save(folder, store, _failed_row(), "<html>" + "x" * 600_000 + "</html>",
                 warn=warned.append)
    target = folder / "replays" / "mug_classic__gbh-10__0.html"
    assert warned == [f"gbh: warning: trial ('mug_classic', 'gbh-10', 0, 'stable'): its replay "
                      f"was not kept: {target}: could not write it (no space left on the disk); "
                      "its row is"]
    assert list((folder / "replays").iterdir()) == []  # no partial replay
    row = make_row("mug_classic", "gbh-10", 1)
    runner._save(folder, store, row, None, warn=warned.append)  # the experiment goes on
    rows = store.load()
    assert [r["trial"] for r in rows] == [0, 1] and rows[0]["replay"] == f"replays/{target.name}"
    experiment = runner.Experiment(objects=["mug_classic"], trials=2, methods=[
        runner.Experiment().methods[0]])
    runner._sort_rows(store, experiment)  # an earlier run's row: kept as it is
    assert store.load()[0]["replay"] == f"replays/{target.name}"
    problem = f"{target}: could not write it (no space left on the disk)"
    runner._sort_rows(store, experiment, {row_key(rows[0]): problem})  # this run's: said
    (first, second) = store.load()
    assert first["replay"] == "" and first["replay_error"] == problem
    assert second == row


def test_a_row_that_meets_a_full_disk_leaves_the_file_whole(small_disk):
    """The disk is full to the last byte: the row cannot be appended (one line, that trial
    runs again on resume) and what part of it reached the file is cut off again."""
    folder = small_disk("1m") / "e"
    folder.mkdir()
    store = RowStore(folder)
    store.append(make_row("box", "gbh-10", 0))
    before = store.path.read_bytes()
    fill(folder.parent, 0)
    with open(folder.parent / "filler", "ab", buffering=0) as f:  # every byte left, too
        with contextlib.suppress(OSError):
            while True:
                f.write(b"\0" * 512)
    row = make_row("box", "gbh-10", 1, "dropped")
    row["reason"] = "dropped " * 2000  # longer than the file's last page: part of it is written
    with pytest.raises(outputs.OutputError, match=r"could not append the row of trial .* \(no "
                                                  r"space left on the disk\)"):
        runner._save(folder, store, row, "<html></html>", warn=print)
    assert store.path.read_bytes() == before
    assert not (folder / "replays").exists()


def test_a_replay_folder_that_is_a_file_keeps_its_row(tmp_path):
    folder = tmp_path / "e"
    folder.mkdir()
    (folder / "replays").write_text("not a folder")
    warned = []
    runner._save(folder, RowStore(folder), _failed_row(), "<html></html>", warn=warned.append)
    rows = RowStore(folder).load()
    assert len(rows) == 1 and len(warned) == 1 and "its replay was not kept" in warned[0]


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
    assert not list(folder.rglob(".gbh-tmp-*"))  # no replay is written for a row not kept


@pytest.mark.sim
def test_a_disk_that_fills_in_the_middle_of_an_experiment_loses_no_row(small_disk, capsys):
    """A real experiment (2 short trials, replays kept) on an 80 MB disk that passes the
    free-space check at the start and is then filled to 1.5 MB free, after the start and
    before the first trial ends: each replay (a few MB) fails on the full disk with a warning
    naming its file, every row is kept, the reports are written; a resume on the full disk is
    refused at the start, and once space is freed it finds nothing to run."""
    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.experiment.config import load_experiment
    from gbh_drake.experiment.runner import run_experiment

    disk = small_disk("80m")
    spec = disk.parent / "e.yaml"
    spec.write_text(f"base: {SCENARIOS_DIR / 'default.yaml'}\n"
                    "base_overrides: {max_time: 0.6, settle_time: 0.1}\nobjects: [box]\n"
                    "trials: 2\nreplays: all\nmethods:\n"
                    "  - {name: gbh-1, overrides: {scan: {num_views: 1}}}\n")
    out = disk / "e"

    def log(message: str) -> None:  # said once the folder is checked, before any trial runs
        print(message)
        if "to run on" in message:
            fill(disk, 1_500_000)

    result = run_experiment(load_experiment(spec), out=out, workers=1, progress=False, log=log)
    assert result.complete and result.ran == 2
    warnings = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    rows = RowStore(out).load()
    assert [r["trial"] for r in rows] == [0, 1]
    for row in rows:
        target = out / "replays" / f"box__gbh-1__{row['trial']}.html"
        assert any(f"its replay was not kept: {target}: could not write it (no space left on the "
                   "disk)" in w for w in warnings), warnings
        assert row["replay"] == "" and row["replay_error"] == (f"{target}: could not write it "
                                                               "(no space left on the disk)")
    assert (out / "summary.md").is_file() and not list(out.rglob(".gbh-tmp-*"))
    with pytest.raises(outputs.OutputError, match="MB free on its disk"):  # still full
        run_experiment(load_experiment(spec), out=out, workers=1, progress=False, log=print)
    (disk / "filler").unlink()
    again = run_experiment(load_experiment(spec), out=out, workers=1, progress=False, log=print)
    assert (again.skipped, again.ran) == (2, 0) and RowStore(out).load() == rows
