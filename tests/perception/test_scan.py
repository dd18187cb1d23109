"""Scanning the mug beside the robot: 10 views are accurate and keep the handle's hole (GbH finds
it), 1 view is partial, an empty view gives an empty result, noise is deterministic."""

import numpy as np
import pytest

from gbh_drake.perception.camera import CameraIntrinsics, make_depth_camera, render_depth_images
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.depth import valid_points_W
from gbh_drake.perception.quality import check_through_hole, compare_scan
from gbh_drake.perception.scan import ScanResult, scan_depth_images, scan_object
from gbh_drake.perception.viewpoints import camera_poses

pytestmark = pytest.mark.sim


def quality(scene, result: ScanResult, config: ScanConfig):
    return (compare_scan(result.mesh_W, scene.mesh_W, z_min=config.crop_z_min),
            check_through_hole(result.mesh_W, scene.handle_center_W, scene.handle_axis_W))


@pytest.fixture(scope="module")
def ten_views(mug_scene):
    config = ScanConfig(num_views=10)
    return config, scan_object(mug_scene.query_object, config, mug_scene.p_WT)


@pytest.mark.parametrize("scale", [1, 4])
def test_rendered_table_lies_on_z_0(mug_scene, scale):
    """Intrinsics and X_WC agree with Drake's renderer (pixel centres at u + 0.5, v + 0.5): table
    pixels back-project onto z = 0, also in small images, where half a pixel is 1 mm there."""
    config = ScanConfig(num_views=1, width=640 // scale, height=480 // scale)
    (X_WC,) = camera_poses(config, mug_scene.p_WT)
    (depth,) = render_depth_images(mug_scene.query_object, make_depth_camera(config), [X_WC])
    p_WQ, _, _ = valid_points_W(depth, CameraIntrinsics.from_config(config), X_WC)
    on_table = np.abs(p_WQ[:, 2]) < 5e-5
    assert on_table.mean() > 0.5
    assert p_WQ[:, 2].min() > -5e-5  # nothing seen below the table top


def test_ten_views_are_accurate_and_keep_the_handle_open(mug_scene, ten_views):
    config, result = ten_views
    assert not result.empty, result.message
    assert len(result.X_WCs) == 10
    assert len(result.o3d_mesh().triangles) == len(result.mesh_W.faces)
    # Only the mug: no table, no robot (its hand is above the mug), no background.
    np.testing.assert_allclose(result.mesh_W.bounds, mug_scene.mesh_W.bounds, atol=0.004)
    q, hole = quality(mug_scene, result, config)
    assert q.scan_to_truth_mm < 1.5 and q.chamfer_mm < 2.0, q
    assert q.coverage > 0.95, q
    assert hole.through, hole
    assert result.warnings == [] and result.table.source == "verified"
    assert result.cap.capped_regions >= 1 and result.cap.open_holes == 0  # its bottom closed


def test_gbh_finds_the_handle_on_the_scan(mug_scene, ten_views):
    """The GbH core on the scanned mesh: a hanging structure in the handle, along its axis."""
    from gbh_drake.core.pipeline import plan_grasps

    _, result = ten_views
    gbh = plan_grasps(result.mesh_W)
    near = [s for s in gbh.structures
            if np.linalg.norm(s.c - mug_scene.handle_center_W) < 0.015
            and abs(np.dot(s.v, mug_scene.handle_axis_W)) > np.cos(np.deg2rad(25))]
    assert near, [(s.c, s.v) for s in gbh.structures]
    assert len(gbh.ranked) > 0


def test_one_view_is_partial(mug_scene, ten_views):
    config = ScanConfig(num_views=1)
    result = scan_object(mug_scene.query_object, config, mug_scene.p_WT)
    assert not result.empty, result.message
    q1, _ = quality(mug_scene, result, config)
    q10, _ = quality(mug_scene, *ten_views[::-1])
    assert q1.scan_to_truth_mm < 1.5  # what is seen is right ...
    assert q1.coverage < 0.6 and q1.coverage < q10.coverage - 0.3  # ... but half is missing


def test_true_handle_is_a_through_hole_and_a_filled_one_is_not(mug_scene):
    truth = check_through_hole(mug_scene.mesh_W, mug_scene.handle_center_W,
                               mug_scene.handle_axis_W)
    filled = check_through_hole(mug_scene.mesh_W.convex_hull, mug_scene.handle_center_W,
                                mug_scene.handle_axis_W)
    assert truth.through and truth.surround == 1.0
    assert not filled.open_along_axis and not filled.through


def test_target_away_from_the_object_gives_an_empty_scan(mug_scene):
    p_WT = mug_scene.p_WT + [0.0, 0.6, 0.0]  # the cameras look at bare table
    result = scan_object(mug_scene.query_object, ScanConfig(num_views=3), p_WT)
    assert result.empty and len(result.mesh_W.faces) == 0
    assert result.message.startswith("empty scan") and "in view" in result.message


def test_all_invalid_depth_images_give_an_empty_scan(mug_scene):
    config = ScanConfig(num_views=2, width=64, height=48)
    X_WCs = camera_poses(config, mug_scene.p_WT)
    depths = [np.full((48, 64), np.inf, np.float32), np.zeros((48, 64), np.float32)]
    result = scan_depth_images(depths, CameraIntrinsics.from_config(config), X_WCs, config,
                               mug_scene.p_WT)
    assert result.empty and len(result.p_WQ) == 0
    assert "none of the 2 depth images has a valid pixel" in result.message


def test_noisy_scan_is_deterministic_and_still_good(mug_scene):
    config = ScanConfig(num_views=10, noise=True)
    first, second = (scan_object(mug_scene.query_object, config, mug_scene.p_WT, noise_seed=7)
                     for _ in range(2))
    np.testing.assert_array_equal(first.mesh_W.vertices, second.mesh_W.vertices)
    np.testing.assert_array_equal(first.mesh_W.faces, second.mesh_W.faces)
    q, hole = quality(mug_scene, first, config)
    assert q.chamfer_mm < 3.0 and q.coverage > 0.9 and hole.through, (q, hole)
    other = scan_object(mug_scene.query_object, config, mug_scene.p_WT, noise_seed=8)
    assert other.mesh_W.vertices.shape != first.mesh_W.vertices.shape or not np.array_equal(
        other.mesh_W.vertices, first.mesh_W.vertices)


def test_a_copied_scan_shares_its_mesh_but_not_its_lists(ten_views):
    """Drake copies abstract state at every unrestricted update: the copy shares the mesh and
    arrays (a scan is never modified) and owns its lists, so extending one's warnings leaves the
    other's alone; the values are equal."""
    import copy

    from pydrake.common.value import AbstractValue

    _, scan = ten_views
    clone = AbstractValue.Make(scan).Clone().get_value()
    assert clone is not scan
    assert clone.mesh_W is scan.mesh_W and clone.p_WQ is scan.p_WQ
    clone.warnings.append("only on the copy")
    assert "only on the copy" not in scan.warnings
    assert copy.deepcopy(scan).timing == scan.timing
    assert len(clone.X_WCs) == len(scan.X_WCs) == 10


def test_a_view_inside_the_robot_says_so(mug_scene):
    """One view from the robot's side (azimuth 180 deg), far back: its camera lands in the arm's
    elbow at the home pose, so nearly every pixel is nearer than depth_min; the empty scan says
    which view is blocked and where its camera is, instead of asking whether the object is in
    view. (As in the held-out experiment's tote bag, natural trial 0, seed 1.)"""
    config = ScanConfig(num_views=1, aim_views=False, distance=0.9)
    result = scan_object(mug_scene.query_object, config, mug_scene.p_WT)
    assert result.empty, "the view should be blocked by the arm"
    assert "blocked at the lens: view 0 (camera at p_WC" in result.message, result.message
    assert "in view of the cameras" not in result.message
    # A view at the default distance sees the mug: nothing blocked, nothing said.
    assert not scan_object(mug_scene.query_object, ScanConfig(num_views=1, aim_views=False),
                           mug_scene.p_WT).empty


def test_the_empty_bare_table_scan_names_no_blocked_view(mug_scene):
    result = scan_object(mug_scene.query_object, ScanConfig(num_views=3),
                         mug_scene.p_WT + [0.0, 0.6, 0.0])
    assert result.empty and "blocked" not in result.message
