"""A scan completed by shape completion (:mod:`gbh_drake.core.completion`), as a scan.

:func:`complete_scan` returns the scan with the completed surface added to its mesh and, as its
free space, a :class:`~gbh_drake.core.completion.CompletedFreeSpace`: the cameras' free space
(eroded as ``CompletionParams.erode`` says: by default not at all) and the completion's
likely-free space, which the GbH core takes as free (the exit proof, the sweep's unknown
space); no hanging contact is taken on the completed surface (``contact_candidates``). The
measured points, the cameras, the region and the table are the scan's. The pick is planned on
the scan as taken (its lift allows for the space no camera saw, not for the completion's guess).
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from gbh_drake.core.completion import CompletedFreeSpace, complete_by_symmetry
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.params import CompletionParams
from gbh_drake.perception.scan import ScanResult

trimesh = lazy_module("trimesh")


def complete_scan(scan: ScanResult, params: CompletionParams | None = None,
                  seed: int = 0) -> ScanResult:
    """``scan`` completed (module docstring); an empty scan, or one without its views' free
    space or region, is returned as it is. ``timing["completion"]`` says how long it took;
    a warning says when nothing was completed (the body of revolution explained too little of
    what was seen). ``seed``: which of the scan's vertices fit the axis (when there are many)."""
    if scan.empty or scan.free_space is None or scan.region is None or \
            len(scan.mesh_W.faces) == 0:
        return scan
    params = params or CompletionParams()
    start = time.perf_counter()
    free = _free_space(scan, params)
    up = np.asarray(scan.table.normal_W if scan.table is not None else (0.0, 0.0, 1.0), float)
    vertices = np.asarray(scan.mesh_W.vertices, dtype=float)
    # As the lift's unseen space: from the cut above the table, raised by the views' margin
    # (nearer the table no pixel proves a point free).
    floor = float((vertices @ up).min()) + max(free.view_margin(v) for v in free.views)
    completion = complete_by_symmetry(vertices, scan.mesh_W.vertex_normals, scan.p_WQ, free,
                                      scan.region.lower_W, scan.region.upper_W, params,
                                      up_W=up, floor=floor, seed=seed)
    mesh = scan.mesh_W
    warnings = list(scan.warnings)
    if completion is None:
        warnings.append(f"shape completion ({params.method}): the body of revolution explains "
                        f"less than {params.min_explained:g} of what was seen; nothing completed")
    elif len(completion.mesh.faces):
        mesh = trimesh.util.concatenate([scan.mesh_W, completion.mesh])
    timing = dict(scan.timing)
    timing["completion"] = time.perf_counter() - start
    return dataclasses.replace(scan, mesh_W=mesh,
                               free_space=CompletedFreeSpace.of(free, completion),
                               timing=timing, warnings=warnings,
                               X_WCs=list(scan.X_WCs),
                               first_look_X_WCs=list(scan.first_look_X_WCs))


def _free_space(scan: ScanResult, params: CompletionParams):
    """The scan's free space, its views eroded as ``params.erode`` says (``FreeSpace.eroded``;
    ``coarse``: the views whose pixels are wider than ``params.cell`` at the region's centre,
    the first look's, which may see "through" thin walls at their silhouettes)."""
    free = scan.free_space
    if params.erode == "none":
        return free
    if params.erode == "all":
        return free.eroded()
    centre = 0.5 * (np.asarray(scan.region.lower_W) + np.asarray(scan.region.upper_W))
    return free.eroded(coarser_than=(centre, params.cell))
