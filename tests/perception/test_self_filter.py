"""The self filter (perception/self_filter.py): the robot's own pixels, found by render label,
are not the object's. The case of issue 42: a tote bag right under the hook gripper at the
robot's home pose, whose rods end a centimetre above the bag's handles."""

import numpy as np
import pytest

from gbh_drake.modeling.names import ARM, GRIPPER
from gbh_drake.perception.camera import make_depth_camera
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import scan_object
from gbh_drake.perception.self_filter import robot_labels, robot_masks, without_pixels
from gbh_drake.perception.viewpoints import camera_poses

pytestmark = pytest.mark.sim

XY = (0.47, 0.0)  # under the hand at the home pose (its frame at x = 0.463 m)
TARGET = [*XY, 0.06]


@pytest.fixture(scope="module")
def bag(scene_cache):
    scene = scene_cache("tote_bag", xyz=(*XY, 0.0))
    plant = scene.plant
    labels = robot_labels(scene.query_object, [plant.GetModelInstanceByName(ARM),
                                               plant.GetModelInstanceByName(GRIPPER)])
    return scene, labels


def test_the_robots_labels_are_its_bodies(bag):
    scene, labels = bag
    plant = scene.plant
    robot = [plant.get_body(b) for name in (ARM, GRIPPER)
             for b in plant.GetBodyIndices(plant.GetModelInstanceByName(name))]
    with_geometry = {int(b.index()) for b in robot if plant.GetVisualGeometriesForBody(b)}
    assert labels == with_geometry and int(scene.body.index()) not in labels


def test_the_masks_cover_the_robot_and_spare_the_object(bag):
    scene, labels = bag
    config = ScanConfig()
    camera = make_depth_camera(config)
    X_WCs = camera_poses(config, np.asarray(TARGET), config.distance)
    masks = robot_masks(scene.query_object, camera, X_WCs, labels)
    assert any(m.any() for m in masks) and all(m.shape == (config.height, config.width)
                                               for m in masks)
    depths = [np.full(m.shape, 0.5, dtype=np.float32) for m in masks]
    seen = without_pixels(depths, masks)
    assert all((s[m] == 0).all() and (s[~m] == 0.5).all() for s, m in zip(seen, masks, strict=True))
    assert not any(m.any() for m in robot_masks(scene.query_object, camera, X_WCs, frozenset()))


def test_the_hand_above_the_bag_is_no_longer_fused_into_its_scan(bag):
    """Without the filter the ten views fuse the hand hanging above the bag's handles into its
    scan (17 cm above the bag's top); with it the scan stops at the bag's top, and its free
    space still has the robot's pixels (the rays to the robot's surface crossed free space)."""
    scene, labels = bag
    config = ScanConfig()
    top = scene.mesh_W.vertices[:, 2].max()
    unfiltered = scan_object(scene.query_object, config, TARGET)
    assert unfiltered.mesh_W.vertices[:, 2].max() > top + 0.05
    scan = scan_object(scene.query_object, config, TARGET, robot_labels=labels)
    assert scan.mesh_W.vertices[:, 2].max() < top + 0.005
    assert scan.object_radius < unfiltered.object_radius
    masks = robot_masks(scene.query_object, make_depth_camera(config), scan.X_WCs, labels)
    views = scan.free_space.views[:len(masks)]  # the scan's own views (the first look's follow)
    hand = [np.isfinite(v.depth[m]).mean() for v, m in zip(views, masks, strict=True)
            if m.any()]
    assert hand and max(hand) > 0.9
