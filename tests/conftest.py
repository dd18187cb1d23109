"""Shared fixtures: small meshes whose truth is known, and a station-building helper."""

import os

# Open3D's OpenMP threads thrash on a shared 2-core machine: one thread is steadier (and what
# the perception bench measured). Set before anything imports open3d.
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np
import pytest
import trimesh

from gbh_drake.scenario import Scenario


def make_staple(rod_height: float = 0.06, rod_radius: float = 0.006, span: float = 0.14):
    """A horizontal rod on two legs (a 'staple'), frame O: rod along x at z = rod_height."""
    rod = trimesh.creation.cylinder(radius=rod_radius, height=span + 0.02, sections=24)
    rod.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    rod.apply_translation([0, 0, rod_height])
    legs = []
    for x in (-span / 2, span / 2):
        leg = trimesh.creation.box([0.012, 0.03, rod_height + rod_radius])
        leg.apply_translation([x, 0, (rod_height + rod_radius) / 2])
        legs.append(leg)
    return trimesh.boolean.union([rod, *legs], engine="manifold")


@pytest.fixture(autouse=True)
def _work_in_tmp_path(tmp_path, monkeypatch):
    """Every test runs in its own folder, so runs that default to ./output never write into
    the checkout (others may be using it)."""
    monkeypatch.chdir(tmp_path)


@pytest.fixture(autouse=True)
def _methods_registered_by_a_test_stay_in_it(monkeypatch):
    """A method a test registers (register_method, register_spec) is gone after the test, so
    no later test (e.g. the generated errors table) sees it."""
    import sys

    for module, name in (("gbh_drake.method_spec", "_SPECS"), ("gbh_drake.methods", "_REGISTRY")):
        if module in sys.modules:
            table = getattr(sys.modules[module], name)
            monkeypatch.setattr(sys.modules[module], name, dict(table))


@pytest.fixture
def staple_mesh():
    return make_staple()


@pytest.fixture
def scenario(tmp_path) -> Scenario:
    """The default scenario with its output in a temporary folder."""
    s = Scenario()
    s.output_dir = str(tmp_path / "out")
    return s


#: The test files that start a Ray or look for one on this machine (``--ray local``, a cluster,
#: ``--ray auto``): under pytest-xdist they share one worker, one after another, since ``auto``
#: finds any Ray of the machine, a sibling worker's too.
RAY_FILES = ("tests/experiment/test_run.py", "tests/experiment/test_ray_cluster.py",
             "tests/input/test_ray_faults.py")


def pytest_collection_modifyitems(items):
    """A trial is a simulation too: ``-m "not sim"`` leaves out every ``trial`` test."""
    for item in items:
        if item.get_closest_marker("trial") and not item.get_closest_marker("sim"):
            item.add_marker(pytest.mark.sim)


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``./dev.sh test``'s workers (pytest-xdist) take whole test files, as ``--dist loadfile``
    (a file's module fixtures once), and the :data:`RAY_FILES` together as one unit."""
    from xdist.scheduler import LoadFileScheduling

    class FilesAndRay(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            path = nodeid.split("::", 1)[0]
            return "ray" if path in RAY_FILES else path

    return FilesAndRay(config, log)
