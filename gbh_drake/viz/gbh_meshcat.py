"""Debug view of the GbH core in Drake's Meshcat, in the style of the paper's Figs. 4-5.

* object: translucent grey mesh;
* structures: hanging position c_i as a red sphere, hanging direction v_i as a black arrow (line
  plus a small cone of segments), hit rays red from c_i to the blue hit points H_i, missed rays
  green (paper Fig. 5a);
* grasps: the gripper's keypoint polyline (p2-p4-p5-p3-p1 and the hand axis p7-p6) in red for
  every grasp, and the solid model's boxes for the best ``n_solid``.

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
from gbh_drake.core.results import GraspCandidate, HangingStructure
from gbh_drake.core.simplify import simplified

RED = Rgba(0.9, 0.1, 0.1, 1.0)
GREEN = Rgba(0.1, 0.7, 0.2, 1.0)
BLUE = Rgba(0.1, 0.3, 0.9, 1.0)
BLACK = Rgba(0.0, 0.0, 0.0, 1.0)
GREY = Rgba(0.6, 0.6, 0.6, 0.4)
GRIPPER = Rgba(0.85, 0.55, 0.2, 0.6)
#: Refused grasps (the closest to passing, drawn when none passed).
REFUSED = Rgba(0.55, 0.2, 0.8, 1.0)


def clear(meshcat: Meshcat, prefix: str = "gbh") -> None:
    """Remove everything this module drew under ``prefix``."""
    meshcat.Delete(prefix)


def draw_object(meshcat: Meshcat, mesh: trimesh.Trimesh, prefix: str = "gbh",
                max_faces: int = 6000) -> None:
    """The object mesh (vertices in W, metres), translucent grey, simplified to at most
    ``max_faces`` triangles (a 10-view scan has ~23k: 0.6 MB of every saved replay)."""
    mesh = simplified(mesh, max_faces)
    meshcat.SetTriangleMesh(
        f"{prefix}/object",
        np.asfortranarray(np.asarray(mesh.vertices, dtype=float).T),
        np.asfortranarray(np.asarray(mesh.faces, dtype=np.int32).T),
        GREY,
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
            cloud = PointCloud(len(s.H), Fields(BaseField.kXYZs))
            cloud.mutable_xyzs()[:] = s.H.T
            meshcat.SetObject(f"{path}/hits", cloud, point_size=0.004, rgba=BLUE)
        if len(s.miss_directions):
            _segments(meshcat, f"{path}/miss_rays", s.c, s.c + arrow_length * s.miss_directions,
                      GREEN)


def draw_grasps(
    meshcat: Meshcat,
    grasps: list[GraspCandidate],
    prefix: str = "gbh",
    n_solid: int = 1,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    *,
    rgba: Rgba = RED,
    folder: str = "grasps",
) -> None:
    """Grasps X_WG as keypoint polylines of ``rgba`` (open gripper) under
    ``<prefix>/<folder>``; the first ``n_solid`` also as the solid model's boxes (the model
    N_c is counted against)."""
    for i, g in enumerate(grasps):
        path = f"{prefix}/{folder}/{i}"
        kp = keypoints_W(g.X_WG, gripper.q_open, gripper)
        fingers = np.stack([kp[k] for k in ("p2", "p4", "p5", "p3", "p1")])
        meshcat.SetLine(f"{path}/fingers", np.asfortranarray(fingers.T), 3.0, rgba)
        hand = np.stack([kp["p7"], kp["p6"]])
        meshcat.SetLine(f"{path}/hand_axis", np.asfortranarray(hand.T), 3.0, rgba)
        if i < n_solid:
            X_WG = RigidTransform(g.X_WG)
            for b in gripper.solid_boxes_G(gripper.q_open):
                meshcat.SetObject(f"{path}/solid/{b.name}", Box(*b.size), GRIPPER)
                meshcat.SetTransform(f"{path}/solid/{b.name}",
                                     X_WG @ RigidTransform(np.asarray(b.center)))


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
