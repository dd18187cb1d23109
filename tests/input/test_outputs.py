"""Output folders: refused before the simulation when they cannot be used, one run at a time,
all outputs or none, no stale outputs of an earlier run; the same for ``gbh objects build``."""

from __future__ import annotations

import errno
import os
import shutil
from collections import namedtuple

import pytest
import yaml

import gbh_drake.trial as trial_module
from gbh_drake import outputs
from gbh_drake.cli import main
from gbh_drake.outputs import LOCK_NAME, OutputError, RunOutputs

SETTLE = "task: settle\nsettle_time: 0.02\n"
OUTPUTS = ("replay.html", "scenario.yaml", "summary.yaml")


def _scenario(tmp_path, extra=""):
    path = tmp_path / "s.yaml"
    path.write_text(SETTLE + extra)
    return path


def _no_simulation(monkeypatch):
    """Any attempt to build the trial fails the test: the error must come before."""
    def forbidden(*args, **kwargs):
        raise AssertionError("the trial was built")
    monkeypatch.setattr(trial_module, "build_trial", forbidden)


def _one_line(capsys, start: str) -> str:
    out, err = capsys.readouterr()
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(start), err
    return err


def _left(folder) -> list[str]:
    return sorted(p.name for p in folder.iterdir()) if folder.exists() else []


@pytest.mark.sim
def test_a_settle_run_writes_its_three_outputs(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {out}"]) == 0
    assert _left(out) == sorted([LOCK_NAME, *OUTPUTS])
    summary = yaml.safe_load((out / "summary.yaml").read_text())
    assert summary["task"] == "settle" and summary["replay"] == str(out / "replay.html")
    assert (out / "replay.html").read_text().rstrip().endswith("</html>")


def test_output_dir_is_a_file_at_run_start(tmp_path, capsys, monkeypatch):
    _no_simulation(monkeypatch)
    (tmp_path / "output").mkdir()
    (tmp_path / "output" / "s").write_text("not a folder")  # the default output/<stem>
    assert main(["run", str(_scenario(tmp_path))]) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {tmp_path / 'output' / 's'}: is a file, "
                      "not a folder")


def test_output_dir_under_a_file(tmp_path, capsys, monkeypatch):
    _no_simulation(monkeypatch)
    (tmp_path / "f").write_text("x")
    assert main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {tmp_path}/f/sub"]) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {tmp_path}/f/sub: cannot create the folder "
                      "(a part of the path is a file)")


def test_output_dir_cannot_be_created(tmp_path, capsys, monkeypatch):
    _no_simulation(monkeypatch)
    assert main(["run", str(_scenario(tmp_path)), "--set", "output_dir: /proc/gbh_out"]) == 2
    _one_line(capsys, "gbh: cannot write outputs: /proc/gbh_out: cannot create the folder")


def test_output_dir_not_writable(tmp_path, capsys, monkeypatch):
    _no_simulation(monkeypatch)
    (tmp_path / "ro").mkdir()
    real_access = os.access
    monkeypatch.setattr(outputs.os, "access",
                        lambda p, mode: False if str(p).endswith("ro") else real_access(p, mode))
    assert main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {tmp_path}/ro"]) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {tmp_path}/ro: the folder is not writable")


def test_read_only_file_system(tmp_path, capsys, monkeypatch):
    """The lock file cannot be created (as on a read-only mount): refused before simulating."""
    _no_simulation(monkeypatch)
    real_open = os.open

    def read_only(path, flags, *args):
        if str(path).endswith(LOCK_NAME):
            raise OSError(errno.EROFS, "Read-only file system")
        return real_open(path, flags, *args)
    monkeypatch.setattr(outputs.os, "open", read_only)
    assert main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {tmp_path}/o"]) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {tmp_path}/o: cannot write in the folder "
                      "(read-only file system)")


def test_full_disk_before_the_run(tmp_path, capsys, monkeypatch):
    _no_simulation(monkeypatch)
    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(outputs.shutil, "disk_usage", lambda p: usage(10**9, 10**9 - 10**6, 10**6))
    assert main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {tmp_path}/o"]) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {tmp_path}/o: only 1.0 MB free on its disk; a "
                      "run needs 64 MB")


@pytest.mark.sim
def test_full_disk_during_the_run_leaves_nothing(tmp_path, capsys, monkeypatch):
    """The disk fills while the outputs are written: a clear error, no partial file, no
    output of the run, no temporary file."""
    out = tmp_path / "o"
    calls = []
    real_fsync = os.fsync

    def fsync(fd):
        calls.append(fd)
        if len(calls) == 2:  # the second output
            raise OSError(errno.ENOSPC, "No space left on device")
        return real_fsync(fd)
    monkeypatch.setattr(outputs.os, "fsync", fsync)
    assert main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {out}"]) == 2
    err = _one_line(capsys, f"gbh: cannot write outputs: {out}/")
    assert "could not write it (no space left on the disk)" in err
    assert _left(out) == [LOCK_NAME]


def test_the_previous_run_stays_whole_when_a_run_fails(tmp_path, monkeypatch):
    """A failed run leaves the previous run's outputs as they were (and clears what a killed
    run left)."""
    out = tmp_path / "o"
    out.mkdir()
    for name in OUTPUTS:
        (out / name).write_text("from an earlier run")
    (out / ".gbh-tmp-99999-summary.yaml").write_text("left by a killed run")

    def boom(*args, **kwargs):
        raise RuntimeError("a bug deep inside")
    monkeypatch.setattr(trial_module, "build_trial", boom)
    with pytest.raises(RuntimeError, match="a bug deep inside"):  # a bug: not an input error
        main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {out}"])
    assert _left(out) == sorted([LOCK_NAME, *OUTPUTS])
    assert all((out / name).read_text() == "from an earlier run" for name in OUTPUTS)


def test_a_commit_replaces_the_whole_previous_run(tmp_path):
    """Committed, the folder holds the new run's outputs only (a previous output the new run
    does not make is gone too), no temporary file."""
    folder = tmp_path / "o"
    folder.mkdir()
    for name in OUTPUTS:
        (folder / name).write_text("old")
    with RunOutputs(folder) as run_outputs:
        for name in OUTPUTS[1:]:
            run_outputs.stage(name, "new")
        run_outputs.commit()
    assert _left(folder) == sorted([LOCK_NAME, *OUTPUTS[1:]])
    assert all((folder / name).read_text() == "new" for name in OUTPUTS[1:])


@pytest.mark.sim
def test_interrupted_run_leaves_nothing(tmp_path, capsys, monkeypatch):
    out = tmp_path / "o"
    real_stage = RunOutputs.stage

    def stage_then_interrupt(self, name, data):
        path = real_stage(self, name, data)
        if name == "scenario.yaml":
            raise KeyboardInterrupt
        return path
    monkeypatch.setattr(RunOutputs, "stage", stage_then_interrupt)
    assert main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {out}"]) == 130
    _one_line(capsys, "gbh: interrupted (SIGINT); unfinished outputs were discarded")
    assert _left(out) == [LOCK_NAME]


def test_interrupt_between_renames_removes_the_renamed(tmp_path):
    folder = tmp_path / "o"
    real_replace = os.replace
    done = []

    def replace(src, dst):
        if done:
            raise KeyboardInterrupt
        done.append(dst)
        return real_replace(src, dst)
    with pytest.raises(KeyboardInterrupt), RunOutputs(folder) as run_outputs:
        for name in OUTPUTS:
            run_outputs.stage(name, "x")
        outputs.os.replace = replace
        try:
            run_outputs.commit()
        finally:
            outputs.os.replace = real_replace
    assert _left(folder) == [LOCK_NAME]


def test_interrupt_between_renames_puts_the_previous_run_back(tmp_path):
    """Interrupted after the previous outputs were moved aside and one new one renamed in: the
    new one is removed, the previous ones are back, whole."""
    folder = tmp_path / "o"
    folder.mkdir()
    for name in OUTPUTS:
        (folder / name).write_text("old")
    real_replace = os.replace
    moved = []

    def replace(src, dst):
        if "previous" not in str(dst) and moved:  # the second new output
            raise KeyboardInterrupt
        if "previous" not in str(dst):
            moved.append(dst)
        return real_replace(src, dst)
    with pytest.raises(KeyboardInterrupt), RunOutputs(folder) as run_outputs:
        for name in OUTPUTS:
            run_outputs.stage(name, "new")
        outputs.os.replace = replace
        try:
            run_outputs.commit()
        finally:
            outputs.os.replace = real_replace
    assert _left(folder) == sorted([LOCK_NAME, *OUTPUTS])
    assert all((folder / name).read_text() == "old" for name in OUTPUTS)


def test_a_second_run_into_a_busy_folder_is_refused(tmp_path, capsys, monkeypatch):
    _no_simulation(monkeypatch)
    out = tmp_path / "o"
    with RunOutputs(out):  # a first run holds the folder
        assert main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {out}"]) == 2
        _one_line(capsys, f"gbh: cannot write outputs: {out}: another gbh run (process "
                          f"{os.getpid()}) is writing into this folder; wait for it to finish or "
                          "give another output folder (output_dir)")
    with RunOutputs(out):  # released: usable again
        pass


def test_lock_is_released_by_a_failed_run(tmp_path):
    folder = tmp_path / "o"
    with pytest.raises(ValueError), RunOutputs(folder):
        raise ValueError("x")
    with RunOutputs(folder):
        pass


# ---- gbh objects build --out ------------------------------------------------------------------


def _small_build(monkeypatch, names=("key_ring", "box"), interrupt_after=None):
    from gbh_drake.modeling import object_set

    real = object_set.build_object_models

    def build(out_dir):
        models = []
        for i, name in enumerate(names):
            if interrupt_after is not None and i == interrupt_after:
                raise KeyboardInterrupt
            models += real(out_dir, [name])
        return models
    monkeypatch.setattr(object_set, "build_object_models", build)


def test_objects_build_writes_and_replaces(tmp_path, capsys, monkeypatch):
    _small_build(monkeypatch)
    out = tmp_path / "models"
    (out / "key_ring").mkdir(parents=True)
    (out / "key_ring" / "old.txt").write_text("old")
    assert main(["objects", "build", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert f"wrote {out}/key_ring/key_ring.sdf" in printed and ".gbh-tmp" not in printed
    assert sorted(p.name for p in (out / "key_ring").iterdir()) == \
        ["ground_truth.yaml", "key_ring.obj", "key_ring.sdf"]
    assert _left(out) == [LOCK_NAME, "box", "key_ring"]


def test_objects_build_interrupted_keeps_the_old_models(tmp_path, capsys, monkeypatch):
    _small_build(monkeypatch, interrupt_after=1)
    out = tmp_path / "models"
    (out / "key_ring").mkdir(parents=True)
    (out / "key_ring" / "old.txt").write_text("old")
    assert main(["objects", "build", "--out", str(out)]) == 130
    _one_line(capsys, "gbh: interrupted (SIGINT)")
    assert _left(out) == [LOCK_NAME, "key_ring"]
    assert _left(out / "key_ring") == ["old.txt"]


@pytest.mark.parametrize("problem", ["file", "under_file", "full"])
def test_objects_build_bad_out(tmp_path, capsys, monkeypatch, problem):
    _small_build(monkeypatch)
    out = tmp_path / "models"
    if problem == "file":
        out.write_text("x")
        expect = f"gbh: cannot write outputs: {out}: is a file, not a folder"
    elif problem == "under_file":
        (tmp_path / "f").write_text("x")
        out = tmp_path / "f" / "models"
        expect = f"gbh: cannot write outputs: {out}: cannot create the folder"
    else:
        usage = namedtuple("usage", "total used free")
        monkeypatch.setattr(outputs.shutil, "disk_usage", lambda p: usage(1, 1, 0))
        expect = f"gbh: cannot write outputs: {out}: only 0.0 MB free"
    assert main(["objects", "build", "--out", str(out)]) == 2
    _one_line(capsys, expect)


def test_objects_build_disk_full_midway(tmp_path, capsys, monkeypatch):
    from gbh_drake.modeling import object_sdf

    _small_build(monkeypatch)
    out = tmp_path / "models"

    def full(self, data):
        raise OSError(errno.ENOSPC, "No space left on device", str(self))
    monkeypatch.setattr(object_sdf.Path, "write_bytes", full)
    assert main(["objects", "build", "--out", str(out)]) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {out}/.gbh-tmp-")
    assert _left(out) == [LOCK_NAME]


def test_diagram_out_is_a_file(tmp_path, capsys):
    (tmp_path / "d").write_text("x")
    assert main(["diagram", "--out", str(tmp_path / "d")]) == 2
    _one_line(capsys, f"gbh: cannot write outputs: {tmp_path / 'd'}: is a file, not a folder")


def test_replace_contents_keeps_old_on_failure(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "x").write_text("old")

    def build(staging):
        (staging / "a").mkdir()
        (staging / "a" / "x").write_text("new")
        raise RuntimeError("fails after writing")
    with pytest.raises(RuntimeError):
        outputs.replace_contents(tmp_path, build)
    assert (tmp_path / "a" / "x").read_text() == "old"
    assert not any(p.name.startswith(".gbh-tmp") for p in tmp_path.iterdir())
    shutil.rmtree(tmp_path / "a")


def test_output_error_is_an_oserror_with_path():
    e = OutputError("/x", "is a file, not a folder")
    assert isinstance(e, OSError) and e.path == "/x" and str(e) == "/x: is a file, not a folder"


# ---- the command line's error handling --------------------------------------------------------


def test_a_bug_is_not_reported_as_bad_input(tmp_path, monkeypatch, capsys):
    """A ValueError from inside the run is a bug: it propagates (Python prints its traceback
    and exits 1), it is not turned into a one-line 'bad input'."""
    def bug(*args, **kwargs):
        raise ValueError("an internal bug")
    monkeypatch.setattr(trial_module, "build_trial", bug)
    with pytest.raises(ValueError, match="an internal bug"):
        main(["run", str(_scenario(tmp_path)), "--set", f"output_dir: {tmp_path}/o"])
    assert capsys.readouterr().err == ""


def test_closed_stdout_is_quiet(tmp_path, monkeypatch):
    """``gbh objects list | head -1``: the reader goes away; no BrokenPipeError traceback."""
    import io
    import sys

    class Closed(io.StringIO):
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def fileno(self):
            return os.open(os.devnull, os.O_WRONLY)
    monkeypatch.setattr(sys, "stdout", Closed())
    from gbh_drake.modeling import object_set
    monkeypatch.setattr(object_set, "describe_object_set", lambda: ["a", "b"])
    assert main(["objects", "list"]) == 141
