"""Scan quality against the true mesh: Chamfer distance, coverage, and open through-holes.

Distances are exact point-to-triangle distances (Open3D ``RaycastingScene``) from area-uniform
samples of one surface to the other mesh.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from gbh_drake.core.object_model import raycasting_scene


@dataclass
class ScanQuality:
    """How a scan compares with the truth (both in W)."""

    scan_to_truth_mm: float
    """Mean distance from the scan's surface to the true surface (accuracy), mm."""
    truth_to_scan_mm: float
    """Mean distance from the observable true surface to the scan (completeness), mm."""
    chamfer_mm: float
    """Mean of the two directions, mm."""
    coverage: float
    """Fraction of the observable true surface within ``tolerance`` of the scan."""
    tolerance_mm: float


def distances_to_mesh(p_WQ: np.ndarray, mesh: trimesh.Trimesh) -> np.ndarray:
    """Unsigned distance (n,) in metres from each point p_WQ (n, 3) to the surface of ``mesh``."""
    from gbh_drake.core.o3d import open3d
    o3d = open3d()  # lazy: see gbh_drake.core.o3d
    query = o3d.core.Tensor(np.asarray(p_WQ, dtype=np.float32))
    return raycasting_scene(mesh).compute_distance(query).numpy().astype(np.float64)


def sample_surface(mesh: trimesh.Trimesh, count: int, seed: int) -> np.ndarray:
    """``count`` points (count, 3) spread uniformly by area over ``mesh`` (seeded)."""
    points, _ = trimesh.sample.sample_surface(mesh, count, seed=seed)
    return np.asarray(points)


def compare_scan(scan_W: trimesh.Trimesh, truth_W: trimesh.Trimesh, *, z_min: float,
                 tolerance: float = 0.003, num_samples: int = 20000, seed: int = 0
                 ) -> ScanQuality:
    """Compares the scan with the true mesh, both in W (m).

    Only the true surface above ``z_min`` (the scan's floor, e.g. ``crop_z_min``) counts as
    observable: the part on the table cannot be scanned. An empty scan has infinite distances
    and zero coverage."""
    truth_samples = sample_surface(truth_W, num_samples, seed)
    truth_samples = truth_samples[truth_samples[:, 2] >= z_min]
    if len(scan_W.faces) == 0:
        return ScanQuality(np.inf, np.inf, np.inf, 0.0, 1e3 * tolerance)
    d_truth = distances_to_mesh(truth_samples, scan_W)
    d_scan = distances_to_mesh(sample_surface(scan_W, num_samples, seed + 1), truth_W)
    a, b = 1e3 * d_scan.mean(), 1e3 * d_truth.mean()
    return ScanQuality(a, b, 0.5 * (a + b), float(np.mean(d_truth <= tolerance)),
                       1e3 * tolerance)


@dataclass
class HoleCheck:
    """Whether a true hole (centre, axis in W) is still a through-hole of a mesh."""

    open_along_axis: bool
    """Rays along the axis (both ways) through the centre and around it all miss the mesh."""
    surround: float
    """Fraction of rays from the centre across the axis that hit the mesh within reach."""
    through: bool
    """Open along the axis and enclosed (surround >= the required fraction)."""


def check_through_hole(mesh_W: trimesh.Trimesh, center_W, axis_W, *, radius: float = 0.003,
                       reach: float = 0.05, min_surround: float = 0.75, num_angles: int = 16
                       ) -> HoleCheck:
    """Whether the hole at ``center_W`` (m) along ``axis_W`` is a through-hole of ``mesh_W``.

    Open: a rod of ``radius`` (m) fits, i.e. rays from the centre and from rings of radius and
    radius / 2 around it, cast both ways along the axis, all miss. Enclosed: at least
    ``min_surround`` of the rays from the centre across the axis hit the mesh within ``reach``
    (m), so that a missing handle does not count as an open one."""
    from gbh_drake.core.o3d import open3d
    o3d = open3d()  # lazy: see gbh_drake.core.o3d
    axis = np.asarray(axis_W, dtype=float)
    axis = axis / np.linalg.norm(axis)
    e1 = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    phi = 2.0 * np.pi * np.arange(num_angles) / num_angles
    across = np.outer(np.cos(phi), e1) + np.outer(np.sin(phi), np.cross(axis, e1))
    center = np.asarray(center_W, dtype=float)
    origins = center + np.vstack([np.zeros(3), radius * across, 0.5 * radius * across])
    along = np.vstack([np.hstack([origins, np.tile(s * axis, (len(origins), 1))])
                       for s in (1.0, -1.0)])
    rays = np.vstack([along, np.hstack([np.tile(center, (num_angles, 1)), across])])
    if len(mesh_W.faces) == 0:
        return HoleCheck(True, 0.0, False)
    t_hit = raycasting_scene(mesh_W).cast_rays(
        o3d.core.Tensor(rays.astype(np.float32)))["t_hit"].numpy()
    is_open = bool(np.all(np.isinf(t_hit[:len(along)])))
    surround = float(np.mean(t_hit[len(along):] <= reach))
    return HoleCheck(is_open, surround, is_open and surround >= min_surround)
