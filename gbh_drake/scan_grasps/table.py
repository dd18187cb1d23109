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
