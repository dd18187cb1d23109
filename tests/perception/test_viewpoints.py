"""Viewpoint layouts: cameras at the working distance, looking at the target, image upright."""

import numpy as np
import pytest

from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.viewpoints import (
    camera_poses,
    first_look_poses,
    fit_view_distance,
    half_fov,
    look_at,
)

P_WT = np.array([0.55, 0.0, 0.05])


@pytest.mark.parametrize("layout", ["ring", "spiral"])
@pytest.mark.parametrize("num_views", [1, 10])
def test_cameras_look_at_target_from_distance(layout, num_views):
    config = ScanConfig(layout=layout, num_views=num_views, distance=0.45)
    X_WCs = camera_poses(config, P_WT)
    assert len(X_WCs) == num_views
    for X_WC in X_WCs:
        R_WC = X_WC.rotation().matrix()
        to_target = P_WT - X_WC.translation()
        assert np.linalg.norm(to_target) == pytest.approx(0.45)
        np.testing.assert_allclose(R_WC[:, 2], to_target / 0.45, atol=1e-12)  # +z_C at T
        assert abs(R_WC[2, 0]) < 1e-12  # +x_C horizontal: no roll
        assert R_WC[2, 1] < 0  # +y_C (image down) points down in W


def test_single_view_at_azimuth_and_elevation():
    config = ScanConfig(num_views=1, azimuth_deg=180.0, elevation_deg=30.0, distance=0.5)
    (X_WC,) = camera_poses(config, P_WT)
    expected = P_WT + 0.5 * np.array([-np.cos(np.pi / 6), 0.0, np.sin(np.pi / 6)])
    np.testing.assert_allclose(X_WC.translation(), expected, atol=1e-12)


def test_spiral_spreads_views_over_the_band():
    config = ScanConfig(layout="spiral", num_views=10, elevation_deg=30, elevation_max_deg=70)
    p_WC = np.array([X.translation() for X in camera_poses(config, P_WT)]) - P_WT
    elevation = np.rad2deg(np.arcsin(p_WC[:, 2] / np.linalg.norm(p_WC, axis=1)))
    assert elevation.min() > 30 and elevation.max() < 70 and np.ptp(elevation) > 25
    azimuth = np.sort(np.arctan2(p_WC[:, 1], p_WC[:, 0]))
    assert np.diff(azimuth).min() > np.deg2rad(10)  # no two views from the same side


def test_look_at_straight_down_is_defined():
    X_WC = look_at(P_WT + [0, 0, 0.5], P_WT)
    np.testing.assert_allclose(X_WC.rotation().matrix()[:, 2], [0, 0, -1], atol=1e-12)


def test_views_framing_an_object_are_as_near_as_allowed():
    config = ScanConfig(distance=0.5, distance_max=1.0, fov_margin=1.15, fov_y_deg=45.0)
    assert half_fov(config) == pytest.approx(np.deg2rad(22.5))  # 4:3, so vertical is narrower
    assert fit_view_distance(0.05, config) == (0.5, False)  # a mug: the nominal distance
    d, limited = fit_view_distance(0.23, config)  # a tote bag: farther, sphere fits
    assert d == pytest.approx(1.15 * 0.23 / np.sin(np.deg2rad(22.5))) and not limited
    assert fit_view_distance(0.5, config) == (1.0, True)


def test_camera_poses_at_a_given_distance():
    config = ScanConfig(num_views=4)
    for X_WC in camera_poses(config, P_WT, distance=0.7):
        assert np.linalg.norm(X_WC.translation() - P_WT) == pytest.approx(0.7)


def test_first_look_from_the_sides():
    config = ScanConfig(azimuth_deg=180.0, first_look_distance=0.8, first_look_elevation_deg=60)
    poses = first_look_poses(config, P_WT)
    assert len(poses) == 2
    for X_WC, side in zip(poses, (-1.0, 1.0), strict=True):
        offset = X_WC.translation() - P_WT
        assert np.linalg.norm(offset) == pytest.approx(0.8)
        np.testing.assert_allclose(offset / 0.8, [0.0, side * 0.5, np.sin(np.pi / 3)],
                                   atol=1e-12)
        np.testing.assert_allclose(X_WC.rotation().matrix()[:, 2], -offset / 0.8, atol=1e-12)
