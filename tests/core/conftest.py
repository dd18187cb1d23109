"""Fixtures of the GbH core tests: default parameters and the shapes of gbh_shapes."""

from __future__ import annotations

import pytest
import trimesh
from gbh_shapes import make_bottle, make_hook, make_mug, make_ring

from gbh_drake.core.params import GbhParams


@pytest.fixture(scope="session")
def params() -> GbhParams:
    # The test shapes float in space, with no table under them: the supporting-surface check
    # is off here and tested on its own (test_ground.py).
    return GbhParams(ground_clearance=-1.0)


@pytest.fixture(scope="session")
def ring() -> trimesh.Trimesh:
    return make_ring()


@pytest.fixture(scope="session")
def mug() -> trimesh.Trimesh:
    return make_mug()


@pytest.fixture(scope="session")
def hook() -> trimesh.Trimesh:
    return make_hook()


@pytest.fixture(scope="session")
def bottle() -> trimesh.Trimesh:
    return make_bottle()
