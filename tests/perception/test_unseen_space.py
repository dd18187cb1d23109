"""The unseen space next to a real one-view scan (perception/unseen.py) holds the part of the
object the view did not see: the set's teapot, its far side."""

import numpy as np
import pytest
from scipy import spatial

from gbh_drake.core.unseen import UNSEEN_CELL, farthest_distance
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import scan_object
from gbh_drake.perception.unseen import scan_unseen


@pytest.mark.sim
def test_one_view_of_the_teapot_leaves_its_far_side_in_the_unseen_cells(scene_cache):
    """A real one-view scan: the teapot's surface the view missed lies in the unseen cells (within
    a cell), and their farthest point from its handle is as far as the object's, where the scan's
    own points fall short."""
    scene = scene_cache("teapot", yaw_deg=60.0)
    config = ScanConfig(num_views=1)
    result = scan_object(scene.query_object, config, np.array([0.55, 0.0, 0.06]))
    assert not result.empty, result.message
    # What the cameras saw free: the fused view and the first look's two side views, each at
    # its own margin (the GbH core's through-hole proof and the unseen cells use them all).
    look = result.first_look_free_space
    assert look is not None and len(result.free_space.views) == 1 + len(look.views) == 3
    assert all(v.depth is w.depth and v.margin == look.margin
               for v, w in zip(result.free_space.views[1:], look.views, strict=True))
    assert result.free_space.views[0].margin == result.free_space.margin
    cells = scan_unseen(result)
    assert len(cells)
    floor = float(result.mesh_W.vertices[:, 2].min()) + result.free_space.margin + UNSEEN_CELL
    truth = np.asarray(scene.mesh_W.sample(4000, return_index=False))
    truth = truth[truth[:, 2] > floor]
    known = np.concatenate([cells, result.mesh_W.vertices])
    d, _ = spatial.cKDTree(known).query(truth)
    # A cell's centre is within half its diagonal of any point in it; the first look's small
    # images free a little more near the silhouette.
    assert np.quantile(d, 0.99) < np.sqrt(3) * UNSEEN_CELL, np.quantile(d, [0.5, 0.99, 1.0])
    centre, _, _ = scene.part_W(0)
    scan_reach = farthest_distance(result.mesh_W.vertices, centre)
    true_reach = farthest_distance(scene.mesh_W.vertices, centre)
    assert scan_reach < true_reach - 0.01  # the one view misses the far end
    assert farthest_distance(cells, centre) >= true_reach - UNSEEN_CELL


def test_a_scan_without_a_first_look_has_unseen_space_from_its_views_alone(scene_cache):
    """``aim_views: false``: no first look, the fused views' free space bounds it alone."""
    scene = scene_cache("teapot", yaw_deg=60.0)
    result = scan_object(scene.query_object, ScanConfig(num_views=1, aim_views=False),
                         np.array([0.55, 0.0, 0.06]))
    assert not result.empty and result.first_look_free_space is None
    cells = scan_unseen(result)
    assert len(cells) and cells[:, 2].min() >= result.mesh_W.vertices[:, 2].min()
