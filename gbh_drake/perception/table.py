"""The table top: a plane fitted to the depth data (Open3D RANSAC, then least squares).

The plane is ``normal_W . p = height`` with the unit normal pointing up (+z_W side). The table is
expected horizontal at ``ScanConfig.table_height``; the fit verifies that (and is then snapped to
it, so the default scene stays exact and deterministic) or finds a table elsewhere.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from gbh_drake.perception.config import ScanConfig

if TYPE_CHECKING:
    pass

#: A fitted plane tilted more than this from horizontal is not the table (deg).
MAX_TILT_DEG = 10.0
#: The table must hold at least this fraction of the (downsampled) points it is fitted to.
MIN_INLIER_FRACTION = 0.1
#: Points are thinned to one per cube of this edge (m) before RANSAC.
FIT_VOXEL = 0.005


@dataclass(frozen=True)
class TablePlane:
    """The plane ``normal_W . p = height`` (m) in W; ``normal_W`` (3,) unit, pointing up."""

    normal_W: np.ndarray
    height: float
    source: str = "assumed"
    """``assumed`` (the config's, nothing fitted), ``verified`` (a fit agreed with the config's
    plane, which is used) or ``fitted`` (the fitted plane, elsewhere than expected)."""

    @staticmethod
    def horizontal(height: float, source: str = "assumed") -> TablePlane:
        return TablePlane(np.array([0.0, 0.0, 1.0]), float(height), source)

    def heights(self, p_WQ: np.ndarray) -> np.ndarray:
        """Signed height (...) in m of the points p_WQ (..., 3) above the plane."""
        n = self.normal_W
        return p_WQ[..., 0] * n[0] + p_WQ[..., 1] * n[1] + p_WQ[..., 2] * n[2] - self.height

    def point_W(self, p_WQ) -> np.ndarray:
        """The projection (3,) of the point p_WQ (3,) onto the plane."""
        p = np.asarray(p_WQ, dtype=float)
        return p - self.heights(p) * self.normal_W

    def basis(self) -> np.ndarray:
        """(3, 3) columns e1, e2, n: an orthonormal frame of the plane (e1 along x_W projected)."""
        n = self.normal_W
        e1 = np.array([1.0, 0.0, 0.0]) - n[0] * n
        e1 /= np.linalg.norm(e1)
        return np.column_stack([e1, np.cross(n, e1), n])

    def as_ground(self) -> tuple[list[float], float]:
        """(normal, height) as ``GbhParams.ground_normal`` and ``ground_height`` take them."""
        return [float(v) for v in self.normal_W], float(self.height)


def fit_table_plane(p_WQ: np.ndarray, config: ScanConfig) -> tuple[TablePlane, str]:
    """The table plane from points p_WQ (n, 3) in W, and a warning ("" if none).

    RANSAC (Open3D ``segment_plane``, seeded) on the points thinned to one per ``FIT_VOXEL``
    cube, then refined on the points near it (``_refine``). The largest plane is the
    table if it is within ``MAX_TILT_DEG`` of horizontal, holds ``MIN_INLIER_FRACTION`` of the
    points and has few points below it; otherwise the config's plane is assumed, with a warning.
    A fit within ``table_tolerance`` (and 1 deg) of the config's plane is snapped to it."""
    from gbh_drake.core.o3d import open3d
    o3d = open3d()  # lazy: see gbh_drake.core.o3d
    expected = TablePlane.horizontal(config.table_height)
    if len(p_WQ) < 3:
        return expected, (f"no depth data to find the table: assuming it at z = "
                          f"{config.table_height:.3f} m")
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(
        np.ascontiguousarray(p_WQ, dtype=np.float64))).voxel_down_sample(FIT_VOXEL)
    points = np.asarray(cloud.points)
    fitted = None
    if len(points) >= 3:
        o3d.utility.random.seed(0)
        model, _ = cloud.segment_plane(distance_threshold=2.0 * config.table_tolerance,
                                       ransac_n=3, num_iterations=200)
        normal, offset = _refine(points, np.asarray(model, dtype=float), config.table_tolerance)
        inliers = np.abs(points @ normal - offset) < config.table_tolerance
        below = points @ normal - offset < -3.0 * config.table_tolerance
        tilt = np.rad2deg(np.arccos(min(1.0, normal[2])))
        if (tilt <= MAX_TILT_DEG and inliers.mean() >= MIN_INLIER_FRACTION
                and below.mean() <= 0.5 * inliers.mean()):
            fitted = TablePlane(normal, float(offset), "fitted")
    if fitted is None:
        return expected, (f"no table plane found in the depth data: assuming it at z = "
                          f"{config.table_height:.3f} m")
    # Where the fitted plane meets the vertical through the data's centre, vs the expected.
    centre = points.mean(axis=0)
    tilt = np.rad2deg(np.arccos(min(1.0, fitted.normal_W[2])))
    if abs(fitted.heights(centre) - expected.heights(centre)) <= config.table_tolerance \
            and tilt <= 1.0:
        return TablePlane.horizontal(config.table_height, "verified"), ""
    return fitted, ""


def _refine(points: np.ndarray, model: np.ndarray, tolerance: float) -> tuple[np.ndarray, float]:
    """Least-squares plane (unit normal pointing up, offset) through the points near the RANSAC
    ``model`` (a, b, c, d: a x + b y + c z + d = 0): normal from the SVD of the points within
    2 ``tolerance``, then within ``tolerance``; offset their median (robust to the foot of an
    object standing on the table)."""
    normal = model[:3] / np.linalg.norm(model[:3])
    offset = -model[3] / np.linalg.norm(model[:3])
    for band in (2.0 * tolerance, tolerance, tolerance):
        near = points[np.abs(points @ normal - offset) < band]
        if len(near) < 3:
            break
        _, _, vt = np.linalg.svd(near - near.mean(axis=0), full_matrices=False)
        normal = vt[2] if vt[2][2] >= 0 else -vt[2]
        offset = float(np.median(near @ normal))
    if normal[2] < 0:
        normal, offset = -normal, -offset
    return normal, float(offset)
