"""The Meshcat debug view draws structures, rays and grasps at the expected paths."""

from __future__ import annotations

import numpy as np
import pytest
from gbh_shapes import make_hook

from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.viz.meshcat_server import local_meshcat


@pytest.fixture(scope="module")
def meshcat():
    return local_meshcat()


def test_draws_structures_rays_and_grasps(meshcat):
    from gbh_drake.viz.gbh_meshcat import clear, draw_grasps, draw_object, draw_structures

    mesh = make_hook()
    result = plan_grasps(mesh, GbhParams(ground_clearance=-1.0))  # the hook floats in space
    (s,) = result.structures
    assert 0 < len(s.miss_directions) == s.n_rays - len(s.H)
    np.testing.assert_allclose(s.a, s.miss_directions.mean(0) / np.linalg.norm(
        s.miss_directions.mean(0)))
    draw_object(meshcat, mesh)
    draw_structures(meshcat, result.structures)
    draw_grasps(meshcat, result.ranked, n_solid=2)
    for path in ("gbh/object", "gbh/structures/0/c", "gbh/structures/0/v",
                 "gbh/structures/0/hit_rays", "gbh/structures/0/miss_rays",
                 "gbh/structures/0/hits", "gbh/grasps/0/fingers", "gbh/grasps/1/solid/hand",
                 f"gbh/grasps/{len(result.ranked) - 1}/hand_axis"):
        assert meshcat.HasPath(path), path
    assert not meshcat.HasPath("gbh/grasps/2/solid")
    clear(meshcat)
    assert not meshcat.HasPath("gbh/object")
