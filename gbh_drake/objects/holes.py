"""Measure a hole of a mesh seen along an axis: its clear diameter and best centre (metres).

A hole admits a rod along ``axis`` exactly where a line parallel to ``axis`` misses the whole
object, i.e. outside the object's *silhouette* projected along ``axis``. The clear diameter at a
point is twice its distance to the silhouette. Works for any triangle mesh (watertight or not).
"""

from __future__ import annotations

import numpy as np
import trimesh
from manifold3d import CrossSection, FillRule


def plane_basis(axis) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors ``(e1, e2)`` spanning the plane normal to ``axis``, right-handed
    (``e1 x e2 = axis``) and chosen deterministically."""
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    helper = np.array([0.0, 0.0, 1.0]) if abs(a[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = np.cross(helper, a)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(a, e1)


def silhouette(mesh: trimesh.Trimesh, axis) -> list[np.ndarray]:
    """The outline of ``mesh`` projected along ``axis``: polygons ``(k, 2)`` in ``(e1, e2)``
    coordinates of :func:`plane_basis` (outer boundaries and holes alike)."""
    e1, e2 = plane_basis(axis)
    uv = np.asarray(mesh.vertices) @ np.column_stack([e1, e2])
    tri = uv[np.asarray(mesh.faces)]
    a, b = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    area = 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    tri = tri[np.abs(area) > 1e-12]
    area = area[np.abs(area) > 1e-12]
    tri[area < 0] = tri[area < 0][:, ::-1]
    section = CrossSection(list(tri), fillrule=FillRule.Positive)
    return [np.asarray(p, dtype=np.float64) for p in section.to_polygons()]


def _distance_to_polygons(points: np.ndarray, polygons: list[np.ndarray]) -> np.ndarray:
    """Distance of 2-D ``points`` (n, 2) to the boundary of the polygons."""
    seg_a = np.vstack([p for p in polygons])
    seg_b = np.vstack([np.roll(p, -1, axis=0) for p in polygons])
    d = seg_b - seg_a
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-30)
    best = np.full(len(points), np.inf)
    for start in range(0, len(points), 256):
        q = points[start : start + 256, None, :]
        t = np.clip(np.einsum("pij,ij->pi", q - seg_a[None], d) / dd[None], 0.0, 1.0)
        nearest = seg_a[None] + t[..., None] * d[None]
        best[start : start + 256] = np.sqrt(((q - nearest) ** 2).sum(-1)).min(axis=1)
    return best


def _inside(points: np.ndarray, polygons: list[np.ndarray]) -> np.ndarray:
    """Even-odd point-in-polygon test of 2-D ``points`` against all polygons together."""
    inside = np.zeros(len(points), dtype=bool)
    x, y = points[:, 0:1], points[:, 1:2]
    for p in polygons:
        a, b = p, np.roll(p, -1, axis=0)
        crosses = (a[None, :, 1] > y) != (b[None, :, 1] > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_at = a[None, :, 0] + (y - a[None, :, 1]) * (b[None, :, 0] - a[None, :, 0]) / (
                b[None, :, 1] - a[None, :, 1]
            )
        inside ^= (crosses & (x < x_at)).sum(axis=1) % 2 == 1
    return inside


def fit_hole(
    mesh: trimesh.Trimesh, center, axis, search_radius: float = 0.0, steps: int = 15
) -> tuple[np.ndarray, float]:
    """The clear diameter (m) of the hole around ``center`` seen along ``axis``.

    With ``search_radius > 0`` the centre is moved (only across the axis, within that radius) to
    the point farthest from the silhouette, i.e. the centre of the largest rod the hole admits.
    Returns ``(center (3,), clear_diameter)``; the diameter is 0 if the centre is covered.
    """
    center = np.asarray(center, dtype=np.float64)
    e1, e2 = plane_basis(axis)
    polygons = silhouette(mesh, axis)
    c_uv = np.array([center @ e1, center @ e2])
    best_uv, best_r = c_uv, 0.0
    radius = search_radius
    for _ in range(3 if search_radius > 0 else 1):
        g = np.linspace(-radius, radius, steps) if radius > 0 else np.zeros(1)
        cand = best_uv + np.stack(np.meshgrid(g, g, indexing="ij"), -1).reshape(-1, 2)
        cand = np.vstack([best_uv, cand[np.hypot(*(cand - best_uv).T) <= radius + 1e-12]])
        dist = _distance_to_polygons(cand, polygons)
        dist[_inside(cand, polygons)] = 0.0
        k = int(np.argmax(dist))
        if dist[k] > best_r:
            best_uv, best_r = cand[k], float(dist[k])
        radius = 2.0 * radius / (steps - 1)
    shift = (best_uv - c_uv) @ np.vstack([e1, e2])
    return center + shift, 2.0 * best_r
