"""A static Meshcat page of a :class:`~gbh_drake.scan_grasps.result.GraspsResult` (``gbh grasps
--html``): one self-contained HTML file that opens offline in a browser.

Drawn in B (Meshcat's world) with :mod:`gbh_drake.viz.gbh_meshcat`, as the trials' replays draw
GbH: the scanned object (grey), the hanging structures (red c, black axis v, hit and missed
rays), the ranked grasps (red keypoint lines, the best one's solid model in orange, its flange
frame as axes: x red, y green, z blue), the refused candidates that came closest to passing
(purple), the table (a thin grey slab) and B's own axes at the origin.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from gbh_drake.core.gripper import X_B_link8

#: Length (m) of the drawn frames' axes.
AXIS = 0.05


def grasps_page(result) -> str:
    """The HTML of the page (see the module docstring)."""
    from pydrake.geometry import Box, Rgba
    from pydrake.math import RigidTransform, RotationMatrix

    from gbh_drake.viz.gbh_meshcat import REFUSED, draw_grasps, draw_object, draw_structures
    from gbh_drake.viz.meshcat_server import local_meshcat

    meshcat = local_meshcat()
    scan = result.scan
    if scan is not None and len(scan.mesh_W.faces):
        draw_object(meshcat, scan.mesh_W)
        centre = np.asarray(scan.mesh_W.bounds, dtype=float).mean(axis=0)
    else:
        centre = np.zeros(3)
    draw_structures(meshcat, result.structures)
    as_drawn = [SimpleNamespace(X_WG=g.X_BG, kind=g.kind) for g in result.grasps]
    if as_drawn:
        draw_grasps(meshcat, as_drawn)
        _axes(meshcat, "gbh/best_flange", X_B_link8(result.grasps[0].X_BG))
    refused = [SimpleNamespace(X_WG=g.X_BG, kind=g.kind) for g in result.refused]
    if refused:
        draw_grasps(meshcat, refused, rgba=REFUSED, folder="refused", n_solid=0)
    _axes(meshcat, "gbh/B", np.eye(4))
    table = result.table
    if table is not None:
        R = RotationMatrix.MakeFromOneVector(np.asarray(table.normal_W, dtype=float), 2)
        on_plane = table.point_W(centre) - 0.001 * np.asarray(table.normal_W)
        meshcat.SetObject("gbh/table", Box(0.4, 0.4, 0.002), Rgba(0.8, 0.8, 0.8, 0.5))
        meshcat.SetTransform("gbh/table", RigidTransform(R, on_plane))
    meshcat.SetCameraPose(centre + np.array([0.45, -0.45, 0.35]), centre)
    return meshcat.StaticHtml()


def _axes(meshcat, path: str, X: np.ndarray) -> None:
    """Frame X (4, 4) as three lines: x red, y green, z blue."""
    from pydrake.geometry import Rgba

    colours = (Rgba(0.9, 0.1, 0.1, 1.0), Rgba(0.1, 0.7, 0.2, 1.0), Rgba(0.1, 0.3, 0.9, 1.0))
    origin = X[:3, 3]
    for k, (name, rgba) in enumerate(zip("xyz", colours, strict=True)):
        tip = origin + AXIS * X[:3, k]
        meshcat.SetLine(f"{path}/{name}", np.asfortranarray(np.stack([origin, tip]).T), 4.0, rgba)
