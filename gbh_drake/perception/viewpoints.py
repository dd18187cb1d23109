"""Camera viewpoints around the scan target: 1 view, a ring, or a spiral over a hemisphere band.

Camera frame C follows Drake and OpenCV: +z_C along the optical axis, +x_C to the image's
right, +y_C down the image.
"""

from __future__ import annotations

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix

from gbh_drake.core.geometry import GOLDEN_ANGLE
from gbh_drake.perception.config import ScanConfig


def look_at(p_WC, p_WT, up_W=(0.0, 0.0, 1.0)) -> RigidTransform:
    """X_WC of a camera at p_WC (m) looking at p_WT, image up as close to ``up_W`` as possible."""
    p_WC = np.asarray(p_WC, dtype=float)
    z_C = np.asarray(p_WT, dtype=float) - p_WC
    distance = np.linalg.norm(z_C)
    if distance == 0:
        raise ValueError("look_at: camera and target coincide")
    z_C /= distance
    x_C = np.cross(z_C, up_W)
    if np.linalg.norm(x_C) < 1e-9:  # looking along up_W: any right direction will do
        x_C = np.cross(z_C, [1.0, 0.0, 0.0])
    x_C /= np.linalg.norm(x_C)
    y_C = np.cross(z_C, x_C)
    return RigidTransform(RotationMatrix(np.column_stack([x_C, y_C, z_C])), p_WC)


def view_directions(config: ScanConfig) -> np.ndarray:
    """Unit vectors (n, 3) from the target T toward each camera, in W, first at ``azimuth_deg``."""
    n = config.num_views
    i = np.arange(n)
    if config.layout == "ring" or n == 1:
        azimuth = np.deg2rad(config.azimuth_deg) + 2.0 * np.pi * i / n
        elevation = np.full(n, np.deg2rad(config.elevation_deg))
    else:  # spiral: equal areas over the band (uniform in sin(elevation)), golden-angle azimuth
        s = np.sin(np.deg2rad([config.elevation_deg, config.elevation_max_deg]))
        elevation = np.arcsin(s[0] + (s[1] - s[0]) * (i + 0.5) / n)
        azimuth = np.deg2rad(config.azimuth_deg) + GOLDEN_ANGLE * i
    return np.column_stack([np.cos(elevation) * np.cos(azimuth),
                            np.cos(elevation) * np.sin(azimuth),
                            np.sin(elevation)])


def camera_poses(config: ScanConfig, p_WT, distance: float | None = None
                 ) -> list[RigidTransform]:
    """X_WC of every view: at ``distance`` (m; default ``config.distance``) from the point p_WT
    (the target, or the object's centre), looking at it."""
    p_WT = np.asarray(p_WT, dtype=float).reshape(3)
    d = config.distance if distance is None else float(distance)
    return [look_at(p_WT + d * u, p_WT) for u in view_directions(config)]


def first_look_poses(config: ScanConfig, p_WT, distance: float | None = None
                     ) -> list[RigidTransform]:
    """X_WC of the first look's two views: from the sides (azimuth ``azimuth_deg`` +-90 deg, so
    away from the robot, which stands on the side of the first view), at
    ``first_look_elevation_deg``, ``distance`` (m; default ``first_look_distance``) from p_WT."""
    p_WT = np.asarray(p_WT, dtype=float).reshape(3)
    d = config.first_look_distance if distance is None else float(distance)
    elevation = np.deg2rad(config.first_look_elevation_deg)
    poses = []
    for azimuth in np.deg2rad(config.azimuth_deg + np.array([90.0, -90.0])):
        u = [np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
             np.sin(elevation)]
        poses.append(look_at(p_WT + d * np.asarray(u), p_WT))
    return poses


def half_fov(config: ScanConfig) -> float:
    """Half the narrower field of view (rad) of the config's camera (pinhole, square pixels)."""
    half_y = 0.5 * np.deg2rad(config.fov_y_deg)
    half_x = np.arctan(np.tan(half_y) * config.width / config.height)
    return float(min(half_x, half_y))


def fit_view_distance(radius: float, config: ScanConfig) -> tuple[float, bool]:
    """(distance, limited): the camera distance (m) at which a sphere of ``radius`` (m) times
    ``fov_margin`` fits the narrower field of view, at least ``distance`` and at most
    ``distance_max``; ``limited`` when it would need more than ``distance_max``."""
    needed = config.fov_margin * radius / np.sin(half_fov(config))
    return float(np.clip(needed, config.distance, config.distance_max)), bool(
        needed > config.distance_max)
