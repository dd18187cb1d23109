"""``gbh run --meshcat`` keeps its view open after the run until Enter, Ctrl-C or SIGTERM, in
any process (a script without a terminal too), or ``--keep-open SECONDS``; ``--help`` says so."""

from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
import threading
import time

import pytest

from gbh_drake.cli import main
from gbh_drake.viz.meshcat_server import keep_open

SETTLE = "{task: settle, settle_time: 0.05}"


def test_help_says_how_the_live_view_is_left(capsys):
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "keep it open until Enter or Ctrl-C (SIGINT) or SIGTERM (in any process" in text
    assert "--keep-open SECONDS" in text


def test_keep_open_without_meshcat_or_below_zero_is_a_usage_error():
    for argv in (["run", "--keep-open", "3"], ["run", "--meshcat", "--keep-open", "-1"]):
        with pytest.raises(SystemExit) as e:
            main(argv)
        assert e.value.code == 2


def test_enter_on_stdin_or_the_time_ends_it():
    out = io.StringIO()
    assert keep_open("http://x", stdin=io.StringIO("\n"), out=out) == "enter"
    assert "until Enter on stdin, Ctrl-C (SIGINT) or SIGTERM" in out.getvalue()
    start = time.monotonic()
    assert keep_open("http://x", 0.3, stdin=io.StringIO(""), out=out) == "time"
    assert 0.3 <= time.monotonic() - start < 2.0
    assert "for 0.3 s (Ctrl-C ends it sooner)" in out.getvalue()


def test_the_end_of_stdin_waits_for_the_signal():
    """stdin at its end (no terminal, nothing piped) is not Enter: the view stays open until
    the signal (here raised as SIGINT's KeyboardInterrupt, from a timer thread)."""
    # Python keeps SIGINT ignored when it starts so (a job put in the background by a shell
    # without job control): the test's premise, Ctrl-C raising KeyboardInterrupt, is set here.
    handler = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, lambda: signal.raise_signal(signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        assert keep_open("http://x", stdin=io.StringIO(""), out=io.StringIO()) == "signal"
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, handler)
    assert time.monotonic() - start >= 0.5


def _gbh_run(*args: str, stdin=subprocess.DEVNULL) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "gbh_drake.cli", "run", "--meshcat", *args,
                             "--set", SETTLE, "--set", "output_dir: out"],
                            stdin=stdin, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})


def _wait_for_line(process: subprocess.Popen, text: str, timeout: float = 240.0) -> str:
    deadline = time.monotonic() + timeout
    seen = []
    while time.monotonic() < deadline:
        line = process.stdout.readline()
        if not line and process.poll() is not None:
            break
        seen.append(line)
        if text in line:
            return line
    process.kill()
    raise AssertionError(f"no {text!r} in {''.join(seen)}{process.stderr.read()}")


@pytest.mark.sim
@pytest.mark.parametrize("how", ["SIGINT", "SIGTERM", "Enter"])
def test_a_script_without_a_terminal_keeps_the_view_until_a_signal_or_enter(how, tmp_path):
    """Run from a script (stdin not a terminal): the process stays up after the run, its page
    served, until SIGINT, SIGTERM or a line on stdin; then it exits 0 (the run was complete)."""
    process = _gbh_run(stdin=subprocess.PIPE if how == "Enter" else subprocess.DEVNULL)
    line = _wait_for_line(process, "Meshcat stays open at")
    assert "until Enter on stdin, Ctrl-C (SIGINT) or SIGTERM" in line
    time.sleep(1.0)
    assert process.poll() is None, (process.stdout.read(), process.stderr.read())  # still serving
    if how == "Enter":
        process.stdin.write("\n")
        process.stdin.flush()
    else:
        process.send_signal(getattr(signal, how))
    assert process.wait(timeout=30) == 0, process.stderr.read()
    assert (tmp_path / "out" / "replay.html").is_file()


@pytest.mark.sim
def test_keep_open_seconds_then_exits():
    process = _gbh_run("--keep-open", "1.5")
    line = _wait_for_line(process, "Meshcat stays open at")
    assert "for 1.5 s" in line
    start = time.monotonic()
    assert process.wait(timeout=30) == 0, process.stderr.read()
    assert time.monotonic() - start >= 1.0
