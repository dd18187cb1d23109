"""What the studio draws at each step, and the words it says beside it.

The drawing is the one ``gbh grasps --html`` and the replays use
(:mod:`gbh_drake.scan_grasps.page`, :mod:`gbh_drake.viz.gbh_meshcat`, the cameras of
:mod:`gbh_drake.replay`; colours :mod:`gbh_drake.viz.palette`), in W, under ``studio/``; the
explanations are the detector's report (:class:`~gbh_drake.core.results.HangabilityReport`),
the collision rules' counts (:mod:`gbh_drake.core.rejections`), the planner's refusal
(:class:`~gbh_drake.planning.pick.Refusal`) and the monitor's verdict, as ``gbh grasps`` and
``gbh run`` say them.
"""

from __future__ import annotations

import numpy as np
from pydrake.geometry import Meshcat

from gbh_drake.core.gripper import GRIPPERS
from gbh_drake.core.words import counted
from gbh_drake.replay import draw_cameras, extent, frame
from gbh_drake.viz import gbh_meshcat as draw

#: Where the studio draws (under Meshcat's ``/drake``).
PREFIX = "studio"
#: Spacing (m) of the free-space points drawn, and how far (m) round the scan they are drawn.
FREE_STEP, FREE_AROUND = 0.006, 0.03


def frame_object(meshcat: Meshcat, session, cameras: float = 0.0) -> None:
    """Points the camera at the placed object (and its scan's cameras, ``cameras`` m away)."""
    from pydrake.common.eigen_geometry import Quaternion

    trial = session.trial
    x = trial.station.GetOutputPort("object.state").Eval(
        trial.station.GetMyContextFromRoot(session.simulator.get_context()))
    centre_O, radius = extent(session.asset())
    R = Quaternion(np.asarray(x[:4]) / np.linalg.norm(x[:4])).rotation()
    frame(meshcat, R @ centre_O + np.asarray(x[4:7]), radius, cameras)


def clear(meshcat: Meshcat, what: str = "") -> None:
    """Removes what the studio drew (``what``: one part of it, e.g. ``grasp``)."""
    meshcat.Delete(f"{PREFIX}/{what}" if what else PREFIX)


def draw_scan(meshcat: Meshcat, scan) -> float:
    """The fused scan (translucent blue) and the cameras that took it (frusta); returns the
    farthest camera's distance from the scan (m)."""
    clear(meshcat)
    if len(scan.mesh_W.faces):
        draw.draw_object(meshcat, scan.mesh_W, PREFIX)
    return draw_cameras(meshcat, scan, PREFIX)


def draw_free_space(meshcat: Meshcat, scan) -> int:
    """What the cameras saw free round the scan (white points every :data:`FREE_STEP` within
    :data:`FREE_AROUND` of its box, above the table); returns how many."""
    if scan.free_space is None or not len(scan.mesh_W.vertices):
        return 0
    lo, hi = np.asarray(scan.mesh_W.bounds, dtype=float)
    lo, hi = lo - FREE_AROUND, hi + FREE_AROUND
    lo[2] = max(lo[2], float(np.asarray(scan.mesh_W.bounds)[0, 2]))
    axes = [np.arange(a, b, FREE_STEP) for a, b in zip(lo, hi, strict=True)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    free = grid[scan.free_space.observed_free(grid)]
    draw.draw_points(meshcat, f"{PREFIX}/free_space", free, draw.FREE, size=0.003)
    return len(free)


def draw_detection(meshcat: Meshcat, detection) -> None:
    """The hanging structures (and the positions the detector refused)."""
    from gbh_drake.scan_grasps.page import draw_detection as draw_structures

    clear(meshcat, "structures")
    clear(meshcat, "refused_positions")
    draw_structures(meshcat, detection.result, PREFIX)


def draw_offered(meshcat: Meshcat, session, index: int, near: list) -> None:
    """Offered grasp ``index`` open and closed (GbH's: :func:`~gbh_drake.scan_grasps.page.
    draw_grasp`; a refused one in purple) and the refused candidates ``near`` it (purple)."""
    from gbh_drake.core.grasp_synthesis import closed_gripper
    from gbh_drake.scan_grasps.page import draw_grasp, draw_refused

    clear(meshcat, "grasp")
    clear(meshcat, "near")
    gripper = GRIPPERS[session.scenario.gripper]
    offered = session.detection.offered[index]
    path = f"{PREFIX}/grasp"
    if offered.shown is not None and not offered.rule:
        draw_grasp(meshcat, offered.shown, path, gripper)
    else:
        g = offered.grasp
        X_closed, q_closed = closed_gripper(g.X_WG, g.kind, gripper)
        colour = draw.REFUSED if offered.rule else draw.CHOSEN
        draw.draw_gripper(meshcat, f"{path}/open", g.X_WG, gripper.q_open, gripper,
                          rgba=colour, solid_rgba=draw.GRIPPER)
        draw.draw_gripper(meshcat, f"{path}/closed", X_closed, q_closed, gripper,
                          rgba=draw.CLOSED)
    if near:
        draw_refused(meshcat, [r.candidate for r in near], PREFIX, folder="near")


# ---- words ----------------------------------------------------------------------------------
def placed_lines(session, clock) -> list[str]:
    """The object, where, and how it rests."""
    c, asset = session.choices, session.asset()
    rest = "drop (drawn by probability from the seed)" if c.rest < 0 else \
        f"rest {c.rest} of {len(session.rests().poses)} " \
        f"(p {session.rests().poses[c.rest].probability:.2f})"
    return [f"{session.objects[c.object].label}: {asset.mass * 1000:.0f} g, {asset.source}",
            f"at x {c.x:.3f} y {c.y:.3f} m, yaw {c.yaw_deg:.0f} deg; {rest}",
            f"{c.views} view(s), method {c.method}, preset {c.preset or 'ours'}, seed {c.seed}",
            f"settled ({clock})"]


def scan_lines(scan, clock) -> list[str]:
    """What the scan holds."""
    if scan.empty:
        return [f"scan: empty: {scan.message} ({clock})"]
    lines = [f"scan: {len(scan.X_WCs)} views, {len(scan.mesh_W.faces)} triangles, taken at "
             f"t = {scan.taken_at:.2f} s ({clock})"]
    lines += [f"warning: {w}" for w in scan.warnings]
    return lines


def detection_lines(detection) -> list[str]:
    """What the detector found and refused, what each collision rule removed."""
    from gbh_drake.core.rejections import RULES

    result, lines = detection.result, []
    structures = result.structures
    if structures:
        ms = ", ".join(f"{s.m:.2f}" for s in structures[:4])
        lines.append(f"detect: {counted(len(structures), 'hanging structure')} (m {ms})")
    lines += list(result.notes)  # e.g. a method that runs no GbH
    if result.none is not None and not result.notes:
        lines.append(f"{result.none.outcome}: {result.none.message}")
    report = result.hangability
    if report is not None and structures:
        lines.append("positions refused: " + ", ".join(
            f"{rule} {n}" for rule, n in report.refused_by().items()))
    if detection.candidates:
        removed = detection.rejections.removed
        lines.append(f"{len(detection.candidates)} candidates; removed: " + ", ".join(
            f"{rule} {removed.get(rule, 0)}" for rule in RULES) +
            f"; {detection.rejections.passed} passed")
    n = sum(o.rule == "" for o in detection.offered)
    if n:
        lines.append(f"{n} grasps offered ({detection.clock})")
    elif detection.offered:
        lines.append("no grasp offered: the rank slider shows the refused ones that came "
                     "closest")
    else:
        lines.append(f"no grasp offered ({detection.clock})")
    return lines


def offered_lines(session, index: int, near: list) -> list[str]:
    """Offered grasp ``index``: what it is, its score's terms, and the refused ones near it."""
    offered = session.detection.offered[index]
    n = len(session.detection.offered)
    g = offered.grasp
    if offered.rule:
        lines = [f"refused {index + 1}/{n}: {offered.rule}: {offered.words}"]
    else:
        tier = offered.tier.value if offered.tier is not None else ""
        score = getattr(g, "score", float("nan"))
        lines = [f"grasp {index + 1}/{n} ({tier} #{offered.rank + 1}): {g.kind}, "
                 f"score {score:.3f}"]
        shown = offered.shown
        if shown is not None:
            t = shown.terms
            beta = "" if np.isnan(t["beta_deg"]) else f", beta {t['beta_deg']:.0f} deg"
            lines.append(f"= m {t['m']:.2f} x S_alpha {t['s_alpha']:.2f} x S_beta "
                         f"{t['s_beta']:.2f} (alpha {t['alpha_deg']:.0f} deg{beta})")
    for r in near:
        d = np.linalg.norm(np.asarray(r.candidate.X_WG)[:3, 3] - np.asarray(g.X_WG)[:3, 3])
        lines.append(f"near ({d * 1000:.0f} mm), refused by {r.rule}: {r.words}")
    return lines


def plan_lines(plan) -> list[str]:
    """What the planner would do with the grasp."""
    from gbh_drake.planning.pick import Refusal

    if isinstance(plan, Refusal):
        return [f"planner would refuse it: {plan.text()}"]
    return [f"planner: plannable (lift {plan.lift * 100:.1f} cm)"]


def stopped_lines(record, sim_from: float) -> list[str]:
    """An Execute that Reset stopped: where the pick was (no verdict)."""
    return [f"stopped by Reset after {record.sim_time - sim_from:.1f} s simulated: "
            f"{record.reason}"]


def verdict_lines(record, sim_from: float) -> list[str]:
    """The monitor's verdict on the executed grasp."""
    verdict = "SUCCESS" if record.success else "FAILURE"
    held = f" ({record.held_by})" if record.held_by else ""
    simulated = record.sim_time - sim_from
    wall = record.timings.get("simulate", 0.0)
    rate = simulated / wall if wall > 0 else float("inf")
    return [f"verdict: {verdict}{held}: {record.outcome}", record.reason,
            f"simulated {simulated:.1f} s in {wall:.1f} s ({rate:.2f}x real time)"]
