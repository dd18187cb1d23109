"""The depth noise model: seeded, axial noise growing with depth, quantised, grazing dropout."""

import numpy as np
import pytest

from gbh_drake.perception.camera import CameraIntrinsics
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.noise import add_depth_noise

K = CameraIntrinsics.from_config(ScanConfig(width=160, height=120))


def plane_depth(z0: float, slope: float = 0.0) -> np.ndarray:
    """Depth (h, w) of a plane at z0 (m) on the optical axis, tilted about x_C: z = z0 + slope y."""
    v = np.arange(K.height, dtype=float)[:, None]
    y_over_z = (v - K.cy) / K.fy
    return np.repeat(z0 / (1.0 - slope * y_over_z), K.width, axis=1).astype(np.float32)


def noisy(depth, seed=0, **fields):
    return add_depth_noise(depth, K, ScanConfig(**fields), np.random.default_rng(seed))


def test_same_seed_same_image_other_seed_other_image():
    depth = plane_depth(0.6)
    np.testing.assert_array_equal(noisy(depth, seed=3), noisy(depth, seed=3))
    assert not np.array_equal(noisy(depth, seed=3), noisy(depth, seed=4))


@pytest.mark.parametrize("z0", [0.5, 1.2])
def test_axial_sigma_grows_with_depth_squared(z0):
    out = noisy(plane_depth(z0), noise_depth_step=0.0)
    error = (out - z0)[out > 0]
    expected = 0.0012 + 0.0019 * (z0 - 0.4) ** 2
    assert np.std(error) == pytest.approx(expected, rel=0.1)
    assert abs(np.mean(error)) < 0.1 * expected


def test_disparity_quantisation():
    step = 0.00285
    out = noisy(plane_depth(0.8), noise_depth_step=step)
    disparity_steps = 1.0 / (out[out > 0].astype(np.float64) * step)
    np.testing.assert_allclose(disparity_steps, np.round(disparity_steps), atol=1e-3)


def test_dropout_follows_the_viewing_angle():
    slope, threshold = 2.0, 45.0  # depths stay positive over the image for |slope| < 2.4
    grazing = noisy(plane_depth(0.6, slope), noise_grazing_deg=threshold)
    # The angle between each row's ray (0, y/z, 1) and the plane's normal (0, -slope, 1).
    y_over_z = (np.arange(K.height) - K.cy) / K.fy
    cos = np.abs(1.0 - slope * y_over_z) / np.hypot(1.0, y_over_z) / np.hypot(1.0, slope)
    angle = np.rad2deg(np.arccos(cos))
    expected = np.clip((angle - threshold) / (90.0 - threshold), 0.0, 1.0)
    observed = np.mean(grazing == 0, axis=1)
    np.testing.assert_allclose(observed[1:-1], expected[1:-1], atol=0.15)
    assert np.mean(noisy(plane_depth(0.6)) == 0) < 0.01  # a facing plane keeps its pixels
