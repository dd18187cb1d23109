"""Nothing in the package reaches the network: no download URLs, no remote connections."""

import ipaddress
import os
import socket
from pathlib import Path

import pytest

from gbh_drake import MODELS_DIR, REPO_ROOT
from gbh_drake.run import run
from gbh_drake.station import ObjectAsset

FORBIDDEN = ("package://drake_models", "open3d.data", "urllib.request", "requests.get",
             "hf_hub", "from pydrake.all import *")


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


def _udp_sockets_of_this_process() -> list[tuple[str, int]]:
    """(local address hex, port) of every UDP socket this process holds (Linux /proc)."""
    inodes = set()
    for fd in Path("/proc/self/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith("socket:["):
            inodes.add(target[8:-1])
    found = []
    for table in ("/proc/self/net/udp", "/proc/self/net/udp6"):
        for line in Path(table).read_text().splitlines()[1:]:
            fields = line.split()
            if fields[9] in inodes:
                address, port = fields[1].split(":")
                found.append((address, int(port, 16)))
    return found


def test_run_uses_no_network(no_remote_sockets, scenario, staple_mesh):
    """A whole run (pick task) connects nowhere but the loopback and opens no UDP socket
    (Drake's default LCM bus would be UDP multicast)."""
    scenario.settle_time = 0.05
    asset = ObjectAsset("staple", staple_mesh, 500.0, (0.2, 0.4, 0.8, 1.0), "test")
    summary = run(scenario, object_asset=asset)
    assert summary.sim_time >= 0.05 and summary.pick is not None
    assert _udp_sockets_of_this_process() == []


def test_cameras_publish_nowhere(scenario, staple_mesh):
    """Scenario cameras (CameraConfig) publish to the in-memory bus, not UDP multicast."""
    from pydrake.systems.sensors import CameraConfig

    scenario.cameras = [CameraConfig(name="overhead", fps=10.0)]
    scenario.settle_time = 0.2
    scenario.task = "settle"
    asset = ObjectAsset("staple", staple_mesh, 500.0, (0.2, 0.4, 0.8, 1.0), "test")
    run(scenario, object_asset=asset)
    assert _udp_sockets_of_this_process() == []
