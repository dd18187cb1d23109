"""Debug view of the GbH core in Drake's Meshcat, in the style of the paper's Figs. 4-5.

Colours are :mod:`gbh_drake.viz.palette`'s (one home, with the legend that names them):

* the scanned object: a translucent blue mesh;
* structures: hanging position c_i as a red sphere, hanging direction v_i as a black arrow (line
  plus four barbs), hit rays red from c_i to the blue hit points H_i, missed rays green (paper
  Fig. 5a); the positions the detector refused as small grey spheres;
* grasps: the gripper's keypoint polyline (p2-p4-p5-p3-p1 and the hand axis p7-p6) in yellow for
  every ranked grasp, the chosen one in cyan with the solid model's boxes, open or closed
  (darker); refused ones in purple;
* cameras: their frusta (brown; the first look's paler); points (what the cameras did not see,
  magenta; what they saw free, white).

Everything is drawn in the frame the mesh is given in (Meshcat's world). Paths live under
``prefix`` so one call of :func:`clear` removes them.
"""

from __future__ import annotations

import numpy as np
import trimesh
from pydrake.geometry import Box, Meshcat, Rgba, Sphere
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.perception import BaseField, Fields, PointCloud

from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry, keypoints_W
from gbh_drake.core.results import GraspCandidate, HangingStructure, RefusedPosition
from gbh_drake.core.simplify import simplified
from gbh_drake.viz import palette

RED = Rgba(*palette.STRUCTURE)
GREEN = Rgba(*palette.MISSED)
BLUE = Rgba(*palette.CONTACTS)
BLACK = Rgba(*palette.AXIS)
#: The scanned object.
GREY = Rgba(*palette.SCAN)
RANKED = Rgba(*palette.RANKED)
#: The chosen grasp's solid model (open), its lines, and the gripper closed.
GRIPPER = Rgba(*palette.CHOSEN_SOLID)
CHOSEN = Rgba(*palette.CHOSEN)
CLOSED = Rgba(*palette.CLOSED)
#: Refused grasps (the closest to passing, drawn when none passed).
REFUSED = Rgba(*palette.REFUSED)
CAMERA = Rgba(*palette.CAMERA)
FIRST_LOOK = Rgba(*palette.FIRST_LOOK)
UNSEEN = Rgba(*palette.UNSEEN)
FREE = Rgba(*palette.FREE)
REFUSED_POSITION = Rgba(*palette.REFUSED_POSITION)


def clear(meshcat: Meshcat, prefix: str = "gbh") -> None:
    """Remove everything this module drew under ``prefix``."""
    meshcat.Delete(prefix)


def draw_object(meshcat: Meshcat, mesh: trimesh.Trimesh, prefix: str = "gbh",
                max_faces: int = 6000, rgba: Rgba = GREY) -> None:
    """The object mesh (vertices in W, metres) at ``<prefix>/object``, translucent blue,
    simplified to at most ``max_faces`` triangles (a 10-view scan has ~23k: 0.6 MB of every
    saved replay)."""
    mesh = simplified(mesh, max_faces)
    meshcat.SetTriangleMesh(
        f"{prefix}/object",
        np.asfortranarray(np.asarray(mesh.vertices, dtype=float).T),
        np.asfortranarray(np.asarray(mesh.faces, dtype=np.int32).T),
        rgba,
    )


def draw_structures(
    meshcat: Meshcat,
    structures: list[HangingStructure],
    prefix: str = "gbh",
    arrow_length: float = 0.06,
    show_rays: bool = True,
) -> None:
    """Hanging structures: red c_i, black arrow along v_i, red hit / green missed rays, blue H_i.
    Missed rays are drawn ``arrow_length`` long."""
    for i, s in enumerate(structures):
        path = f"{prefix}/structures/{i}"
        meshcat.SetObject(f"{path}/c", Sphere(0.004), RED)
        meshcat.SetTransform(f"{path}/c", RigidTransform(s.c))
        _draw_arrow(meshcat, f"{path}/v", s.c, s.c + arrow_length * s.v, BLACK)
        if not show_rays:
            continue
        if len(s.H):
            _segments(meshcat, f"{path}/hit_rays", s.c, s.H, RED)
            draw_points(meshcat, f"{path}/hits", s.H, BLUE, size=0.004)
        if len(s.miss_directions):
            _segments(meshcat, f"{path}/miss_rays", s.c, s.c + arrow_length * s.miss_directions,
                      GREEN)


def draw_refused_positions(meshcat: Meshcat, refused: list[RefusedPosition],
                           prefix: str = "gbh", arrow_length: float = 0.03) -> None:
    """The hanging positions the detector refused (small grey spheres at c, with the axis it
    found, if any) under ``<prefix>/refused_positions``."""
    for i, r in enumerate(refused):
        path = f"{prefix}/refused_positions/{i}"
        meshcat.SetObject(f"{path}/c", Sphere(0.003), REFUSED_POSITION)
        meshcat.SetTransform(f"{path}/c", RigidTransform(np.asarray(r.c, dtype=float)))
        if r.v is not None:
            c = np.asarray(r.c, dtype=float)
            _segments(meshcat, f"{path}/v", c - arrow_length * r.v, c + arrow_length * r.v,
                      REFUSED_POSITION)


def draw_grasps(
    meshcat: Meshcat,
    grasps: list[GraspCandidate],
    prefix: str = "gbh",
    n_solid: int = 1,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    *,
    rgba: Rgba = RANKED,
    folder: str = "grasps",
    solid_rgba: Rgba = GRIPPER,
) -> None:
    """Grasps X_WG as keypoint polylines of ``rgba`` (open gripper) under
    ``<prefix>/<folder>/<i>``; the first ``n_solid`` also as the solid model's boxes (the model
    N_c is counted against) of ``solid_rgba``."""
    for i, g in enumerate(grasps):
        draw_gripper(meshcat, f"{prefix}/{folder}/{i}", g.X_WG, gripper.q_open, gripper,
                     rgba=rgba, solid_rgba=solid_rgba if i < n_solid else None)


def draw_gripper(meshcat: Meshcat, path: str, X_WG, q: float,
                 gripper: HookGripperGeometry = HOOK_GRIPPER, *, rgba: Rgba = CHOSEN,
                 solid_rgba: Rgba | None = None) -> None:
    """One gripper at X_WG (4, 4) with its fingers at ``q`` (m): its keypoint lines of ``rgba``
    at ``<path>/fingers`` and ``<path>/hand_axis``, and, with ``solid_rgba``, the solid model's
    boxes at ``<path>/solid/<box>``."""
    X_WG = np.asarray(X_WG, dtype=float)
    kp = keypoints_W(X_WG, q, gripper)
    fingers = np.stack([kp[k] for k in ("p2", "p4", "p5", "p3", "p1")])
    meshcat.SetLine(f"{path}/fingers", np.asfortranarray(fingers.T), 3.0, rgba)
    hand = np.stack([kp["p7"], kp["p6"]])
    meshcat.SetLine(f"{path}/hand_axis", np.asfortranarray(hand.T), 3.0, rgba)
    if solid_rgba is None:
        return
    X = RigidTransform(X_WG)
    for b in gripper.solid_boxes_G(q):
        meshcat.SetObject(f"{path}/solid/{b.name}", Box(*b.size), solid_rgba)
        meshcat.SetTransform(f"{path}/solid/{b.name}", X @ RigidTransform(np.asarray(b.center)))


def draw_cameras(meshcat: Meshcat, path: str, X_WCs, intrinsics, *, depth: float = 0.08,
                 rgba: Rgba = CAMERA) -> None:
    """Camera frusta: for each pose X_WC (a RigidTransform or 4 x 4; C: +z along the optical
    axis, +x right, +y down) a pyramid ``depth`` (m) deep over the image of ``intrinsics``
    (``width``, ``height``, ``fx``, ``fy``, ``cx``, ``cy``), with its optical axis, at
    ``<path>/<i>``."""
    w, h = intrinsics.width, intrinsics.height
    corners_C = np.array([[(u - intrinsics.cx) / intrinsics.fx * depth,
                           (v - intrinsics.cy) / intrinsics.fy * depth, depth]
                          for u, v in ((0, 0), (w, 0), (w, h), (0, h))])
    for i, X in enumerate(X_WCs):
        X = X.GetAsMatrix4() if isinstance(X, RigidTransform) else np.asarray(X, dtype=float)
        o = X[:3, 3]
        c = corners_C @ X[:3, :3].T + o
        starts = np.vstack([np.tile(o, (4, 1)), c, o])
        ends = np.vstack([c, np.roll(c, -1, axis=0), o + 1.5 * depth * X[:3, 2]])
        meshcat.SetLineSegments(f"{path}/{i}", np.asfortranarray(starts.T),
                                np.asfortranarray(ends.T), 2.0, rgba)


def draw_points(meshcat: Meshcat, path: str, points: np.ndarray, rgba: Rgba, *,
                size: float = 0.004) -> None:
    """Points (n, 3, m, W) as a point cloud of one colour at ``path``."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    cloud = PointCloud(len(points), Fields(BaseField.kXYZs))
    cloud.mutable_xyzs()[:] = points.T
    meshcat.SetObject(path, cloud, point_size=size, rgba=rgba)


def _segments(meshcat: Meshcat, path: str, start: np.ndarray, end: np.ndarray, rgba: Rgba) -> None:
    """Line segments from ``start`` (3,) or (n, 3) to ``end`` (n, 3)."""
    end = np.atleast_2d(end)
    start = np.broadcast_to(start, end.shape)
    meshcat.SetLineSegments(path, np.asfortranarray(start.T), np.asfortranarray(end.T), 2.0, rgba)


def _draw_arrow(meshcat: Meshcat, path: str, tail: np.ndarray, tip: np.ndarray,
                rgba: Rgba) -> None:
    """An arrow as a shaft and four barbs (line segments)."""
    d = tip - tail
    length = float(np.linalg.norm(d))
    R = RotationMatrix.MakeFromOneVector(d / length, 2).matrix()  # column 2 along d
    barbs = tip - 0.2 * length * (R[:, 2] * 1.0 + 0.5 * np.array(
        [R[:, 0], -R[:, 0], R[:, 1], -R[:, 1]]))
    starts = np.vstack([tail, np.tile(tip, (4, 1))])
    ends = np.vstack([tip, barbs])
    meshcat.SetLineSegments(path, np.asfortranarray(starts.T), np.asfortranarray(ends.T), 4.0,
                            rgba)
