"""A whole scan: render depth views around a target, (optionally) add noise, fuse, crop, clean.

``scan_object`` works on a SceneGraph ``QueryObject``; ``scan_depth_images`` does the same from
depth images already in hand (e.g. from a real camera). Neither needs a running simulation.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import trimesh
from pydrake.geometry import QueryObject
from pydrake.math import RigidTransform

from gbh_drake.perception.camera import CameraIntrinsics, make_depth_camera, render_depth_images
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.crop import CropBox
from gbh_drake.perception.depth import valid_depth
from gbh_drake.perception.fusion import fuse_depth_images
from gbh_drake.perception.noise import add_depth_noise
from gbh_drake.perception.viewpoints import camera_poses


@dataclass
class ScanResult:
    """The scanned object in W. When ``empty``, ``mesh_W`` has no faces and ``message`` says
    why (nothing is raised)."""

    mesh_W: trimesh.Trimesh
    """The fused, cropped, cleaned mesh (m, in W); not watertight (open at the table)."""
    p_WQ: np.ndarray
    """Measured points (n, 3) inside the crop box (m, in W), from all views."""
    X_WCs: list[RigidTransform]
    """Pose of each camera C in W."""
    intrinsics: CameraIntrinsics
    crop: CropBox
    """The workspace box (W) the mesh was cut to."""
    timing: dict[str, float] = field(default_factory=dict)
    """Wall-clock seconds: ``render``, ``fuse``."""
    empty: bool = False
    message: str = ""

    def o3d_mesh(self):
        """``mesh_W`` as an ``open3d.geometry.TriangleMesh`` (with vertex normals)."""
        import open3d as o3d

        mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(self.mesh_W.vertices),
                                         o3d.utility.Vector3iVector(self.mesh_W.faces))
        return mesh.compute_vertex_normals()


def scan_object(query_object: QueryObject, config: ScanConfig, p_WT) -> ScanResult:
    """Scans whatever the cameras see around the target p_WT (m, in W) with ``config``'s views.

    ``query_object`` comes from the SceneGraph's ``query`` output port; its renderer
    ``config.renderer_name`` must exist. The robot, the table and everything outside the crop
    box are removed."""
    config.validate()
    X_WCs = camera_poses(config, p_WT)
    start = time.perf_counter()
    depths = render_depth_images(query_object, make_depth_camera(config), X_WCs)
    render_s = time.perf_counter() - start
    result = scan_depth_images(depths, CameraIntrinsics.from_config(config), X_WCs, config, p_WT)
    result.timing = {"render": render_s, **result.timing}
    return result


def scan_depth_images(depths: Sequence[np.ndarray], intrinsics: CameraIntrinsics,
                      X_WCs: Sequence[RigidTransform], config: ScanConfig, p_WT) -> ScanResult:
    """Fuses depth images (h, w) float32 (m; 0 or inf: no measurement) taken from X_WC into the
    mesh of the object near target p_WT (m, in W); adds noise first when ``config.noise``."""
    start = time.perf_counter()
    box = CropBox.around(p_WT, config)
    if config.noise:
        rng = np.random.default_rng(config.noise_seed)
        depths = [add_depth_noise(d, intrinsics, config, rng) for d in depths]
    mesh, p_WQ = fuse_depth_images(depths, intrinsics, X_WCs, config, box)
    result = ScanResult(mesh, p_WQ, list(X_WCs), intrinsics, box,
                        timing={"fuse": time.perf_counter() - start})
    result.message = _empty_reason(depths, p_WQ, mesh, box, config)
    result.empty = bool(result.message)
    return result


def _empty_reason(depths, p_WQ, mesh, box: CropBox, config: ScanConfig) -> str:
    """Why the scan is empty, or "" when it is not."""
    n = len(depths)
    if not any(valid_depth(d).any() for d in depths):
        return (f"empty scan: none of the {n} depth images has a valid pixel (depth range "
                f"{config.depth_min}-{config.depth_max} m)")
    if len(p_WQ) == 0:
        return (f"empty scan: no depth pixel of the {n} views falls inside the crop box "
                f"{np.round(box.lower_W, 3).tolist()}-{np.round(box.upper_W, 3).tolist()} m "
                "(W); is the object at the scan target and in view of the cameras?")
    if len(mesh.faces) == 0:
        return (f"empty scan: {len(p_WQ)} points inside the crop box but fusion gave no "
                f"surface (voxel {config.voxel_size} m)")
    return ""
