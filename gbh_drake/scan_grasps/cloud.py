"""A point cloud in, the object's mesh out: fused as a scan fuses its depth images.

A cloud has no camera and no surface: it is drawn into virtual depth views (each point a small
square of pixels, the nearest one winning), and those views go through the scan's own
:func:`~gbh_drake.perception.scan.scan_depth_images`: table plane, segmentation, TSDF fusion,
cut at the table and capped bottom. The virtual views' rays are not measurements, so the result
keeps no free space.

Quality (the note :func:`fuse_cloud` returns says it for the cloud at hand): the views' pixels
are about one point spacing wide at the object, so surfaces sampled every few millimetres come
out whole; material thinner than the TSDF voxel (2.5 mm) or gaps between points wider than the
drawn squares (about 1.5 spacings) are lost or closed; what no point covers (the object's
underside, its far side from a single camera) is missing, as in a one-view scan.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gbh_drake.scan_grasps.errors import GraspsInputError
from gbh_drake.scan_grasps.table import under

#: Points below this count are not an object.
MIN_POINTS = 100
#: Largest and smallest virtual image (pixels, width x height).
MAX_IMAGE = (640, 480)
MIN_IMAGE = (64, 48)
#: Points used to estimate the cloud's spacing (a deterministic subset).
SPACING_SAMPLE = 20_000
#: Each point is drawn this many spacings wide (a square of pixels).
SPLAT_SPACINGS = 1.5


@dataclass
class FusedCloud:
    """A cloud fused into a scan (in the cloud's frame: B)."""

    scan: object
    """A ``ScanResult`` (``free_space`` None)."""
    table_source: str
    note: str


def read_cloud(path: Path) -> np.ndarray:
    """(n, 3) float64 finite points of a .ply, .pcd or .npy file (NaN rows dropped)."""
    path = Path(path)
    if path.suffix.lower() == ".npy":
        try:
            array = np.load(path, allow_pickle=False)
        except Exception as e:  # noqa: BLE001  (numpy raises many types on bad bytes)
            raise GraspsInputError(path, "", f"cannot be read ({type(e).__name__}: {e})") \
                from None
        if array.ndim != 2 or array.shape[1] < 3 or not np.issubdtype(array.dtype, np.number):
            raise GraspsInputError(path, "points", f"a cloud is an (n, 3) array of numbers "
                                   f"(or (n, 6) with normals), got {array.dtype} {array.shape}")
        points = np.asarray(array[:, :3], dtype=float)
    else:
        from gbh_drake.core.o3d import open3d

        cloud = open3d().io.read_point_cloud(str(path))
        points = np.asarray(cloud.points, dtype=float)
    finite = np.isfinite(points).all(axis=1)
    if len(points) and not finite.any():
        raise GraspsInputError(path, "points", f"all {len(points)} points are NaN or infinite")
    points = points[finite]
    if len(points) < MIN_POINTS:
        raise GraspsInputError(path, "points", f"{len(points)} finite points: at least "
                                               f"{MIN_POINTS} make an object")
    return points


def cloud_spacing(points: np.ndarray) -> float:
    """Median distance (m) from a point to its nearest neighbour (on a subset of at most
    :data:`SPACING_SAMPLE` points, every k-th)."""
    from scipy.spatial import cKDTree

    sample = points[:: max(1, len(points) // SPACING_SAMPLE)]
    distance, _ = cKDTree(points).query(sample, k=2)
    return float(np.median(distance[:, 1]))


def fuse_cloud(points: np.ndarray, config, *, table=None, target=None) -> FusedCloud:
    """The object of the cloud ``points`` (n, 3, m) as a scan: see the module docstring.
    ``table``: a ``TablePlane`` (None: fitted, else under the lowest point); ``target`` (3,):
    where the object is (None: the median of the points above the table)."""
    from gbh_drake.perception.crop import CropBox
    from gbh_drake.perception.scan import ScanResult, scan_depth_images
    from gbh_drake.perception.segment import bounding_sphere, segment_points
    from gbh_drake.perception.table import fit_table_plane
    from gbh_drake.perception.viewpoints import camera_poses, fit_view_distance

    if table is None:
        table, _ = fit_table_plane(points, config)
        if table.source == "assumed":  # no plane in the cloud: the object alone
            table = under(points)
    above = points[table.heights(points) >= config.crop_z_min]
    if len(above) == 0:
        return FusedCloud(ScanResult.empty_result("empty scan: no point of the cloud lies above "
                                                  "the table"), table.source, "")
    target = np.median(above, axis=0) if target is None else np.asarray(target, dtype=float)
    box = CropBox.workspace(target, config, float(table.point_W(target)[2]))
    inside = points[box.contains(points)]
    segmentation = segment_points(inside, table, config, target, box)
    if not segmentation.found:
        return FusedCloud(ScanResult.empty_result(
            f"empty scan: no cluster of the cloud stands on the table within "
            f"{config.object_search_radius} m of {np.round(target, 3).tolist()} (dropped: "
            f"{segmentation.dropped})"), table.source, "")
    object_points = inside[segmentation.object_mask]
    centre, radius = bounding_sphere(object_points, table)
    distance, _ = fit_view_distance(radius, config)
    spacing = cloud_spacing(object_points)
    intrinsics = _virtual_camera(spacing, distance, config.fov_y_deg)
    X_WCs = camera_poses(config, centre, distance)
    depths = [splat_depth(inside, X_WC.GetAsMatrix4(), intrinsics,
                          SPLAT_SPACINGS * spacing, config.depth_max) for X_WC in X_WCs]
    scan = scan_depth_images(depths, intrinsics, X_WCs, config, target, table=table,
                             reference=centre, far_is_free=False)
    scan.free_space = None  # the virtual rays measured nothing
    scan.p_WQ = object_points
    note = (f"the point cloud was fused: {len(object_points)} points of the object (spacing "
            f"{spacing * 1e3:.1f} mm) drawn into {len(X_WCs)} virtual {intrinsics.width}x"
            f"{intrinsics.height} depth views, TSDF at {config.voxel_size * 1e3:.1f} mm voxels, "
            f"cut at the table and capped: parts thinner than a voxel and gaps wider than "
            f"{SPLAT_SPACINGS * spacing * 1e3:.1f} mm are lost or closed; what no point covers "
            "is missing")
    return FusedCloud(scan, table.source, note)


def _virtual_camera(spacing: float, distance: float, fov_y_deg: float):
    """A pinhole whose pixel is about ``spacing`` wide at ``distance``, with the field of view
    ``fov_y_deg`` (images between :data:`MIN_IMAGE` and :data:`MAX_IMAGE`)."""
    from gbh_drake.perception.camera import CameraIntrinsics

    half = np.tan(np.radians(0.5 * fov_y_deg))
    height = int(np.clip(np.ceil(2.0 * half * distance / spacing), MIN_IMAGE[1], MAX_IMAGE[1]))
    width = int(np.clip(round(height * 4 / 3), MIN_IMAGE[0], MAX_IMAGE[0]))
    f = 0.5 * height / half
    return CameraIntrinsics(width, height, f, f, 0.5 * width, 0.5 * height)


def splat_depth(points: np.ndarray, X_WC: np.ndarray, intrinsics, size: float,
                depth_max: float) -> np.ndarray:
    """(h, w) float32 depth (m; 0: nothing) of ``points`` (n, 3, W) seen from X_WC (4, 4), each
    drawn as a square ``size`` (m) wide at its depth, the nearest point winning per pixel
    (pixel (u, v) covers [u, u + 1) of fx x / z + cx, as Drake's camera)."""
    R, t = X_WC[:3, :3], X_WC[:3, 3]
    p = (points - t) @ R  # p_C
    z = p[:, 2]
    front = (z > 1e-6) & (z <= depth_max)
    p, z = p[front], z[front]
    u = intrinsics.fx * p[:, 0] / z + intrinsics.cx
    v = intrinsics.fy * p[:, 1] / z + intrinsics.cy
    half = np.maximum(np.ceil(0.5 * size * intrinsics.fx / z - 0.5), 0).astype(int)
    k = int(half.max(initial=0))
    w, h = intrinsics.width, intrinsics.height
    buffer = np.full(w * h, np.inf)
    for du in range(-k, k + 1):
        for dv in range(-k, k + 1):
            sel = (abs(du) <= half) & (abs(dv) <= half)
            uu = np.floor(u[sel]).astype(int) + du
            vv = np.floor(v[sel]).astype(int) + dv
            ok = (uu >= 0) & (uu < w) & (vv >= 0) & (vv < h)
            np.minimum.at(buffer, vv[ok] * w + uu[ok], z[sel][ok])
    depth = buffer.reshape(h, w)
    depth[~np.isfinite(depth)] = 0.0
    return depth.astype(np.float32)
