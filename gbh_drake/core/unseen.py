"""Where the object may be although no camera saw it: the unseen space next to a scan.

A scan holds only what the cameras saw. Behind the surface a single view measured, the object
may go on (the far half of a teapot, the body of a pot held by its handle); a lift computed
from the scanned points alone then leaves the unseen part dragging on the table. This module
bounds that part from the other side: a point some camera saw through is certainly free
(``core.free_space``), so the object lies within the scanned points and the unseen space
connected to them.

:func:`unseen_cells` samples a box on a grid, keeps the cells no camera saw free, and returns
those of the connected regions (6-connected cells) that touch a scanned point: the object's
inside, the shadows behind it, the pockets under it. It is an upper bound on where material can
be (within the box), not an estimate: with ten views it is little more than the object's inside,
with one view it runs back to where the first look's side views or the table's depth close it.
Pure numpy (and ``scipy.ndimage``), no Drake.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from gbh_drake.core.lazy import lazy_module

ndimage = lazy_module("scipy.ndimage")

#: Grid spacing (m) of the unseen space: two TSDF voxels of the default scan (2.5 mm). A cell's
#: centre lies within half a diagonal (4.3 mm) of any point in it.
UNSEEN_CELL = 0.005
#: At most this many cells: a larger box is sampled more coarsely.
MAX_CELLS = 2_000_000


def unseen_cells(points_W: np.ndarray, observed_free: Callable[[np.ndarray], np.ndarray],
                 lower_W, upper_W, cell: float = UNSEEN_CELL) -> np.ndarray:
    """Centres (m, 3) of the grid cells in the box [``lower_W``, ``upper_W``] (m, W) that no
    camera saw free (``observed_free``: (n, 3) points -> (n,) bool) and that are connected, by
    such cells, to a cell holding one of ``points_W`` (n, 3, the scan). Cells of scan points
    count as unseen. Empty when there are no points in the box or the box is empty."""
    lower = np.asarray(lower_W, dtype=float).reshape(3)
    upper = np.asarray(upper_W, dtype=float).reshape(3)
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    if len(p) == 0 or np.any(upper <= lower):
        return np.zeros((0, 3))
    size = upper - lower
    cell = max(float(cell), float(np.cbrt(np.prod(size) / MAX_CELLS)))
    shape = np.maximum(np.ceil(size / cell).astype(int), 1)
    axes = [lower[i] + cell * (np.arange(shape[i]) + 0.5) for i in range(3)]
    centres = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    unseen = ~np.asarray(observed_free(centres), dtype=bool).reshape(shape)
    index = np.floor((p - lower) / cell).astype(int)
    inside = np.all((index >= 0) & (index < shape), axis=1)
    if not inside.any():
        return np.zeros((0, 3))
    index = index[inside]
    unseen[index[:, 0], index[:, 1], index[:, 2]] = True
    labels, _ = ndimage.label(unseen)
    touched = np.unique(labels[index[:, 0], index[:, 1], index[:, 2]])
    keep = np.isin(labels, touched[touched > 0])
    return centres[keep.reshape(-1)]


def farthest_distance(points_W: np.ndarray, pivot_W) -> float:
    """The largest distance (m) from ``pivot_W`` (3,) to ``points_W`` (n, 3); 0 when empty."""
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    if len(p) == 0:
        return 0.0
    return float(np.linalg.norm(p - np.asarray(pivot_W, dtype=float).reshape(3), axis=1).max())
