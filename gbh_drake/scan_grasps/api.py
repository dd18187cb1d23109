"""One call for a scan you have: ``gbh_drake.grasps(input) -> GraspsResult``.

    import gbh_drake

    result = gbh_drake.grasps("views/")            # depth images + views.yaml, a mesh or a cloud
    best = result.grasps[0]
    print(best.kind, best.score, best.X_B_link8)     # where the flange goes, in the base frame B

The input is read (:mod:`~gbh_drake.scan_grasps.inputs`), the GbH core runs on the object in B
(``core.pipeline.plan_grasps``: hanging structures, grasps, collision rules, the ranked top k,
distinct), and each ranked grasp gets its waypoints (:mod:`~gbh_drake.scan_grasps.waypoints`).
``result`` writes itself as the versioned document (:mod:`~gbh_drake.scan_grasps.document`).
"""

from __future__ import annotations

import dataclasses
import os
import time
from pathlib import Path

import numpy as np

from gbh_drake.scan_grasps.errors import GraspsInputError
from gbh_drake.scan_grasps.result import GraspsResult


def grasps(input, *, scale: float = 1.0, table_z: float | None = None, table_plane=None,
           frame=None, target=None, params=None, preset: str | None = None,
           seed: int | None = None, top: int | None = None, pick=None) -> GraspsResult:
    """Ranked hook grasps for the object in ``input`` (a path: a mesh, a point cloud, or a
    folder of depth images with its ``views.yaml``), in the robot's base frame B.

    ``scale``: the file's units in metres (a mesh's or a point cloud's: 0.001 for
    millimetres), applied before ``frame``. ``table_z`` (m) or ``table_plane`` ((a, b, c, d):
    a x + b y + c z + d = 0, in B): the table (default: the views file's, else fitted, else
    under the object). ``frame``: the pose (4, 4) of the input's own frame in B, when it is
    not B. ``target`` (3,): where the object is (default: where the views look, or the cloud's
    middle). ``params``: ``GbhParams``
    (default: the views file's ``gbh``, else gbh_drake's), ``preset`` (``"paper"``), ``seed``
    (the surface sampler's; default the file's, else 0), ``top`` (how many; default
    ``top_k``), ``pick``: a ``PickConfig`` for the waypoints (approach distance, lift).

    Raises ValueError for a bad argument (naming it), and
    :class:`~gbh_drake.scan_grasps.errors.GraspsInputError` for an input that cannot be used
    (e.g. an object smaller than 5 mm or larger than 1.2 m, as ``gbh run``; a given table
    above most of the object; its hints name these arguments: ``give scale=0.001``). An empty
    scan, nothing hangable or no collision-free grasp are results (``result.none`` says which
    and why)."""
    return grasps_as(False, input, scale=scale, table_z=table_z, table_plane=table_plane,
                     frame=frame, target=target, params=params, preset=preset, seed=seed,
                     top=top, pick=pick)


def grasps_as(cli: bool, input, *, scale: float = 1.0, table_z: float | None = None,
              table_plane=None, frame=None, target=None, params=None, preset: str | None = None,
              seed: int | None = None, top: int | None = None, pick=None) -> GraspsResult:
    """:func:`grasps`, the input's problems naming ``gbh grasps``' flags (``--scale``) when
    ``cli``, else the arguments (``scale=``: :func:`~.errors.setting`)."""
    from gbh_drake.core.gripper import HOOK_GRIPPER
    from gbh_drake.core.pipeline import plan_grasps
    from gbh_drake.scan_grasps.errors import setting
    from gbh_drake.scan_grasps.inputs import InputOptions, load_input
    from gbh_drake.scan_grasps.result import make_result

    start = time.perf_counter()
    frame = _check_arguments(input, table_z, frame, target, seed, top, params, pick)
    path = Path(input)
    if isinstance(scale, bool) or not isinstance(scale, int | float | np.number) \
            or not (np.isfinite(scale) and scale > 0):
        raise ValueError(f"scale: the file's units in metres, a positive finite number; got "
                         f"{scale!r}")
    options = InputOptions(frame,
                           _table(table_z, table_plane),
                           None if target is None else np.asarray(target, dtype=float),
                           float(scale),
                           setting("table_z" if table_z is not None else "table_plane", cli),
                           cli)
    scan_input = load_input(path, options)
    scan = scan_input.scan
    read = time.perf_counter()
    params = _params(path, params, scan_input, scan.table, preset, top)
    seed = int(seed if seed is not None else scan_input.seed if scan_input.seed is not None
               else 0)
    common = dict(params=params, seed=seed, scan_B=scan, table_B=scan.table,
                  table_source=scan_input.table_source, pick=pick,
                  input_kind=scan_input.kind, input_path=scan_input.path,
                  notes=scan_input.notes, warnings=list(scan.warnings))
    if scan.empty:
        result = make_result(structures_W=[], candidates_W=[], ranked_W=[],
                             empty_message=scan.message or "empty scan", **common)
    else:
        gbh = plan_grasps(scan.mesh_W, params, HOOK_GRIPPER, seed, free_space=scan.free_space)
        result = make_result(structures_W=gbh.structures, candidates_W=gbh.candidates,
                             ranked_W=gbh.ranked, hangability=gbh.hangability,
                             unseen_B=_unseen(scan) if gbh.ranked else None, **common)
        result.timings.update({f"gbh_{k}": v for k, v in gbh.timings.items()})
    result.timings = {"read": read - start, **result.timings,
                      "total": time.perf_counter() - start}
    return result


def _check_arguments(input, table_z, frame, target, seed, top, params, pick):
    """ValueError naming the first argument of :func:`grasps` of the wrong type or shape (they
    failed deep inside, or a frame that is no pose was taken as one); returns ``frame`` as a
    (4, 4) array or None."""
    from gbh_drake.core.arguments import argument_problem, require
    from gbh_drake.core.params import GbhParams
    from gbh_drake.core.pick_config import PickConfig
    from gbh_drake.core.ranges import is_number
    from gbh_drake.scan_grasps.poses import check_pose

    def refuse(name, expected, value):
        raise ValueError(argument_problem("grasps", name, expected, value))

    require("grasps", "input", input, (str, os.PathLike), "a path (a mesh, a point cloud or a "
            "folder of depth images)", ValueError)
    if table_z is not None and not (is_number(table_z) and np.isfinite(table_z)):
        refuse("table_z", "a finite height (m, in B) or None", table_z)
    if target is not None and not (np.shape(target) == (3,) and all(
            is_number(v) and np.isfinite(v) for v in target)):
        refuse("target", "3 finite coordinates (m, in B) or None", target)
    for name, value in (("seed", seed), ("top", top)):
        if value is not None and not (isinstance(value, int | np.integer)
                                      and not isinstance(value, bool)):
            refuse(name, "an integer or None", value)
    require("grasps", "params", params, (GbhParams, type(None)), "a GbhParams or None",
            ValueError)
    require("grasps", "pick", pick, (PickConfig, type(None)), "a PickConfig or None", ValueError)
    if frame is None:
        return None
    try:
        return check_pose(frame)
    except (ValueError, TypeError) as e:
        raise ValueError(f"grasps(): frame: {e}") from None


def _unseen(scan) -> np.ndarray:
    """The unseen space next to ``scan`` (for the lift; ``perception.unseen``), in the region
    round the object the simulated scan reads after its first look (the object's bounding
    sphere grown: ``perception.scan.object_region``), not the whole workspace box of views
    that had none."""
    from gbh_drake.perception.scan import object_region
    from gbh_drake.perception.segment import bounding_sphere
    from gbh_drake.perception.unseen import scan_unseen

    if scan.free_space is None or scan.region is None or not len(scan.mesh_W.faces):
        return np.zeros((0, 3))
    if scan.first_look_free_space is None:
        centre, radius = bounding_sphere(np.asarray(scan.mesh_W.vertices), scan.table)
        scan = dataclasses.replace(scan, region=object_region(scan.region, centre, radius))
    return scan_unseen(scan)


def _table(table_z: float | None, table_plane) -> tuple[np.ndarray, float] | None:
    """(normal, height) of the table given by its height or its plane (a, b, c, d)."""
    if table_z is not None and table_plane is not None:
        raise ValueError("give the table's height or its plane, not both")
    if table_z is not None:
        if not np.isfinite(table_z):
            raise ValueError(f"table_z must be finite, got {table_z}")
        return np.array([0.0, 0.0, 1.0]), float(table_z)
    if table_plane is None:
        return None
    a = np.asarray(table_plane, dtype=float).reshape(-1)
    if len(a) != 4 or not np.isfinite(a).all() or not np.linalg.norm(a[:3]) > 0:
        raise ValueError(f"table_plane is a, b, c, d (a x + b y + c z + d = 0), got "
                         f"{a.tolist()}")
    n = np.linalg.norm(a[:3])
    normal, height = a[:3] / n, -a[3] / n
    if normal[2] < 0:
        normal, height = -normal, -height
    if np.degrees(np.arccos(min(1.0, normal[2]))) > 45.0:
        raise ValueError(f"table_plane's normal {np.round(normal, 3).tolist()} is more than "
                         "45 deg from B's z: a table is (nearly) horizontal")
    return normal, float(height)


def _params(path: Path, params, scan_input, table, preset: str | None, top: int | None):
    """The GbhParams: given, or the views file's ``gbh``, else the defaults; the preset and
    ``top``; the ground is the table unless the file's ``gbh`` names it."""
    from gbh_drake.core.params import GbhParams
    from gbh_drake.core.results import GbhInputError

    given = dict(scan_input.gbh) if params is None else {}
    if params is None:
        names = {f.name for f in dataclasses.fields(GbhParams)}
        for key in given:
            if key not in names:
                raise GraspsInputError(scan_input.path, f"gbh.{key}", "unknown GbhParams field")
        params = GbhParams(**given)
    if preset is not None:
        params = params.with_preset(preset)
    if top is not None:
        params = dataclasses.replace(params, top_k=int(top))
    if table is not None and not {"ground_normal", "ground_height"} & set(given):
        normal, height = table.as_ground()
        params = dataclasses.replace(params, ground_normal=normal, ground_height=height)
    try:
        params.check()
    except GbhInputError as e:
        raise GraspsInputError(scan_input.path if given else path, "gbh", str(e)) from None
    return params
