"""A Kinect/Primesense-like depth noise model (structured light), applied to a rendered image.

Three effects, after Nguyen, Izadi and Lovell (3DIMPVT 2012) and Khoshelham and Elberink
(Sensors 2012):
- axial Gaussian noise, sigma(z) = sigma_0.4 + k (z - 0.4 m)^2;
- disparity quantisation: the sensor measures disparity ~ 1/z in fixed steps, so depth comes in
  steps of c z^2;
- dropout where the surface is seen at a grazing angle (including silhouette edges), certain at
  90 degrees from the normal.
Lateral noise and the projector's shadow are not modelled. :func:`sensor_depth` adds it and
then rounds to the sensor's output unit (``ScanConfig.depth_unit``: a 16-bit depth image holds
whole millimetres, or tenths), when asked.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.perception.camera import CameraIntrinsics
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.depth import points_C, valid_depth


def viewing_angle(depth: np.ndarray, intrinsics: CameraIntrinsics) -> np.ndarray:
    """Angle (h, w), radians, between each pixel's ray and the surface normal estimated from
    neighbouring pixels; nan where a neighbour is invalid (edges of the measured region)."""
    depth = np.where(valid_depth(depth), depth, np.nan).astype(np.float32)
    p = points_C(depth, intrinsics).astype(np.float32)  # (3, h, w)
    du, dv = np.gradient(p, axis=2), np.gradient(p, axis=1)
    normal = np.stack([du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2],
                       du[0] * dv[1] - du[1] * dv[0]])
    dot = np.abs(np.sum(normal * p, axis=0))
    cos = dot / np.sqrt(np.sum(normal * normal, axis=0) * np.sum(p * p, axis=0))
    return np.arccos(np.clip(cos, 0.0, 1.0))


def add_depth_noise(depth: np.ndarray, intrinsics: CameraIntrinsics, config: ScanConfig,
                    rng: np.random.Generator) -> np.ndarray:
    """A noisy copy of ``depth`` (h, w) float32 (m); dropped pixels become 0 (invalid)."""
    valid = valid_depth(depth)
    z = np.where(valid, depth, 1.0).astype(np.float64)
    # Dropout: probability rising linearly from the grazing threshold to 1 at 90 degrees.
    theta_0 = np.deg2rad(config.noise_grazing_deg)
    angle = np.nan_to_num(viewing_angle(depth, intrinsics), nan=np.pi / 2)
    p_drop = np.clip((angle - theta_0) / max(np.pi / 2 - theta_0, 1e-9), 0.0, 1.0)
    keep = valid & (rng.random(depth.shape) >= p_drop)
    # Axial noise growing with depth squared.
    sigma = config.noise_sigma + config.noise_sigma_quadratic * (z - 0.4) ** 2
    z = z + sigma * rng.standard_normal(depth.shape)
    # Quantised disparity: 1/z in steps of noise_depth_step.
    if config.noise_depth_step > 0:
        step = config.noise_depth_step
        z = 1.0 / (np.maximum(np.round(1.0 / (z * step)), 1.0) * step)
    return np.where(keep, z, 0.0).astype(np.float32)


def sensor_depth(depth: np.ndarray, intrinsics: CameraIntrinsics, config: ScanConfig,
                 rng: np.random.Generator) -> np.ndarray:
    """``depth`` (h, w) float32 (m) as the sensor delivers it: with ``config.noise`` the noise
    model (:func:`add_depth_noise`), then with ``config.depth_unit`` each measured depth in
    whole units (as a 16-bit depth image holds it; 0 and inf stay)."""
    if config.noise:
        depth = add_depth_noise(depth, intrinsics, config, rng)
    if config.depth_unit:
        d = np.asarray(depth, dtype=np.float64)
        with np.errstate(invalid="ignore"):
            measured = np.isfinite(d) & (d > 0)
        depth = np.where(measured, np.round(d / config.depth_unit) * config.depth_unit,
                         d).astype(np.float32)
    return depth
