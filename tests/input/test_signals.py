"""Ctrl-C (SIGINT) and SIGTERM at any moment of ``gbh run`` (start-up imports, simulation, scan,
planning, writing the outputs) end the process promptly with exit code 130 / 143 and one line,
no traceback, and no outputs; two runs given one folder at once do not mix their outputs.
Each case is a real subprocess (signal_driver.py marks the moments)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.sim

DRIVER = Path(__file__).with_name("signal_driver.py")
#: Seconds from the signal to the exit: the handler runs as soon as Python regains control
#: (Drake calls back into Python at every simulator step).
PROMPT = 5.0
PICK = "max_time: 20\nsettle_time: 0.1\n"
SETTLE = "task: settle\nsettle_time: 0.05\n"


def _start(moment: str, scenario: Path, out: Path, **env_extra) -> subprocess.Popen:
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONUNBUFFERED="1", **env_extra)
    return subprocess.Popen(
        [sys.executable, str(DRIVER), moment, "run", str(scenario), "--set",
         f"output_dir: {out}"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
        text=True, cwd=scenario.parent)


def _wait_for_mark(proc: subprocess.Popen, moment: str, timeout: float = 300.0) -> list[str]:
    lines, start = [], time.monotonic()
    while time.monotonic() - start < timeout:
        line = proc.stderr.readline()
        if not line:
            break
        lines.append(line)
        if line.strip() == f"MARK {moment}":
            return lines
    proc.kill()
    raise AssertionError(f"no MARK {moment}: {''.join(lines)}")


@pytest.mark.parametrize(("moment", "signum"), [
    ("import", signal.SIGINT),
    ("import", signal.SIGTERM),
    ("simulate", signal.SIGTERM),
    ("scan", signal.SIGINT),
    ("plan", signal.SIGTERM),
    ("commit", signal.SIGINT),
])
def test_signal_ends_the_run_cleanly(moment, signum, tmp_path):
    scenario = tmp_path / "s.yaml"
    scenario.write_text(PICK if moment in ("scan", "plan") else SETTLE)
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.yaml").write_text("an earlier run's summary\n")  # must not survive
    proc = _start(moment, scenario, out)
    _wait_for_mark(proc, moment)
    sent = time.monotonic()
    proc.send_signal(signum)
    try:
        stdout, stderr = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise
    waited = time.monotonic() - sent
    code = 130 if signum == signal.SIGINT else 143
    name = "interrupted (SIGINT)" if signum == signal.SIGINT else "terminated (SIGTERM)"
    assert proc.returncode == code, stderr
    assert "Traceback" not in stderr and "Exception ignored" not in stderr, stderr
    ours = [line for line in stderr.splitlines() if line.startswith("gbh:")]
    assert ours == [f"gbh: {name}; unfinished outputs were discarded"], stderr
    assert stderr.rstrip().splitlines()[-1] == ours[0]
    assert stdout == ""  # no summary printed
    assert waited < PROMPT, f"{waited:.1f} s"
    left = sorted(p.name for p in out.iterdir())
    if moment == "import":  # before the scenario was read: the folder was not touched
        assert left == ["summary.yaml"], left
    else:  # the run had begun: the earlier run's outputs went, none of this run's came
        assert left == [".gbh.lock"], left


def test_two_runs_into_one_folder(tmp_path):
    """While a first run holds the folder, a second one is refused (exit 2, one line); the
    first one's outputs are complete and its own."""
    scenario = tmp_path / "s.yaml"
    scenario.write_text("task: settle\nsettle_time: 0.05\n")
    out = tmp_path / "out"
    go = tmp_path / "go"
    first = _start("commit", scenario, out, GBH_DRIVER_GO=str(go))  # holds the folder...
    _wait_for_mark(first, "commit")  # ...and waits before its commit until "go" exists
    env = dict(os.environ, OMP_NUM_THREADS="1")
    second = subprocess.run([sys.executable, "-m", "gbh_drake.cli", "run", str(scenario),
                             "--set", f"output_dir: {out}\nseed: 5"], capture_output=True,
                            text=True, env=env, cwd=tmp_path, timeout=300)
    assert second.returncode == 2, second.stderr
    assert second.stderr.strip().splitlines()[-1] == (
        f"gbh: cannot write outputs: {out}: another gbh run (process {first.pid}) is writing "
        "into this folder; wait for it to finish or give another output folder (output_dir)")
    go.write_text("")
    stdout, stderr = first.communicate(timeout=120)
    assert first.returncode == 0, stderr
    summary = (out / "summary.yaml").read_text()
    assert "seed: 0" in summary and "seed: 5" not in summary
