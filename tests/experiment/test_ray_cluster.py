"""An experiment file that names a Ray cluster (``engine: ray``, ``ray_address``) runs its trials
there: on a cluster of two nodes, both on this machine, its trials run on both nodes and give the
rows local workers give, timing fields aside; the folder's rows resume on local workers.

The cluster is started as docs/ray.md says: ``ray start --head`` at 127.0.0.2 and a second node
(a resource ``second_node`` of its own) at 127.0.0.3, one CPU each, with the environment of a local
Ray (no usage reporting, HTTP to a dead loopback proxy) and token authentication with a token of
this test. Not 127.0.0.1: with ray 2.60 a node at 127.0.0.1 keeps its servers on the loopback but
no second node may join it (docs/ray.md); these nodes' servers listen on every interface, behind
the token, for the test's duration. Every process the cluster started is ended after the test
(not ``ray stop``, which ends every Ray on the machine).

The Ray run is a ``gbh`` process of its own: Ray is never imported into this one, where
``--ray local`` (test_run.py) needs Ray imported after its environment is set (hence no
``pytest.importorskip("ray")``). The short experiment's box by its four methods, one trial each.
"""

import json
import os
import secrets
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import psutil
import pytest
import yaml

from gbh_drake.experiment.engines import LOCAL_RAY_ENV, WORKER_ENV, ray_installed
from gbh_drake.experiment.rows import RowStore, comparable

pytestmark = [pytest.mark.sim,
              pytest.mark.skipif(not ray_installed(), reason="Ray is not installed "
                                                             "(pip install 'gbh_drake[ray]')")]

SHORT = Path(__file__).parent / "short_experiment.yaml"
HEAD, SECOND = "127.0.0.2", "127.0.0.3"
BIN = Path(sys.executable).parent

#: What a driver of the cluster prints: its nodes (address, alive, resources).
NODES = ("import json, ray; ray.init(address={address!r}, log_to_driver=False); "
         "print('nodes:', json.dumps([[n['NodeManagerAddress'], n['Alive'], n['Resources']] "
         "for n in ray.nodes()]))")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("", 0))
        return s.getsockname()[1]


def _run(command: list, env: dict, timeout: float = 120) -> str:
    """``command``'s output (stdout, then stderr); fails the test when it fails."""
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=timeout)
    output = done.stdout + done.stderr
    assert done.returncode == 0, f"{' '.join(map(str, command))}: exit {done.returncode}\n{output}"
    return output


def _cluster_processes(temp: str) -> list[psutil.Process]:
    """The processes of the cluster whose temp dir is ``temp`` (by their command lines), with
    their descendants (Ray's workers)."""
    found = {}
    for p in psutil.process_iter():
        try:
            if p.pid != os.getpid() and any(temp in a for a in p.cmdline()):
                found[p.pid] = p
                found.update((c.pid, c) for c in p.children(recursive=True))
        except psutil.Error:
            continue
    return list(found.values())


def _alive(p: psutil.Process) -> bool:
    try:  # (a raylet's parent is init: an ended one may stay a zombie a moment)
        return p.status() != psutil.STATUS_ZOMBIE
    except psutil.Error:
        return False


def _end(processes: list[psutil.Process], timeout: float = 10) -> None:
    """SIGKILL to ``processes`` (as ``ray stop --force``: the GCS takes 10 s and more to heed a
    SIGTERM), then waits for them to end."""
    for p in processes:
        try:
            p.kill()
        except psutil.Error:
            pass
    deadline = time.monotonic() + timeout
    while any(map(_alive, processes)) and time.monotonic() < deadline:
        time.sleep(0.1)


@pytest.fixture
def cluster():
    """A head at HEAD and a second node at SECOND (resource ``second_node``), 1 CPU each:
    (its address, the environment that reaches it, its temp dir)."""
    temp = tempfile.mkdtemp(prefix="gbhray", dir="/tmp" if os.path.isdir("/tmp") else None)
    address = f"{HEAD}:{_free_port()}"  # (Ray's socket paths must be short: not tmp_path)
    env = {**os.environ, **LOCAL_RAY_ENV, **WORKER_ENV,
           "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "1",  # (LOCAL_RAY_ENV's 0: no second node)
           "RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN": secrets.token_hex(32)}
    env.pop("RAY_ADDRESS", None)
    try:
        _run([BIN / "ray", "start", "--head", "--node-ip-address", HEAD, "--port",
              address.rpartition(":")[2], "--num-cpus", "1", "--include-dashboard", "false",
              "--temp-dir", temp], env)
        _run([BIN / "ray", "start", "--address", address, "--node-ip-address", SECOND,
              "--num-cpus", "1", "--resources", '{"second_node": 1}', "--temp-dir", temp], env)
        yield address, env, temp
    finally:
        _end(_cluster_processes(temp))
        shutil.rmtree(temp, ignore_errors=True)


class WorkerNodes(threading.Thread):
    """The node (its address) of every process the cluster's raylets start, watched until
    :meth:`stop`: a Ray worker ends with its job, before its rows can be read."""

    def __init__(self, temp: str):
        super().__init__(daemon=True)
        self.raylets = {}
        for p in _cluster_processes(temp):
            args = p.cmdline()
            if p.name() == "raylet":
                self.raylets[p] = next(a.split("=", 1)[1] for a in args
                                       if a.startswith("--node_ip_address="))
        self.node_of: dict[int, str] = {}
        self._done = threading.Event()

    def run(self):
        while not self._done.wait(0.2):
            for raylet, node in self.raylets.items():
                try:
                    for child in raylet.children(recursive=True):
                        self.node_of.setdefault(child.pid, node)
                except psutil.Error:
                    continue

    def stop(self):
        self._done.set()
        self.join()


def test_trials_run_on_both_nodes_of_the_cluster_the_file_names(cluster, experiment_rows,
                                                                 tmp_path):
    address, env, temp = cluster
    said = _run([sys.executable, "-c", NODES.format(address=address)], env).splitlines()
    nodes = json.loads(next(line for line in said if line.startswith("nodes: "))[7:])
    assert sorted((ip, alive) for ip, alive, _ in nodes) == [(HEAD, True), (SECOND, True)]
    assert [ip for ip, _, resources in nodes if "second_node" in resources] == [SECOND]

    spec = yaml.safe_load(SHORT.read_text())  # the short experiment's box, one trial
    spec.update(base=str((SHORT.parent / spec["base"]).resolve()), objects=["box"], trials=1,
                replays="none", engine="ray", ray_address=address)
    experiment = tmp_path / "cluster.yaml"
    experiment.write_text(yaml.safe_dump(spec, sort_keys=False))

    watch = WorkerNodes(temp)
    assert sorted(watch.raylets.values()) == [HEAD, SECOND]
    watch.start()
    try:
        printed = _run([BIN / "gbh", "experiment", experiment, "--out", tmp_path / "ray",
                        "--no-progress"], env, timeout=300)
    finally:
        watch.stop()
    assert f"4 to run on Ray ({address})" in printed, printed
    assert f"ray: connected to {address} in " in printed and "; 2 CPUs" in printed, printed
    assert "4 trials run, 0 found done" in printed, printed
    rows = RowStore(tmp_path / "ray").load()
    ran_on = {watch.node_of.get(int(r["worker"].rpartition(":")[2])) for r in rows}
    assert ran_on == {HEAD, SECOND}, (ran_on, watch.node_of)

    # The same trials on local workers (the file's engine overridden): the same rows.
    _, _, local = experiment_rows(experiment, tmp_path / "local", "--workers", "2",
                                       "--set", "engine: local")
    assert len(rows) == len(local) == 4
    assert [comparable(r) for r in rows] == [comparable(r) for r in local]
    # Where the trials ran is not the experiment's definition: its folder resumes anywhere.
    assert (tmp_path / "ray" / "experiment.yaml").read_text() == \
        (tmp_path / "local" / "experiment.yaml").read_text()
    experiment_rows(experiment, tmp_path / "ray", "--set", "engine: local")
    assert RowStore(tmp_path / "ray").load() == rows  # nothing redone
