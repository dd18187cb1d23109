"""The table an input is read above: a plane given as (normal, height), or the horizontal
plane under the object's lowest point (a mesh or cloud of the object alone)."""

from __future__ import annotations

import numpy as np


def table_plane(given: tuple[np.ndarray, float] | None, source: str = "given"):
    """A ``TablePlane`` from (normal, height) (its normal pointing up)."""
    from gbh_drake.perception.table import TablePlane

    normal, height = given
    normal = np.asarray(normal, dtype=float)
    normal = normal / np.linalg.norm(normal)
    if normal[2] < 0:
        normal, height = -normal, -height
    return TablePlane(normal, float(height), source)


def under(points: np.ndarray):
    """A horizontal table under the lowest of ``points`` (n, 3)."""
    from gbh_drake.perception.table import TablePlane

    return TablePlane.horizontal(float(points[:, 2].min()), "lowest point")


def plane_text(table) -> str:
    """The plane of ``table`` in words (m, in B): ``z = 0.0000 m`` when horizontal, else
    ``[nx, ny, nz] . p = h m``."""
    n, h = table.normal_W, round(float(table.height), 4) + 0.0  # + 0.0: no -0.0000
    if np.allclose(n, [0.0, 0.0, 1.0]):
        return f"z = {h:.4f} m"
    return f"{(np.round(n, 4) + 0.0).tolist()} . p = {h:.4f} m"


def point_text(p) -> str:
    """The point ``p`` (3,) in words: ``(0.550, 0.000, 0.050) m`` (mm precision, no -0.000)."""
    x, y, z = np.round(np.asarray(p, dtype=float), 3) + 0.0
    return f"({x:.3f}, {y:.3f}, {z:.3f}) m"
