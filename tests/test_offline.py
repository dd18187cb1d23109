"""Nothing in the package reaches the network: no download URLs, no remote connections."""

import ipaddress
import socket

import pytest
from network_sockets import network_exposure

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
    assert network_exposure() == []


@pytest.mark.sim
def test_cameras_publish_nowhere(scenario):
    """Scenario cameras (CameraConfig) publish to the in-memory bus, not UDP multicast."""
    from pydrake.systems.sensors import CameraConfig

    scenario.cameras = [CameraConfig(name="overhead", fps=10.0)]
    scenario.settle_time = 0.2
    scenario.task = "settle"
    run(scenario)
    assert network_exposure() == []
