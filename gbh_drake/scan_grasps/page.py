"""A static Meshcat page of a :class:`~gbh_drake.scan_grasps.result.GraspsResult` (``gbh grasps
--html``): one self-contained HTML file that opens offline in a browser.

Drawn in B (Meshcat's world) with :mod:`gbh_drake.viz.gbh_meshcat`, as the trials' replays and
the studio draw GbH (colours: :mod:`gbh_drake.viz.palette`): the scanned object (translucent
blue), the hanging structures (red c, black axis v, hit and missed rays) and the positions the
detector refused (grey), the ranked grasps (yellow keypoint lines, the best one's solid model in
cyan, its flange frame as axes: x red, y green, z blue), the refused candidates that came
closest to passing (purple), the table (a thin grey slab) and B's own axes at the origin. The
drawing functions are shared: the studio (:mod:`gbh_drake.studio`) draws a trial's result with
them, one grasp at a time (:func:`draw_grasp`).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from gbh_drake.core.gripper import HOOK_GRIPPER, X_B_link8

#: Length (m) of the drawn frames' axes.
AXIS = 0.05


def grasps_page(result) -> str:
    """The HTML of the page (see the module docstring)."""
    from gbh_drake.viz.meshcat_server import local_meshcat

    meshcat = local_meshcat()
    centre = draw_scan(meshcat, result)
    draw_detection(meshcat, result)
    draw_ranked(meshcat, result)
    draw_refused(meshcat, result.refused)
    _axes(meshcat, "gbh/B", np.eye(4))
    meshcat.SetCameraPose(centre + np.array([0.45, -0.45, 0.35]), centre)
    return meshcat.StaticHtml()


def draw_scan(meshcat, result, prefix: str = "gbh") -> np.ndarray:
    """The scanned object and the table under it; returns the scan's centre (3,) (the origin
    without a scan)."""
    from pydrake.geometry import Box, Rgba
    from pydrake.math import RigidTransform, RotationMatrix

    from gbh_drake.viz.gbh_meshcat import draw_object

    scan = result.scan
    if scan is not None and len(scan.mesh_W.faces):
        draw_object(meshcat, scan.mesh_W, prefix)
        centre = np.asarray(scan.mesh_W.bounds, dtype=float).mean(axis=0)
    else:
        centre = np.zeros(3)
    table = result.table
    if table is not None:
        R = RotationMatrix.MakeFromOneVector(np.asarray(table.normal_W, dtype=float), 2)
        on_plane = table.point_W(centre) - 0.001 * np.asarray(table.normal_W)
        meshcat.SetObject(f"{prefix}/table", Box(0.4, 0.4, 0.002), Rgba(0.8, 0.8, 0.8, 0.5))
        meshcat.SetTransform(f"{prefix}/table", RigidTransform(R, on_plane))
    return centre


def draw_detection(meshcat, result, prefix: str = "gbh") -> None:
    """The hanging structures and the positions the detector refused (when it says which)."""
    from gbh_drake.viz.gbh_meshcat import draw_refused_positions, draw_structures

    draw_structures(meshcat, result.structures, prefix)
    if result.hangability is not None and result.hangability.refused:
        draw_refused_positions(meshcat, result.hangability.refused, prefix)


def draw_ranked(meshcat, result, prefix: str = "gbh") -> None:
    """The ranked grasps (keypoint lines), the best one's solid model and flange frame."""
    from gbh_drake.viz.gbh_meshcat import draw_grasps

    as_drawn = [SimpleNamespace(X_WG=g.X_BG, kind=g.kind) for g in result.grasps]
    if as_drawn:
        draw_grasps(meshcat, as_drawn, prefix)
        _axes(meshcat, f"{prefix}/best_flange", X_B_link8(result.grasps[0].X_BG))


def draw_refused(meshcat, refused, prefix: str = "gbh", folder: str = "refused") -> None:
    """Refused grasps (objects with ``X_BG`` or ``X_WG`` and ``kind``), purple lines, under
    ``<prefix>/<folder>``."""
    from gbh_drake.viz.gbh_meshcat import REFUSED, draw_grasps

    as_drawn = [SimpleNamespace(X_WG=g.X_BG if hasattr(g, "X_BG") else g.X_WG, kind=g.kind)
                for g in refused]
    if as_drawn:
        draw_grasps(meshcat, as_drawn, prefix, rgba=REFUSED, folder=folder, n_solid=0)


def draw_grasp(meshcat, grasp, path: str, gripper=HOOK_GRIPPER) -> None:
    """One ranked :class:`~gbh_drake.scan_grasps.result.Grasp` at ``path``: the open gripper at
    the grasp (cyan lines and solid model, ``<path>/open``), the gripper closed where it
    closes (dark cyan, ``<path>/closed``) and the flange frame at the grasp
    (``<path>/flange``)."""
    from gbh_drake.viz.gbh_meshcat import CHOSEN, CLOSED, GRIPPER, draw_gripper

    way = grasp.waypoints
    draw_gripper(meshcat, f"{path}/open", way.grasp, way.q_open, gripper, rgba=CHOSEN,
                 solid_rgba=GRIPPER)
    draw_gripper(meshcat, f"{path}/closed", way.closed, way.q_closed, gripper, rgba=CLOSED)
    _axes(meshcat, f"{path}/flange", X_B_link8(way.grasp))


def _axes(meshcat, path: str, X: np.ndarray) -> None:
    """Frame X (4, 4) as three lines: x red, y green, z blue."""
    from pydrake.geometry import Rgba

    colours = (Rgba(0.9, 0.1, 0.1, 1.0), Rgba(0.1, 0.7, 0.2, 1.0), Rgba(0.1, 0.3, 0.9, 1.0))
    origin = X[:3, 3]
    for k, (name, rgba) in enumerate(zip("xyz", colours, strict=True)):
        tip = origin + AXIS * X[:3, k]
        meshcat.SetLine(f"{path}/{name}", np.asfortranarray(np.stack([origin, tip]).T), 4.0, rgba)
