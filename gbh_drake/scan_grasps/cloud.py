"""A point cloud in, the object's mesh out: fused as a scan fuses its depth images.

A cloud has no camera and no surface: it is drawn into virtual depth views (each point a small
square of pixels, the nearest one winning), and those views go through the scan's own
:func:`~gbh_drake.perception.scan.scan_depth_images`: table plane, segmentation, TSDF fusion,
cut at the table and capped bottom. The virtual views' rays are not measurements, so the result
keeps no free space.

:func:`find_object` finds the table and the object's points first (or says why there is no
object), :func:`fuse_object` fuses them.

Quality (the note :func:`fuse_object` returns says it for the cloud at hand): the views' pixels
are about one point spacing wide at the object, so surfaces sampled every few millimetres come
out whole; material thinner than the TSDF voxel (2.5 mm) or gaps between points wider than the
drawn squares (about 1.5 spacings) are lost or closed; what no point covers (the object's
underside, its far side from a single camera) is missing, as in a one-view scan.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gbh_drake.scan_grasps.errors import GraspsInputError, setting
from gbh_drake.scan_grasps.table import plane_text, point_text, under

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
class CloudObject:
    """The object found in a cloud (m, in the cloud's frame: B), or why there is none."""

    table: object
    """The ``TablePlane`` (given, fitted, or under the lowest point)."""
    message: str
    """Why there is no object ("empty scan: ..."), or "" when found."""
    column: np.ndarray
    """(n, 3): the object's points and the cloud's points under its footprint below the
    table (all the cloud's points when none lies above the table; none when no object was
    found): what a given table through the object cuts off."""
    target: np.ndarray | None = None
    """(3,) where the object was looked for."""
    inside: np.ndarray | None = None
    """(n, 3) the cloud's points in the workspace box round ``target``."""
    object_points: np.ndarray | None = None
    """(k, 3) the object's points."""


@dataclass
class FusedCloud:
    """A cloud fused into a scan (in the cloud's frame: B)."""

    scan: object
    """A ``ScanResult`` (``free_space`` None; an empty one, with the table, when no object was
    found: ``scan.message`` says why)."""
    table_source: str
    note: str
    """How the cloud was fused ("" when no object was found)."""


def read_cloud(path: Path) -> np.ndarray:
    """(n, 3) float64 finite points of a .ply, .pcd or .npy file (NaN rows dropped)."""
    path = Path(path)
    if path.suffix.lower() == ".npy":
        try:
            array = np.load(path, allow_pickle=False)
        except Exception as e:  # noqa: BLE001  (numpy raises many types on bad bytes)
            raise GraspsInputError(path, "", f"cannot be read ({type(e).__name__}: {e})") \
                from None
        if array.ndim != 2 or array.shape[1] not in (3, 6) \
                or not np.issubdtype(array.dtype, np.number):
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


def find_object(points: np.ndarray, config, *, table=None, target=None,
                cli: bool = True) -> CloudObject:
    """The table and the object's points in the cloud ``points`` (n, 3, m), as a scan segments
    them. ``table``: a ``TablePlane`` (None: fitted, else under the lowest point); ``target``
    (3,): where the object is (None: the median of the points above the table). ``cli``: its
    messages name ``gbh grasps``' flags (``--target``), else ``gbh_drake.grasps``' arguments."""
    from gbh_drake.perception.crop import CropBox
    from gbh_drake.perception.segment import segment_points
    from gbh_drake.perception.table import fit_table_plane

    if table is None:
        table, _ = fit_table_plane(points, config)
        if table.source == "assumed":  # no plane in the cloud: the object alone
            table = under(points)
    none = np.zeros((0, 3))
    above = points[table.heights(points) >= config.crop_z_min]
    if len(above) == 0:
        return CloudObject(table, f"empty scan: no point of the cloud lies "
                           f"{config.crop_z_min * 1e3:g} mm or more above the table "
                           f"({plane_text(table)}, {table.source}; the points: {_span(points)}): "
                           "a cloud of the table alone?", points)
    where = "the target" if target is not None else "the middle of the points above the table"
    target = np.median(above, axis=0) if target is None else np.asarray(target, dtype=float)
    box = CropBox.workspace(target, config, float(table.point_W(target)[2]))
    inside = points[box.contains(points)]
    if len(inside) == 0:
        return CloudObject(table, f"empty scan: no point of the cloud lies in the workspace "
                           f"round {where} {point_text(target)} (+-{config.crop_half_size_xy:g} "
                           f"m in x and y; the points: {_span(points)}): give "
                           f"{_setting('target', cli)} where the object is", none, target, inside)
    segmentation = segment_points(inside, table, config, target, box)
    if not segmentation.found:
        return CloudObject(table, f"empty scan: no cluster of the cloud stands on the table "
                           f"within {config.object_search_radius:g} m of {where} "
                           f"{point_text(target)}"
                           + _dropped_text(segmentation.dropped, config, cli), none, target,
                           inside)
    object_points = inside[segmentation.object_mask]
    column = np.vstack([object_points, under_footprint(points, object_points, table)])
    return CloudObject(table, "", column, target, inside, object_points)


def fuse_object(found: CloudObject, config) -> FusedCloud:
    """The object ``found`` (:func:`find_object`) as a scan: see the module docstring (an
    empty scan, with the table, when none was found)."""
    from gbh_drake.perception.scan import ScanResult, scan_depth_images
    from gbh_drake.perception.segment import bounding_sphere
    from gbh_drake.perception.viewpoints import camera_poses, fit_view_distance

    table = found.table
    if found.message:
        scan = ScanResult.empty_result(found.message)
        scan.table = table
        return FusedCloud(scan, table.source, "")
    object_points = found.object_points
    centre, radius = bounding_sphere(object_points, table)
    distance, _ = fit_view_distance(radius, config)
    spacing = cloud_spacing(object_points)
    intrinsics = _virtual_camera(spacing, distance, config.fov_y_deg)
    X_WCs = camera_poses(config, centre, distance)
    depths = [splat_depth(found.inside, X_WC.GetAsMatrix4(), intrinsics,
                          SPLAT_SPACINGS * spacing, config.depth_max) for X_WC in X_WCs]
    scan = scan_depth_images(depths, intrinsics, X_WCs, config, found.target, table=table,
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


def _span(points: np.ndarray) -> str:
    """Where ``points`` (n, 3, m) lie: their box in words."""
    return f"{point_text(points.min(axis=0))} to {point_text(points.max(axis=0))} in B"


def _setting(name: str, cli: bool) -> str:
    """The setting ``name`` as the caller gives it a value (:func:`~.errors.setting`)."""
    return setting(name, cli, given=True)


def _dropped_text(dropped: dict[str, int], config, cli: bool = True) -> str:
    """The clusters ``segment_points`` dropped, each reason with what it means and the option
    that may fix it ("" when none was), named as the caller gives it (``cli``: a flag)."""
    base = ", ".join(f"{v:g}" for v in config.robot_base_xy)
    means = {
        "too small": f"under {config.min_cluster_points} points",
        "robot": f"within {config.robot_clearance:g} m of the robot's base at x, y = {base} m "
                 "in B, taken for the robot's own points: a cloud in another frame, e.g. the "
                 f"object's own, centred at its origin? give its pose in B with "
                 f"{_setting('frame', cli)}",
        "not on the table": f"their lowest point over {config.support_gap * 1e3:g} mm above the "
                            f"table: give {_setting('table_z', cli)} or "
                            f"{_setting('table_plane', cli)} if it is elsewhere",
        "too far": f"over {config.object_search_radius:g} m from it: give "
                   f"{_setting('target', cli)} where the object is",
    }
    said = [f"{n} {reason} ({means[reason]})" for reason, n in dropped.items() if n]
    return f"; clusters dropped: {'; '.join(said)}" if said else ""


def under_footprint(points: np.ndarray, object_points: np.ndarray, table) -> np.ndarray:
    """The ``points`` (n, 3, m) below ``table`` within the footprint of ``object_points``
    (their box along the table's plane)."""
    e = table.basis()[:, :2].T
    footprint = object_points @ e.T
    along = points @ e.T
    inside = np.all((along >= footprint.min(axis=0)) & (along <= footprint.max(axis=0)), axis=1)
    return points[inside & (table.heights(points) < 0.0)]


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
