"""The table plane: fitted to points, verified against the expected height, or assumed."""

import numpy as np
import pytest

from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.table import TablePlane, fit_table_plane


def table_points(height=0.0, tilt_deg=0.0, noise=0.0, seed=0, n=20000):
    """A 1 m x 1 m table top (tilted about x) with a 10 cm box standing on it."""
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-0.5, 0.5, size=(n, 2)) + [0.5, 0.0]
    t = np.deg2rad(tilt_deg)
    z = height + np.tan(t) * xy[:, 1] + noise * rng.standard_normal(n)
    box = rng.uniform([0.45, -0.05, height], [0.55, 0.05, height + 0.1], size=(n // 10, 3))
    return np.vstack([np.column_stack([xy, z]), box])


def test_expected_table_is_verified_and_snapped():
    table, warning = fit_table_plane(table_points(noise=0.001), ScanConfig())
    assert warning == "" and table.source == "verified"
    np.testing.assert_array_equal(table.normal_W, [0.0, 0.0, 1.0])
    assert table.height == 0.0


@pytest.mark.parametrize("height", [0.1, -0.05, 0.75])
def test_table_elsewhere_is_fitted(height):
    table, warning = fit_table_plane(table_points(height), ScanConfig())
    assert warning == "" and table.source == "fitted"
    assert table.height == pytest.approx(height, abs=1e-6)
    assert table.normal_W[2] == pytest.approx(1.0)
    assert table.heights(np.array([0.5, 0.2, height + 0.03])) == pytest.approx(0.03, abs=1e-6)


def test_slightly_tilted_table_is_fitted():
    table, _ = fit_table_plane(table_points(0.02, tilt_deg=3.0), ScanConfig())
    assert table.source == "fitted"
    assert np.rad2deg(np.arccos(table.normal_W[2])) == pytest.approx(3.0, abs=0.05)


@pytest.mark.parametrize("points", [np.zeros((0, 3)), table_points(tilt_deg=40.0)])
def test_no_table_in_the_data_is_assumed_with_a_warning(points):
    table, warning = fit_table_plane(points, ScanConfig(table_height=0.02))
    assert table.source == "assumed" and table.height == 0.02
    assert "assuming it at z = 0.020 m" in warning


def test_plane_frame_and_ground():
    table = TablePlane(np.array([0.0, np.sin(0.1), np.cos(0.1)]), 0.3, "fitted")
    e = table.basis()
    np.testing.assert_allclose(e.T @ e, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(e[:, 2], table.normal_W)
    assert table.heights(table.point_W([0.4, 0.2, 1.0])) == pytest.approx(0.0, abs=1e-12)
    normal, height = table.as_ground()
    assert normal == pytest.approx(list(table.normal_W)) and height == 0.3
