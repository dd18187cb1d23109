"""What ``gbh run`` writes of its scan, in the robot's base frame B: ``scan.ply`` (the fused
mesh), ``grasps.json`` (GbH's ranked grasps, the document of ``gbh grasps``) and, asked for,
``views/`` (the views' depth images as 16-bit PNG, the first look's too, and ``views.yaml``
naming ``../scan.ply`` as the mesh). ``gbh grasps <run>/views`` then gives the same ranked list
as the run: the same mesh, free space (depths rounded to 0.1 mm), table, parameters and seed.

B is the arm's ``panda_link0`` (:mod:`gbh_drake.modeling.robot_frames`): the identity in the
station's default directives; a scenario that moves the arm gets everything transformed.
"""

from __future__ import annotations

import copy
import dataclasses
from pathlib import Path

import numpy as np

from gbh_drake.scan_grasps import views as views_io

#: What ``gbh run`` writes of its scan (the views folder only when asked).
SCAN_FILE, GRASPS_FILE, VIEWS_FOLDER = "scan.ply", "grasps.json", "views"


def scan_ply(mesh_W, X_BW: np.ndarray) -> bytes:
    """The mesh (W) in B as a binary PLY, its vertices in double precision (as fused: read
    back, the GbH core samples the very same surface; trimesh's own writer rounds to float)."""
    mesh = _mesh_in(mesh_W, X_BW)
    vertices = np.ascontiguousarray(mesh.vertices, dtype="<f8")
    faces = np.zeros(len(mesh.faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"], faces["i"] = 3, mesh.faces
    header = ("ply\nformat binary_little_endian 1.0\ncomment gbh_drake scan, frame B (m)\n"
              f"element vertex {len(vertices)}\nproperty double x\nproperty double y\n"
              f"property double z\nelement face {len(faces)}\n"
              "property list uchar int vertex_indices\nend_header\n")
    return header.encode() + vertices.tobytes() + faces.tobytes()


def table_in(table, X_BW: np.ndarray):
    """The table plane (W) in B."""
    n_B = X_BW[:3, :3] @ table.normal_W
    return dataclasses.replace(table, normal_W=n_B, height=float(table.height + n_B @ X_BW[:3, 3]))


def trial_export(done) -> dict:
    """The files of a finished pick trial (a ``TrialRun``): ``{name: bytes or str}`` for
    ``scan.ply`` (unless the scan is empty) and ``grasps.json`` (a method that runs GbH's
    stages; the antipodal baseline's pinches are not GbH grasps), and a function
    ``views(folder)`` writing the views; {} when the trial took no scan (task ``settle``)."""
    from gbh_drake.modeling.robot_frames import robot_frames
    from gbh_drake.scan_grasps.document import document, to_json
    from gbh_drake.systems.scanner import scan_pending

    trial, context = done.trial, done.simulator.get_context()
    scan = trial.scanner.GetOutputPort("mesh_W").Eval(trial.scanner.GetMyContextFromRoot(context))
    if scan_pending(scan):
        return {}
    frames = robot_frames(trial.station.plant)
    X_BW = np.linalg.inv(frames.X_WB)
    files: dict = {}
    gbh = trial.source.candidates is not None  # the method runs GbH's stages
    if gbh:
        result = trial_result(done, scan, X_BW)
        files[GRASPS_FILE] = to_json(document(result))
    if not scan.empty:
        files[SCAN_FILE] = scan_ply(scan.mesh_W, X_BW)
        files[VIEWS_FOLDER] = lambda folder: write_views(
            Path(folder), scan, trial.scenario.scan, X_BW,
            gbh=trial.scenario.gbh if gbh else None,
            seed=trial.seeds.sampling if gbh else None, mesh=f"../{SCAN_FILE}")
    return files


def trial_result(done, scan, X_BW: np.ndarray):
    """The :class:`~gbh_drake.scan_grasps.result.GraspsResult` of a finished trial (a
    ``TrialRun``): :func:`grasps_result`, with the run's scenario, seed, method, the rank it
    executed and GbH's seconds."""
    record, scenario = done.record, done.trial.scenario
    result = grasps_result(done.trial, done.simulator.get_context(), scan, X_BW)
    executed = record.grasp_rank + 1 if record.grasp_source == "grasps" else 0
    result.extra = {"scenario": result.input_path, "seed": int(scenario.seed),
                    "method": scenario.grasp_method, "executed_rank": int(executed)}
    result.timings = {"gbh": float(record.timings.get("grasps", 0.0))}
    return result


def grasps_result(trial, context, scan, X_BW: np.ndarray):
    """The :class:`~gbh_drake.scan_grasps.result.GraspsResult` of ``trial`` (a
    :class:`~gbh_drake.trial.Trial`) in its root ``context``: GbH's structures, candidates and
    ranked grasps as the trial's systems made them (the method's own, also when given grasps
    were executed instead), in B (``X_BW``: the identity keeps them in W)."""
    from gbh_drake.core.hangability import detect_with_report
    from gbh_drake.core.scoring import score_grasps
    from gbh_drake.perception.scan import ScanResult
    from gbh_drake.perception.unseen import scan_unseen
    from gbh_drake.scan_grasps.result import make_result

    source, scenario = trial.source, trial.scenario

    def value(port):
        return None if port is None else port.Eval(port.get_system().GetMyContextFromRoot(context))

    hangability = value(source.hanging_structures)
    structures = hangability.structures if hangability is not None else []
    # The synthesizer's candidates, scored (the scorer scores copies of them).
    candidates = [copy.copy(g) for g in value(source.candidates) or []]
    score_grasps(candidates, scenario.gbh)
    ranked = value((source.method_tiers or source.tiers)[0].grasps) \
        if source.candidates is not None else []
    report = None
    if hangability is not None and not structures and hangability.object is not None:
        report = hangability.report or detect_with_report(hangability.object, scenario.gbh,
                                                          trial.seeds.sampling)[1]
    table = table_in(scan.table, X_BW) if scan.table is not None else None
    scan_B = dataclasses.replace(scan, mesh_W=_mesh_in(scan.mesh_W, X_BW)) \
        if not np.allclose(X_BW, np.eye(4)) else scan
    if table is None:
        from gbh_drake.perception.table import TablePlane

        table = TablePlane.horizontal(0.0)
    notes = [] if source.candidates is not None else [
        f"the grasp method {scenario.grasp_method!r} runs no GbH: no hook grasps"]
    result = make_result(
        structures_W=structures, candidates_W=candidates, ranked_W=list(ranked),
        params=scenario.gbh, seed=trial.seeds.sampling, scan_B=scan_B, table_B=table,
        table_source=table.source, X_BW=X_BW, pick=scenario.pick, hangability=report,
        input_kind="simulation", input_path=str(scenario.source_path or "<in memory>"),
        notes=notes, warnings=list(scan.warnings),
        unseen_B=_points_in(scan_unseen(scan), X_BW) if ranked else None,
        empty_message=scan.message if isinstance(scan, ScanResult) and scan.empty else "")
    return result


def _points_in(p_W: np.ndarray, X_BW: np.ndarray) -> np.ndarray:
    return np.asarray(p_W, dtype=float).reshape(-1, 3) @ X_BW[:3, :3].T + X_BW[:3, 3]


def _mesh_in(mesh_W, X_BW: np.ndarray):
    mesh = mesh_W.copy()
    mesh.apply_transform(X_BW)
    return mesh


def write_views(folder: Path, scan, config, X_BW: np.ndarray, *, gbh=None, seed: int | None = None,
                mesh: str | None = None) -> Path:
    """Writes ``scan``'s views (and its first look's) into ``folder`` as 16-bit PNGs (in the
    sensor's ``depth_unit``, losslessly, else 0.1 mm steps; a ray that hit nothing within range
    as ``no_hit_value``) with ``views.yaml``, in B. The depths are those measured (the noise
    included) and the free-space margins those the scan used. ``gbh`` (GbhParams) and
    ``seed``: GbH's, written into the file; ``mesh``: the scan's mesh file, relative to
    ``folder`` (omitted: ``gbh grasps`` fuses the views)."""
    import yaml

    from gbh_drake.outputs import plain
    from gbh_drake.perception.camera import CameraIntrinsics
    from gbh_drake.perception.scan import depth_error

    folder.mkdir(parents=True, exist_ok=True)
    n_views = len(scan.X_WCs)
    main = _view_set(scan.free_space.views[:n_views], scan.intrinsics, scan.X_WCs, X_BW,
                     depth_error(config, scan.view_distance), scan.robot_masks)
    scale = config.depth_unit or views_io.WRITE_DEPTH_SCALE
    entry: dict = {"version": views_io.VIEWS_VERSION, "depth_scale": scale,
                   "depth_range": [float(config.depth_min), float(config.depth_max)],
                   "no_hit_value": views_io.WRITE_NO_HIT}
    entry.update(_written(folder, "depth", main, config.depth_max, scale))
    look = scan.first_look_free_space
    if look is not None:
        v = look.views[0]
        first = _view_set(look.views, CameraIntrinsics(v.width, v.height, v.fx, v.fy, v.cx, v.cy),
                          scan.first_look_X_WCs, X_BW, look.depth_error,
                          scan.first_look_robot_masks)
        entry["first_look"] = _written(folder, "first_look", first, config.depth_max, scale)
    X = X_BW
    if scan.target_W is not None:
        entry["target"] = (X[:3, :3] @ scan.target_W + X[:3, 3]).tolist()
    if scan.table is not None:
        table = table_in(scan.table, X_BW)
        entry["table"] = {"normal": table.normal_W.tolist(), "height": table.height}
    if mesh is not None:
        entry["mesh"] = mesh
    entry["scan"] = {f.name: getattr(config, f.name) for f in dataclasses.fields(config)
                     if f.name not in ("noise", "depth_unit", "depth_min", "depth_max")}
    base_B = X[:3, :3] @ [*config.robot_base_xy, 0.0] + X[:3, 3]
    entry["scan"]["robot_base_xy"] = base_B[:2].tolist()  # (the same list in the station)
    if gbh is not None:
        entry["gbh"] = _gbh_in(gbh, X_BW)
    if seed is not None:
        entry["seed"] = int(seed)
    path = folder / views_io.VIEWS_FILE
    path.write_text("# Depth images of a gbh_drake scan, in the robot's base frame B "
                    "(docs/grasps.md).\n" + yaml.safe_dump(plain(entry), sort_keys=False,
                                                           default_flow_style=None, width=100))
    return path


def _view_set(depth_views, intrinsics, X_WCs, X_BW: np.ndarray, error: float,
              robot_masks=None) -> views_io.ViewSet:
    """A :class:`~gbh_drake.scan_grasps.views.ViewSet` in B of a scan's free-space views
    (their depths as measured: NaN where nothing was, ``depth_max`` where nothing was hit in
    range), the cameras at X_WC, with the scan's ``robot_masks`` (the self filter's pixels)."""
    return views_io.ViewSet(intrinsics, [v.depth for v in depth_views],
                            [X_BW @ X_WC.GetAsMatrix4() for X_WC in X_WCs], None, float(error),
                            [], robot_masks=robot_masks)


def _written(folder: Path, stem: str, views: views_io.ViewSet, depth_max: float,
             scale: float) -> dict:
    """Writes the images of ``views`` as ``<stem>_NNN.png`` (``scale`` m per unit) and its
    robot masks as ``<stem>_robot_NNN.png``; returns their YAML."""
    names = []
    for i, depth in enumerate(views.depths):
        name = f"{stem}_{i:03d}.png"
        views_io.write_png(folder / name, views_io.encode_depth(depth, scale,
                                                                 depth_max=depth_max))
        names.append(name)
    robot_names = None
    if views.robot_masks is not None:
        robot_names = [f"{stem}_robot_{i:03d}.png" for i in range(len(views.robot_masks))]
        for name, mask in zip(robot_names, views.robot_masks, strict=True):
            views_io.write_png(folder / name, np.asarray(mask, dtype=bool))
    return views_io.group_entry(views, names, robot_mask_names=robot_names)


def _gbh_in(params, X_BW: np.ndarray) -> dict:
    """GbhParams' fields, its ground (W) in B."""
    values = {f.name: getattr(params, f.name) for f in dataclasses.fields(params)}
    if not np.array_equal(X_BW, np.eye(4)):
        n_B = X_BW[:3, :3] @ np.asarray(params.ground_normal, dtype=float)
        values["ground_normal"] = n_B.tolist()
        values["ground_height"] = float(params.ground_height + n_B @ X_BW[:3, 3])
    return values
