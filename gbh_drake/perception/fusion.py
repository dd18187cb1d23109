"""TSDF fusion (Curless and Levoy 1996, as the paper's TSDF Fusion) of depth images into a mesh.

Uses Open3D's ``ScalableTSDFVolume`` (sparse voxel blocks: memory follows the observed surface,
not the workspace); it works in the pinned Open3D 0.19.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import open3d as o3d
import trimesh
from pydrake.math import RigidTransform

from gbh_drake.perception.camera import CameraIntrinsics
from gbh_drake.perception.cleanup import keep_large_components
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.crop import CropBox
from gbh_drake.perception.depth import image_window, valid_points_W

_NO_COLOR = o3d.pipelines.integration.TSDFVolumeColorType.NoColor


def crop_depth(depth: np.ndarray, intrinsics: CameraIntrinsics, X_WC: RigidTransform,
               box: CropBox) -> tuple[np.ndarray, np.ndarray]:
    """``depth`` (h, w) with pixels whose point is outside ``box`` set to 0 (invalid), and the
    kept points p_WQ (n, 3) in W (m)."""
    window = image_window(box.corners(), intrinsics, X_WC)
    p_WQ, v, u = valid_points_W(depth, intrinsics, X_WC, window)
    inside = box.contains(p_WQ)
    cropped = np.zeros(depth.shape, dtype=np.float32)
    cropped[v[inside], u[inside]] = depth[v[inside], u[inside]]
    return cropped, p_WQ[inside]


def integrate(depths: Sequence[np.ndarray], intrinsics: CameraIntrinsics,
              X_WCs: Sequence[RigidTransform], config: ScanConfig) -> trimesh.Trimesh:
    """The TSDF of the depth images (m; 0 = no measurement) from cameras at X_WC, as a mesh
    in W (marching cubes, not cleaned)."""
    volume = o3d.pipelines.integration.ScalableTSDFVolume(
        voxel_length=config.voxel_size, sdf_trunc=config.sdf_trunc, color_type=_NO_COLOR)
    K = o3d.camera.PinholeCameraIntrinsic(intrinsics.width, intrinsics.height, intrinsics.fx,
                                          intrinsics.fy, intrinsics.cx, intrinsics.cy)
    color = o3d.geometry.Image(np.zeros((intrinsics.height, intrinsics.width, 3), np.uint8))
    for depth, X_WC in zip(depths, X_WCs, strict=True):
        rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
            color, o3d.geometry.Image(np.ascontiguousarray(depth, dtype=np.float32)),
            depth_scale=1.0, depth_trunc=config.depth_max, convert_rgb_to_intensity=False)
        volume.integrate(rgbd, K, X_WC.inverse().GetAsMatrix4())  # extrinsic: X_CW
    mesh = volume.extract_triangle_mesh()
    return trimesh.Trimesh(np.asarray(mesh.vertices), np.asarray(mesh.triangles))


def fuse_depth_images(depths: Sequence[np.ndarray], intrinsics: CameraIntrinsics,
                      X_WCs: Sequence[RigidTransform], config: ScanConfig, box: CropBox
                      ) -> tuple[trimesh.Trimesh, np.ndarray]:
    """Fuses depth images (h, w) float32 (m) from cameras C at X_WC into the object's mesh in W.

    Pixels outside ``box`` are ignored, except that the box is extended down through the table
    top: rays ending on the table near the object carve free space around it (on mug_classic,
    10 views: 0.58 mm accuracy and 0.994 coverage with the table, 0.79 and 0.964 without). The
    mesh is then cut to ``box`` (removing the table) and cleaned of small fragments. Returns
    (mesh_W, p_WQ (n, 3) the measured points inside ``box``); the mesh is empty when no pixel
    falls inside the box."""
    fusion_box = CropBox((*box.lower_W[:2], -config.sdf_trunc), box.upper_W)
    cropped = [crop_depth(d, intrinsics, X_WC, fusion_box) for d, X_WC in zip(
        depths, X_WCs, strict=True)]
    p_WQ = np.concatenate([p for _, p in cropped]) if cropped else np.zeros((0, 3))
    p_WQ = p_WQ[box.contains(p_WQ)]
    if len(p_WQ) == 0:
        return trimesh.Trimesh(), p_WQ
    mesh = integrate([d for d, _ in cropped], intrinsics, X_WCs, config)
    mesh = box.cut(mesh)
    return keep_large_components(mesh, config.min_component_fraction), p_WQ
