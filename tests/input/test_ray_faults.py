"""``gbh experiment --ray`` where no cluster answers: ``auto`` without a cluster and an address
where nothing listens are one line naming the address within seconds (exit 2), and a listener
that is not Ray is given up after the connect timeout; progress is printed while Ray starts.
Real subprocesses and real sockets; no trial runs."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from gbh_drake.experiment import engines

pytestmark = pytest.mark.skipif(not engines.ray_installed(), reason="Ray is an optional extra")

SHORT = Path(__file__).parents[1] / "experiment" / "short_experiment.yaml"
#: Runs gbh with a shorter connect timeout (argv[1]) and its other arguments.
GBH = ("import sys\n"
       "from gbh_drake.experiment import engines\n"
       "engines.RAY_CONNECT_TIMEOUT = float(sys.argv[1])\n"
       "from gbh_drake.cli import main\n"
       "sys.exit(main(sys.argv[2:]))\n")


def _gbh(tmp_path, address: str, timeout: float = 30.0) -> tuple[subprocess.CompletedProcess, float]:
    env = {k: v for k, v in os.environ.items() if k != "RAY_ADDRESS"}
    start = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-c", GBH, str(timeout), "experiment", str(SHORT), "--ray", address,
         "--out", str(tmp_path / "e"), "--no-progress"], capture_output=True, text=True,
        env=env, cwd=tmp_path, timeout=120)
    return done, time.monotonic() - start


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _no_traceback(done):
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr, done.stderr


def test_an_address_where_nothing_listens(tmp_path):
    address = f"127.0.0.1:{_closed_port()}"
    done, took = _gbh(tmp_path, address)
    assert done.returncode == 2, done.stderr
    _no_traceback(done)
    assert done.stderr.splitlines()[-1] == (
        f"gbh: cannot use Ray: {address}: nothing listens there (connection refused): is the "
        "cluster's head running (ray start --head)?")
    assert f"ray: connecting to {address} (at most 30 s) ..." in done.stdout
    assert took < 60
    assert not (tmp_path / "e" / "trials.jsonl").exists()


@pytest.mark.parametrize("address", ["nonsense", "127.0.0.1:99999"])
def test_an_address_that_is_not_one(tmp_path, address):
    done, _ = _gbh(tmp_path, address)
    assert done.returncode == 2, done.stderr
    _no_traceback(done)
    assert done.stderr.splitlines()[-1].startswith(f"gbh: cannot use Ray: {address}: not "
                                                   "'local', 'auto' or a cluster's address")


def _a_ray_runs_here() -> bool:
    found = subprocess.run(["pgrep", "-f", "gcs_server"], capture_output=True)
    return found.returncode == 0


@pytest.mark.skipif(_a_ray_runs_here(), reason="a Ray runs on this machine: auto would find it")
def test_auto_without_a_cluster(tmp_path):
    done, took = _gbh(tmp_path, "auto")
    assert done.returncode == 2, done.stderr
    _no_traceback(done)
    assert done.stderr.splitlines()[-1].startswith(
        "gbh: cannot use Ray: auto: no Ray cluster is running on this machine")
    assert took < 60


@pytest.mark.sim
def test_a_listener_that_is_not_ray_is_given_up(tmp_path):
    """Something accepts connections but never answers as Ray: progress lines, then one line
    at the connect timeout (4 s here; 30 s by default)."""
    with socket.socket() as listener:
        listener.bind(("127.0.0.1", 0))
        listener.listen(16)
        address = f"127.0.0.1:{listener.getsockname()[1]}"
        done, took = _gbh(tmp_path, address, timeout=6.0)
    assert done.returncode == 2, done.stderr
    _no_traceback(done)
    assert done.stderr.splitlines()[-1] == (
        f"gbh: cannot use Ray: {address}: something listens there but no Ray cluster answered "
        "within 6 s")
    assert f"ray: still connecting to {address} (5 s) ..." in done.stdout
    assert took < 60
