"""Nothing in the package reaches the network: no download URLs, no remote connections."""

import ipaddress
import os
import socket
from pathlib import Path

import pytest

from gbh_drake import MODELS_DIR, REPO_ROOT
from gbh_drake.run import run

# Spelled in pieces so that a plain grep for them over the repository finds only real uses.
FORBIDDEN = ("package://" + "drake_models", "open3d" + ".data", "urllib" + ".request",
             "requests" + ".get", "hf" + "_hub", "from pydrake.all import " + "*")


def test_no_download_in_sources_or_models():
    files = [*(REPO_ROOT / "gbh_drake").rglob("*.py"), *MODELS_DIR.rglob("*.sdf"),
             *MODELS_DIR.rglob("*.urdf"), *(REPO_ROOT / "scenarios").rglob("*.yaml")]
    assert files
    for path in files:
        text = path.read_text()
        for needle in FORBIDDEN:
            assert needle not in text, f"{path} contains {needle!r}"


@pytest.fixture
def no_remote_sockets(monkeypatch):
    """Fails any connection to an address that is not the loopback."""
    real_connect = socket.socket.connect

    def guarded(self, address):
        host = address[0] if isinstance(address, tuple) else None
        if host is not None:
            try:
                loopback = ipaddress.ip_address(host).is_loopback
            except ValueError:
                loopback = host == "localhost"
            if not loopback:
                raise AssertionError(f"network access attempted: {address}")
        return real_connect(self, address)

    monkeypatch.setattr(socket.socket, "connect", guarded)


def _sockets_of_this_process(protocol: str) -> list[tuple[str, int, str]]:
    """(local address hex, port, state hex) of this process's ``tcp`` or ``udp`` sockets (Linux
    /proc; IPv4 and IPv6)."""
    inodes = set()
    for fd in Path("/proc/self/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith("socket:["):
            inodes.add(target[8:-1])
    found = []
    for table in (f"/proc/self/net/{protocol}", f"/proc/self/net/{protocol}6"):
        for line in Path(table).read_text().splitlines()[1:]:
            fields = line.split()
            if fields[9] in inodes:
                address, port = fields[1].split(":")
                found.append((address, int(port, 16), fields[3]))
    return found


LOOPBACK_HEX = {"0100007F", "00000000000000000000000001000000"}  # 127.0.0.1 and ::1 in /proc


def _network_exposure() -> list[str]:
    """UDP sockets (LCM multicast) and TCP listeners not bound to the loopback."""
    udp = [f"udp {a}:{p}" for a, p, _ in _sockets_of_this_process("udp")]
    listening = [f"tcp listen {a}:{p}" for a, p, state in _sockets_of_this_process("tcp")
                 if state == "0A" and a not in LOOPBACK_HEX]
    return udp + listening


@pytest.mark.sim
def test_run_uses_no_network(no_remote_sockets, scenario, staple_mesh):
    """A whole run (pick task) connects nowhere but the loopback, opens no UDP socket (Drake's
    default LCM bus would be UDP multicast) and listens on the loopback only (Meshcat)."""
    scenario.settle_time = 0.05
    scenario.max_time = 0.3  # scan, plan and the first motions
    scenario.object.mesh = "staple.obj"
    staple_mesh.export(scenario.directory / "staple.obj")
    summary = run(scenario)
    assert summary.record.sim_time >= 0.05 and summary.record.n_grasps_offered > 0
    assert _network_exposure() == []


@pytest.mark.sim
def test_cameras_publish_nowhere(scenario):
    """Scenario cameras (CameraConfig) publish to the in-memory bus, not UDP multicast."""
    from pydrake.systems.sensors import CameraConfig

    scenario.cameras = [CameraConfig(name="overhead", fps=10.0)]
    scenario.settle_time = 0.2
    scenario.task = "settle"
    run(scenario)
    assert _network_exposure() == []
