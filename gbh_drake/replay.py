"""A trial's replay, drawn after the trial from the body poses recorded during it.

During the trial, :func:`add_pose_log` records the station's arm, gripper and object states at
the scenario's ``replay_fps`` (three of Drake's ``VectorLogSink``: a copy of 33 numbers per
frame, nothing drawn). A Meshcat recorder running during the trial would cost it 10-12 %
(``bench/bench_meshcat.py``): here a trial without a live view pays nothing for its replay, and
one whose replay is not kept (the experiment keeps failures') pays nothing at all.

After the trial, :func:`draw_replay` builds a second station from the same scenario and object
with Meshcat's visualisers only (contact forces left out: they need the solver's step), puts its
plant in each recorded frame and publishes it into a Meshcat recording. Over it, what the
trial's systems saw and chose (the scanned object, the hanging structures, the ranked grasps,
the executed grasp open and closed; when no grasp passed the refused ones, when nothing was
hangable the refused hanging positions; for a failed trial the cameras and what they did not
see), each shown from the moment it existed (colours and legend:
:mod:`gbh_drake.viz.palette`). The camera is framed on the object and follows it.
:func:`replay_page` gives the recording as one self-contained HTML page, with a title that says
the verdict and the legend of what is drawn.
"""

from __future__ import annotations

import copy
import html
import json
from dataclasses import dataclass

import numpy as np
from pydrake.geometry import Meshcat, MeshcatVisualizer
from pydrake.math import RigidTransform
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import LogVectorOutput, VectorLogSink

from gbh_drake.core.gripper import GRIPPERS
from gbh_drake.modeling.names import ARM, GRIPPER
from gbh_drake.station import Station, make_station
from gbh_drake.viz import palette

#: The station's state ports the replay records.
LOGGED = ("panda.state", "hook_gripper.state", "object.state")
#: Where the replay's camera looks at the object from (W, a direction; scaled to its size).
CAMERA_DIRECTION = np.array([0.85, -1.0, 0.65]) / np.linalg.norm([0.85, -1.0, 0.65])
#: The camera's distance (m) from the object's centre: this many times its radius, within
#: [MIN_VIEW, MAX_VIEW], through a lens of FOV_DEG (vertical; Meshcat's default is 75): the
#: default mug spans about a third of the frame's width, a 5 cm cup a sixth.
VIEW_RADII, MIN_VIEW, MAX_VIEW, FOV_DEG = 5.0, 0.25, 2.0, 40.0
#: A failed trial's replay stands back this many times the scan cameras' distance: they are in
#: view.
CAMERAS_IN_VIEW = 2.4
#: A failed trial's object is drawn at this opacity: its scan and what the cameras did not see
#: are inside it.
SEE_THROUGH = 0.35
#: Where everything drawn over the simulation lives (under Meshcat's root).
PREFIX = "gbh"


@dataclass
class PoseLog:
    """The trial's recorded states (:func:`add_pose_log`): one ``VectorLogSink`` per port of
    :data:`LOGGED`."""

    sinks: dict[str, VectorLogSink]

    def frames(self, context) -> Frames:
        """What the sinks recorded in the trial's root ``context``."""
        logs = {name: sink.FindLog(context) for name, sink in self.sinks.items()}
        t = logs[LOGGED[0]].sample_times()
        data = {name: log.data().T[:len(t)] for name, log in logs.items()}
        return Frames(np.asarray(t, dtype=float), *(data[name] for name in LOGGED))


@dataclass
class Frames:
    """Recorded states by time: ``t`` (n,) s; ``arm`` (n, 14) [q, v]; ``gripper`` (n, 6);
    ``object`` (n, 13): [quaternion (4), p (3), w (3), v (3)] in W."""

    t: np.ndarray
    arm: np.ndarray
    gripper: np.ndarray
    object: np.ndarray


def add_pose_log(builder: DiagramBuilder, station: Station, fps: float) -> PoseLog:
    """Logs the station's arm, gripper and object states ``fps`` times per simulated second."""
    return PoseLog({name: LogVectorOutput(station.GetOutputPort(name), builder, 1.0 / fps)
                    for name in LOGGED})


@dataclass
class Replay:
    """What :func:`draw_replay` drew: the legend's keys, and the Meshcat paths drawn see-through
    (at :data:`SEE_THROUGH`)."""

    legend: list[palette.Key]
    see_through: list[str]


def draw_replay(meshcat: Meshcat, trial, context, record) -> Replay:
    """Draws the finished ``trial`` (a :class:`~gbh_drake.trial.Trial` built with a pose log;
    ``context``: its root context after the run; ``record``: its
    :class:`~gbh_drake.trial.TrialRecord`) into ``meshcat`` as a recording (the module
    docstring). ``meshcat``'s scene and recording are replaced."""
    scenario = trial.scenario
    frames = trial.poses.frames(context)
    meshcat.Delete()
    meshcat.DeleteRecording()
    meshcat.StartRecording(frames_per_second=scenario.replay_fps,
                           set_visualizations_while_recording=False)
    _draw_frames(meshcat, _replay_station(scenario, trial, meshcat), frames)
    asset = trial.station.asset
    legend = [palette.Key(f"object ({record.object})", tuple(asset.rgba))]
    seen = draw_what_was_seen(meshcat, trial, context, record, end=float(frames.t[-1]))
    legend += seen.keys
    see_through = []
    if not record.success and seen.scanned_at is not None:
        # The scan and what was not seen are inside the object: see through it.
        see_through.append(f"/drake/illustration/{asset.model_name}")
        meshcat.SetProperty(see_through[-1], "modulated_opacity", SEE_THROUGH)
    _follow(meshcat, asset, frames, seen.camera_distance)
    meshcat.StopRecording()
    meshcat.PublishRecording()
    return Replay(legend, see_through)


def replay_page(meshcat: Meshcat, record, replay: Replay, detail: str = "") -> str:
    """``meshcat``'s scene and recording as one self-contained HTML page, with the title (the
    object, method, views and the verdict; below it ``detail``, default the record's reason)
    and the legend over it."""
    return with_overlay(meshcat.StaticHtml(), title(record), detail or record.reason,
                        replay.legend, replay.see_through)


def title(record) -> str:
    """The replay's title: ``mug_classic · gbh, 10 views · SUCCESS (cage)``."""
    if record.outcome == "success" or record.success:
        verdict = f"SUCCESS ({record.held_by})" if record.held_by else "SUCCESS"
    else:
        verdict = f"FAILURE: {record.outcome}"
    views = f"{record.num_views} view{'s' if record.num_views != 1 else ''}"
    grasp = f" · grasp #{record.grasp_rank + 1} {record.grasp_kind}" if record.grasp_rank >= 0 \
        else ""
    return f"{record.object} · {record.method}, {views} · {verdict}{grasp}"


def with_overlay(page: str, heading: str, detail: str, legend: list[palette.Key],
                 see_through: list[str] = ()) -> str:
    """``page`` (a Meshcat page) with a title box (``heading`` over ``detail``) at its top and a
    legend box at its bottom left, and the Meshcat paths ``see_through`` drawn at
    :data:`SEE_THROUGH` (a page's saved properties come before the objects they apply to, so
    this is said again after each of its saved commands): plain HTML, CSS and a line of
    script, nothing fetched."""
    items = "".join(
        f'<div><span style="display:inline-block;width:12px;height:12px;margin-right:6px;'
        f'vertical-align:middle;background:{palette.css(k.rgba)}"></span>'
        f"{html.escape(k.label)}</div>" for k in legend)
    box = ("position:fixed;z-index:10;background:rgba(255,255,255,0.88);color:#111;"
           "border-radius:4px;font-family:sans-serif;pointer-events:none;")
    overlay = (
        f'<div id="gbh-title" style="{box}top:8px;left:50%;transform:translateX(-50%);'
        f'max-width:60%;padding:6px 12px;text-align:center">'
        f'<div style="font-weight:600;font-size:16px">{html.escape(heading)}</div>'
        f'<div style="font-size:12px;margin-top:2px">{html.escape(detail)}</div></div>'
        f'<div id="gbh-legend" style="{box}bottom:8px;left:8px;padding:6px 10px;'
        f'font-size:12px;line-height:17px">{items}</div>')
    if see_through:  # (the page hands its saved commands to the viewer asynchronously)
        paths = ", ".join(json.dumps(path) for path in see_through)
        overlay += (
            "<script>{const handle = viewer.handle_command_bytearray.bind(viewer);"
            "viewer.handle_command_bytearray = (data) => {handle(data);"
            f"for (const p of [{paths}]) viewer.set_property(p.split('/').filter(Boolean), "
            f"'modulated_opacity', {SEE_THROUGH});}};}}</script>")
    at = page.rfind("</body>")
    return page[:at] + overlay + page[at:] if at >= 0 else page + overlay


@dataclass
class Seen:
    """What :func:`draw_what_was_seen` drew: the legend's keys, when the scan was taken (None:
    no scan) and, when the cameras were drawn, how far (m) a camera must stand from the object
    to see them (0 otherwise)."""

    keys: list[palette.Key]
    scanned_at: float | None = None
    camera_distance: float = 0.0


def draw_what_was_seen(meshcat: Meshcat, trial, context, record, *, end: float,
                       prefix: str = PREFIX) -> Seen:
    """What the trial's systems saw and chose (the module docstring), drawn under ``prefix`` and
    shown from when it existed (into the recording, when one is running)."""
    from gbh_drake.core.grasp_synthesis import closed_gripper
    from gbh_drake.core.rejections import closest_rejected
    from gbh_drake.systems.scanner import scan_pending
    from gbh_drake.viz import gbh_meshcat as draw

    def value(port):
        return None if port is None else port.Eval(port.get_system().GetMyContextFromRoot(context))

    scan = value(trial.scanner.GetOutputPort("mesh_W"))
    if scan is None or scan_pending(scan):
        return Seen([])
    status = value(trial.pick.GetOutputPort("status"))
    source, gripper = trial.source, GRIPPERS[trial.scenario.gripper]
    t_scan = scan.taken_at if np.isfinite(scan.taken_at) else 0.0
    t_plan = status.phase_start.get("plan", t_scan)
    t_close = status.phase_start.get("close", end)
    keys: list[palette.Key] = []

    def shown(path: str, key: palette.Key | None, start: float, stop: float = end) -> None:
        _visible_between(meshcat, f"{prefix}/{path}", start, stop, end)
        if key is not None and key not in keys:
            keys.append(key)

    key = {k.rgba: k for k in palette.LEGEND}
    if len(scan.mesh_W.faces):
        draw.draw_object(meshcat, scan.mesh_W, prefix)
        shown("object", key[palette.SCAN], t_scan)
    hangability = value(source.hanging_structures)
    if hangability is not None and hangability.structures:
        draw.draw_structures(meshcat, hangability.structures, prefix)
        shown("structures", key[palette.STRUCTURE], t_scan)
        keys += [key[palette.AXIS], key[palette.MISSED]]
    elif hangability is not None and hangability.report is not None and \
            hangability.report.refused:
        draw.draw_refused_positions(meshcat, hangability.report.refused, prefix)
        shown("refused_positions", key[palette.REFUSED_POSITION], t_scan)
    ranked = value(source.grasps) or []
    if ranked:
        draw.draw_grasps(meshcat, ranked, prefix, n_solid=0, gripper=gripper)
        shown("grasps", key[palette.RANKED], t_plan, t_close)
    elif source.candidates is not None:
        refused = closest_rejected(value(source.candidates) or [], trial.scenario.gbh, 3)
        if refused:
            draw.draw_grasps(meshcat, refused, prefix, n_solid=0, gripper=gripper,
                             rgba=draw.REFUSED, folder="refused")
            shown("refused", key[palette.REFUSED], t_plan)
    if status.grasp_X_WG is not None and status.plan is not None:
        X_closed, q_closed = closed_gripper(status.grasp_X_WG, status.plan.kind, gripper)
        draw.draw_gripper(meshcat, f"{prefix}/chosen/open", status.grasp_X_WG, gripper.q_open,
                          gripper, rgba=draw.CHOSEN, solid_rgba=draw.GRIPPER)
        draw.draw_gripper(meshcat, f"{prefix}/chosen/closed", X_closed, q_closed, gripper,
                          rgba=draw.CLOSED)
        shown("chosen", key[palette.CHOSEN], t_plan, t_close)
        keys.append(key[palette.CLOSED])
    seen = Seen(keys, t_scan)
    if not record.success:
        seen.camera_distance = draw_cameras(meshcat, scan, prefix)
        shown("cameras", key[palette.CAMERA], t_scan)
        from gbh_drake.perception.unseen import scan_unseen

        unseen = scan_unseen(scan)
        if len(unseen):
            draw.draw_points(meshcat, f"{prefix}/unseen", unseen, draw.UNSEEN, size=0.006)
            shown("unseen", key[palette.UNSEEN], t_scan)
    return seen


def draw_cameras(meshcat: Meshcat, scan, prefix: str = PREFIX) -> float:
    """The scan's cameras (``<prefix>/cameras/views``) and its first look's
    (``<prefix>/cameras/first_look``) as frusta; returns the distance (m) from the scanned
    object's centre to the farthest of the views' cameras (0 without a scan)."""
    from gbh_drake.viz import gbh_meshcat as draw

    if scan.intrinsics is not None and scan.X_WCs:
        draw.draw_cameras(meshcat, f"{prefix}/cameras/views", scan.X_WCs, scan.intrinsics)
    look = scan.first_look_free_space
    if look is not None and scan.first_look_X_WCs:
        draw.draw_cameras(meshcat, f"{prefix}/cameras/first_look", scan.first_look_X_WCs,
                          look.views[0], rgba=draw.FIRST_LOOK, depth=0.12)
    if not scan.X_WCs or not len(scan.mesh_W.vertices):
        return 0.0
    centre = np.asarray(scan.mesh_W.bounds, dtype=float).mean(axis=0)
    return max(float(np.linalg.norm(X.translation() - centre)) for X in scan.X_WCs)


def _visible_between(meshcat: Meshcat, path: str, start: float, stop: float,
                     end: float) -> None:
    """Shows ``path`` in the recording from ``start`` to ``stop`` (s; hidden before and
    after)."""
    if start > 0:
        meshcat.SetProperty(path, "visible", False, 0.0)
    meshcat.SetProperty(path, "visible", True, max(start, 0.0))
    if stop < end:
        meshcat.SetProperty(path, "visible", False, stop)


def _replay_station(scenario, trial, meshcat: Meshcat) -> Station:
    """The station drawn in the replay: the trial's models and object, Meshcat's visualisers
    (its contact forces left out), no cameras."""
    visualization = copy.copy(scenario.visualization)
    visualization.publish_contacts = False
    drawn = copy.copy(scenario)
    drawn.cameras, drawn.visualization = [], visualization
    return make_station(drawn, meshcat=meshcat, object_asset=trial.station.asset,
                        seeds=trial.seeds)


def _draw_frames(meshcat: Meshcat, station: Station, frames: Frames) -> None:
    """Publishes ``station``'s Meshcat visualisers at each recorded frame."""
    plant = station.plant
    context = station.CreateDefaultContext()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    arm, gripper = plant.GetModelInstanceByName(ARM), plant.GetModelInstanceByName(GRIPPER)
    obj = plant.GetModelInstanceByName(station.object_name)
    visualizers = [s for s in station.GetSystems() if isinstance(s, MeshcatVisualizer)]
    for k, t in enumerate(frames.t):
        context.SetTime(float(t))
        plant.SetPositions(plant_context, arm, frames.arm[k, :7])
        plant.SetPositions(plant_context, gripper, frames.gripper[k, :3])
        plant.SetPositions(plant_context, obj, frames.object[k, :7])
        for visualizer in visualizers:
            visualizer.ForcedPublish(visualizer.GetMyContextFromRoot(context))


def _follow(meshcat: Meshcat, asset, frames: Frames, cameras: float = 0.0) -> None:
    """Frames the object at the start (:func:`frame`) and keeps it there: the scene (``/drake``,
    where everything is drawn, and the grid) moves back by as much as the object moved, which
    looks as a camera following it does. (Moving the camera itself turns it: Meshcat's orbit
    controls keep it looking at their fixed target.)"""
    centre_O, radius = extent(asset)
    p = np.array([_centre_W(x, centre_O) for x in frames.object])
    frame(meshcat, p[0], radius, cameras)
    for t, p_t in zip(frames.t, p, strict=True):
        for path in ("/drake", "/Grid"):
            meshcat.SetTransform(path, RigidTransform(p[0] - p_t), float(t))


def frame(meshcat: Meshcat, centre_W, radius: float, cameras: float = 0.0) -> None:
    """Points Meshcat's camera at ``centre_W`` (3,) through a narrow lens (:data:`FOV_DEG`),
    from :data:`CAMERA_DIRECTION`, :data:`VIEW_RADII` times ``radius`` (m) away, or far enough
    to see cameras ``cameras`` m from it (within [:data:`MIN_VIEW`, :data:`MAX_VIEW`])."""
    centre_W = np.asarray(centre_W, dtype=float)
    distance = float(np.clip(max(VIEW_RADII * radius, CAMERAS_IN_VIEW * cameras), MIN_VIEW,
                             MAX_VIEW))
    meshcat.SetCamera(Meshcat.PerspectiveCamera(fov=FOV_DEG, near=0.01, far=100.0))
    meshcat.SetCameraPose(camera_in_world=centre_W + distance * CAMERA_DIRECTION,
                          target_in_world=centre_W)


def extent(asset) -> tuple[np.ndarray, float]:
    """The object's bounding-box centre (3, in O) and the radius (m) of the sphere round it."""
    lo, hi = np.asarray(asset.mesh.bounds, dtype=float)
    return 0.5 * (lo + hi), 0.5 * float(np.linalg.norm(hi - lo))


def _centre_W(x: np.ndarray, centre_O: np.ndarray) -> np.ndarray:
    """The object's bounding-box centre in W, the object's state being ``x`` (13,)."""
    from pydrake.common.eigen_geometry import Quaternion

    q = np.asarray(x[:4], dtype=float)
    R = Quaternion(q / np.linalg.norm(q)).rotation()
    return R @ centre_O + np.asarray(x[4:7], dtype=float)
