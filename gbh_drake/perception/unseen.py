"""The unseen space next to a scan (:mod:`gbh_drake.core.unseen`), from a :class:`ScanResult`:
the cells of the scan's region, above the height the scan was cut at (and the views' noise
margin), that neither the fused views nor the first look's side views saw free
(``ScanResult.free_space`` holds both) and that connect to the scanned mesh."""

from __future__ import annotations

import numpy as np

from gbh_drake.core.unseen import UNSEEN_CELL, unseen_cells
from gbh_drake.perception.scan import ScanResult


def scan_unseen(scan: ScanResult, cell: float = UNSEEN_CELL) -> np.ndarray:
    """Centres (m, 3, W) of the unseen cells connected to ``scan``'s mesh (see
    :func:`~gbh_drake.core.unseen.unseen_cells`); empty for an empty scan or one without its
    views' free space or region (a scan made before they were recorded)."""
    if scan.empty or scan.free_space is None or scan.region is None or len(scan.mesh_W.faces) == 0:
        return np.zeros((0, 3))
    free = scan.free_space  # the fused views' and the first look's
    vertices = np.asarray(scan.mesh_W.vertices, dtype=float)

    # From the cut above the table, raised by the views' margin: nearer the table than that no
    # pixel can prove a point free (its depth there is the table's, within the noise margin).
    lower = np.array(scan.region.lower_W, dtype=float)
    margin = max(free.view_margin(v) for v in free.views)
    lower[2] = max(lower[2], float(vertices[:, 2].min()) + margin)
    return unseen_cells(vertices, free.observed_free, lower, scan.region.upper_W, cell)
