"""Depth images in hand through the simulated scan's own functions: the same table fit,
segmentation, TSDF fusion, cut, cap and free space (``perception.scan``), in B.

The simulated scan renders its first look and its views and calls
:func:`~gbh_drake.perception.scan.look_at_images` and
:func:`~gbh_drake.perception.scan.scan_depth_images`; :func:`scan_views` reads them from a
views file and calls the same two. The images are taken as measured (no noise is added); the
free space's margin is the TSDF voxel plus the file's ``depth_error``.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from gbh_drake.scan_grasps.errors import GraspsInputError, setting
from gbh_drake.scan_grasps.views import ViewSet, ViewsFile

#: Camera axes closer to parallel than this (sin of the angle) do not fix a target point.
PARALLEL_AXES = 0.05


def scan_config(views: ViewsFile):
    """The ``ScanConfig`` of a views file: its ``scan`` fields, the sensor's range from
    ``depth_range``, no noise added and no rounding (the images are as measured)."""
    from gbh_drake.core.ranges import FieldError, check_fields
    from gbh_drake.perception.config import ScanConfig

    names = {f.name for f in dataclasses.fields(ScanConfig)}
    for key in views.scan:
        if key not in names:
            raise GraspsInputError(views.path, f"scan.{key}", "unknown ScanConfig field")
    lo, hi = views.depth_range
    values = {**views.scan, "depth_min": max(lo, 1e-3), "depth_max": hi, "noise": False,
              "depth_unit": 0.0}
    config = ScanConfig(**values)
    # The simulated camera's distances must lie in the sensor's range; they only matter there.
    for name in ("distance", "distance_max", "first_look_distance"):
        if name not in views.scan:
            setattr(config, name, float(np.clip(getattr(config, name), config.depth_min * 1.01,
                                                config.depth_max * 0.99)))
    try:
        check_fields(config)
    except (TypeError, ValueError) as e:
        if not isinstance(e, FieldError):
            raise GraspsInputError(views.path, "scan", f"a field has the wrong type ({e})") \
                from None
        raise GraspsInputError(views.path, f"scan.{'.'.join(map(str, e.path))}",
                               e.problem) from None
    return config


def scan_views(views: ViewsFile, options) -> tuple[object, str, list[str]]:
    """(the ``ScanResult`` in B, where the table came from, notes) of a views file read with
    ``options`` (:class:`~gbh_drake.scan_grasps.inputs.InputOptions`)."""
    from pydrake.math import RigidTransform

    from gbh_drake.perception.crop import CropBox
    from gbh_drake.perception.fusion import view_points
    from gbh_drake.perception.scan import (
        ScanResult,
        add_first_look,
        look_at_images,
        make_free_space,
        scan_depth_images,
    )
    from gbh_drake.perception.self_filter import without_pixels
    from gbh_drake.perception.table import fit_table_plane
    from gbh_drake.scan_grasps.table import table_plane

    config = scan_config(views)
    main, first = _in_B(views.views, options.X_BI), _in_B(views.first_look, options.X_BI)
    intrinsics, X_BCs = main.intrinsics, [RigidTransform(X) for X in main.X_BCs]
    target = _point_in_B(options.target, None) if options.target is not None else \
        _point_in_B(views.target, options.X_BI) if views.target is not None else \
        views_target(main)
    reference = _point_in_B(views.object_point, options.X_BI)
    given = options.table if options.table is not None else \
        _plane_in_B(views.table, options.X_BI) if views.table is not None else None
    table = table_plane(given) if given is not None else None
    look = None
    if first is not None:
        look, _ = look_at_images(first.depths, first.intrinsics, [RigidTransform(X) for X in
                                                                first.X_BCs],
                                 config, target, reference=reference,
                                 distance=config.first_look_distance, table=table,
                                 sensor_error=first.depth_error, robot_masks=first.robot_masks)
    notes = []
    if views.mesh is not None:
        mesh = load_raw_mesh(views.mesh, views.path)
        if table is None:
            seen = without_pixels(main.depths, main.robot_masks)  # not the robot's pixels
            table = look.table if look is not None else fit_table_plane(view_points(
                seen, intrinsics, X_BCs, CropBox.workspace(target, config)).p_WQ, config)[0]
        free = make_free_space(main.depths, intrinsics, X_BCs, config, config.distance,
                               sensor_error=main.depth_error)
        box = CropBox.workspace(target, config, float(table.point_W(target)[2]))
        scan = ScanResult(mesh, np.asarray(mesh.vertices, dtype=float), list(X_BCs), intrinsics,
                          box, table=table, free_space=free, region=box, target_W=target)
        notes.append(f"the mesh is {views.mesh.name} as given; the views give the free space "
                     "and the table")
    else:
        scan = scan_depth_images(main.depths, intrinsics, X_BCs, config, target,
                                 first_look=look, table=table, reference=reference,
                                 sensor_error=main.depth_error, pixel_masks=main.masks,
                                 robot_masks=main.robot_masks)
    if look is not None:
        add_first_look(scan, look)
    source = "given" if given is not None else scan.table.source if scan.table else "assumed"
    if source == "assumed":
        notes.append(f"no table plane found in the depth images: assumed at z = "
                     f"{config.table_height:g} m in B; give "
                     f"{setting('table_z', options.cli, given=True)} or "
                     f"{setting('table_plane', options.cli, given=True)}")
    return scan, source, notes


def _in_B(views: ViewSet | None, X_BI: np.ndarray | None) -> ViewSet | None:
    """``views`` with its poses in B (given in the input's frame I at X_BI)."""
    if views is None or X_BI is None:
        return views
    return dataclasses.replace(views, X_BCs=[X_BI @ X for X in views.X_BCs])


def _point_in_B(p, X_BI: np.ndarray | None) -> np.ndarray | None:
    if p is None:
        return None
    p = np.asarray(p, dtype=float)
    return p if X_BI is None else X_BI[:3, :3] @ p + X_BI[:3, 3]


def _plane_in_B(plane, X_BI: np.ndarray | None):
    """A plane (normal, height) of the input's frame I in B."""
    normal, height = plane
    if X_BI is None:
        return plane
    n_B = X_BI[:3, :3] @ np.asarray(normal, dtype=float)
    return n_B, float(height + n_B @ X_BI[:3, 3])


def views_target(views: ViewSet) -> np.ndarray:
    """(3,) m, B: where the views look: the point nearest all their optical axes (least
    squares); for one view, or axes nearly parallel, the point of the first view's axis at the
    median depth of its image's middle."""
    origins = np.array([X[:3, 3] for X in views.X_BCs])
    axes = np.array([X[:3, 2] for X in views.X_BCs])
    if len(axes) >= 2 and float(np.linalg.norm(np.cross(axes[0], axes[1:]), axis=1).max()) \
            > PARALLEL_AXES:
        A = np.zeros((3, 3))
        b = np.zeros(3)
        for o, d in zip(origins, axes, strict=True):
            P = np.eye(3) - np.outer(d, d)
            A += P
            b += P @ o
        return np.linalg.solve(A, b)
    d = views.depths[0]
    h, w = d.shape
    middle = d[h // 3: 2 * h // 3, w // 3: 2 * w // 3]
    valid = middle[np.isfinite(middle) & (middle > 0)]
    depth = float(np.median(valid)) if len(valid) else float(np.median(d[np.isfinite(d) &
                                                                          (d > 0)]))
    return origins[0] + depth * axes[0]


def load_raw_mesh(path: Path, views_file: Path):
    """A views file's ``mesh``, as it is (the scan's own fused mesh: not repaired, so the GbH
    core samples the very surface the scan made)."""
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh", process=False)
    except Exception as e:  # noqa: BLE001  (trimesh raises many types for bad bytes)
        raise GraspsInputError(views_file, "mesh", f"{path} cannot be read ({type(e).__name__}: "
                                                   f"{e})") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise GraspsInputError(views_file, "mesh", f"{path} holds no triangles")
    if not np.isfinite(np.asarray(mesh.vertices)).all():
        raise GraspsInputError(views_file, "mesh", f"{path} has non-finite vertices")
    return mesh
