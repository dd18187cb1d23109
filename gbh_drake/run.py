"""``gbh run``: one scenario, simulated, with its outputs written to its folder.

The steps of :func:`run`: build the trial diagram (:mod:`gbh_drake.trial`), simulate until the
pick-and-carry machine has finished (task ``pick``) or for the settle time (task ``settle``),
draw its replay in Meshcat from the poses recorded (:mod:`gbh_drake.replay`), then write
``replay.html`` (a self-contained Meshcat recording),
``summary.yaml`` (the :class:`~gbh_drake.trial.TrialRecord`) and ``scenario.yaml`` (the
resolved scenario, file plus overrides, so that ``gbh run <folder>/scenario.yaml`` repeats the
run) into the scenario's output folder, all or nothing (:mod:`gbh_drake.outputs`); a pick also
``scan.ply`` and ``grasps.json`` (and ``views/`` when asked), in the robot's base frame B
(:mod:`gbh_drake.scan_grasps.run_export`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import yaml
from pydrake.geometry import Meshcat

from gbh_drake.core.resting import rest_in_words
from gbh_drake.core.words import counted
from gbh_drake.outputs import RunOutputs, plain
from gbh_drake.scan_grasps.run_export import trial_export
from gbh_drake.scenario import Scenario, dump_resolved
from gbh_drake.scenario.loader import require_scenario
from gbh_drake.trial import TrialRecord, TrialRun, record_trial
from gbh_drake.viz.meshcat_server import local_meshcat

#: Below this mean squeeze (N) a closed loop is said to hold what hangs in it without squeezing.
LOOP_SQUEEZE = 5.0


@dataclass
class RunSummary:
    """What a run did and where its outputs are."""

    scenario: str
    task: str
    record: TrialRecord
    replay: str
    settle_drift: float
    """Horizontal distance (m) the object moved while settling (should be ~0)."""

    @property
    def realtime_rate(self) -> float:
        wall = self.record.timings.get("simulate", 0.0)
        return self.record.sim_time / wall if wall > 0 else float("inf")

    def to_text(self) -> str:
        r, v = self.record, self.record.verdict
        phases = ", ".join(r.phases)
        lines = [
            f"scenario {self.scenario}",
            f"  object {r.object} ({r.object_mass * 1000:.0f} g, {r.source}), seed {r.seed}, "
            f"method {r.method}, {r.num_views} view(s), task {self.task}",
            f"  start pose x {r.pose[0]:.3f} y {r.pose[1]:.3f} m, yaw "
            f"{np.degrees(r.pose[5]):.0f} deg, {rest_in_words(r.pose)}; "
            f"settling moved it {self.settle_drift * 1000:.1f} mm",
            f"  simulated {r.sim_time:.2f} s in {r.timings.get('simulate', 0.0):.2f} s wall "
            f"({self.realtime_rate:.2f}x real time); phases: {phases}",
        ]
        for w in r.warnings + r.scan_warnings:
            lines.append(f"  warning: {w}")
        if self.task == "pick":
            lines.append(f"  scan: {r.scan_faces} triangles {r.scan_message}".rstrip())
            lines.append(f"  grasps: {counted(r.n_structures, 'hanging structure')}, "
                         f"{counted(r.n_candidates, 'candidate')}, {r.n_ranked} ranked; "
                         f"{r.n_grasps_offered} offered")
            for text in r.refusal_texts:
                lines.append(f"  refused {text}")
            for note in r.plan_notes:
                lines.append(f"  plan: {note}")
            if r.grasp_rank >= 0:
                lines.append(f"  executed grasp #{r.grasp_rank + 1} ({r.grasp_kind}"
                             f"{', fallback' if r.fallback else ''}, score {r.grasp_score:.3g}); "
                             + _lift_in_words(r))
            verdict = "SUCCESS" if r.success else "FAILURE"
            held = f" [{r.held_by}]" if r.held_by else ""
            lines.append(f"  verdict: {verdict}{held}: {r.outcome}: {r.reason}")
            if "release" in r.phases and v.released_pose:
                down = set_down_in_words(v.released_pose, v.released_on_table,
                                         v.released_standing)
                lines.append(f"  set down: {down}")
            if v.squeeze_force == v.squeeze_force:  # not nan
                squeeze = f"squeeze {v.squeeze_force:.0f} N while carried"
                if v.loop_closed and v.squeeze_force < LOOP_SQUEEZE:
                    squeeze += " (the loop closed on its stop: what hangs in it is not squeezed)"
                lines.append(f"  {squeeze}; highest clearance {v.max_clearance * 100:.1f} cm; "
                             f"touching: {_touching(v.touching)}")
            lines.append("  timings: " + ", ".join(f"{k} {t:.2f} s" for k, t in r.timings.items()))
        lines.append(f"  replay: {self.replay}")
        return "\n".join(lines)


def _lift_in_words(r: TrialRecord) -> str:
    """The executed grasp's lift (the hand's, m -> cm) and place, as planned: said as done once
    the hand has lifted (its carry began), as planned and not reached before."""
    if "carry" in r.phases:  # lifted: the carry began
        return (f"lift {r.lift * 100:.1f} cm, hook point to ({r.place[0]:.2f}, "
                f"{r.place[1]:.2f}) m at the place")
    return f"lift {r.lift * 100:.1f} cm planned, not reached (the verdict says where it ended)"


def set_down_in_words(pose: list[float], on_table: bool, standing: bool = False) -> str:
    """Where the released object ended: ``pose`` (W: x, y, z m, roll, pitch, yaw rad), whether
    it lies free on the table, and whether it rests there at all (``standing``: the open hand
    may be left round it)."""
    where = f"at ({pose[0]:.2f}, {pose[1]:.2f}) m"
    if not on_table and standing:
        return f"it ended on the table {where}, {rest_in_words(pose)}, the gripper still touching it"
    if not on_table:
        return f"it ended {where}, not free on the table"
    return f"it ended free on the table {where}, {rest_in_words(pose)}"


def _touching(touching: dict[str, list[str]]) -> str:
    bodies = sorted({b for names in touching.values() for b in names})
    return ", ".join(bodies) or "nothing"


def run(scenario: Scenario, *, meshcat: Meshcat | None = None,
        save_views: bool = False, live: bool = False) -> RunSummary:
    """Simulates ``scenario`` and writes its outputs (see the module docstring); a pick also
    writes its scan and GbH's ranked grasps in the robot's base frame (``scan.ply``,
    ``grasps.json``) and, with ``save_views``, the views' depth images (``views/``:
    :mod:`gbh_drake.scan_grasps.run_export`). The replay is drawn in ``meshcat`` (default: a
    server of its own) after the trial; ``live``: the trial is drawn there as it runs too.

    The output folder is checked and locked before anything is built (a folder that is a file,
    not writable, on a full disk or in use by another run raises
    :class:`~gbh_drake.outputs.OutputError`); the outputs appear all together at the end, and a
    run that fails or is interrupted leaves none (:class:`~gbh_drake.outputs.RunOutputs`)."""
    require_scenario(scenario, "run")
    # Check and lock the output folder before anything is built.
    with RunOutputs(scenario.output_path()) as outputs:
        # Build the trial diagram, simulate it, record it (with its Meshcat replay).
        done = record_trial(scenario, meshcat=meshcat or local_meshcat(), live=live)
        # What the run did, in words.
        summary = RunSummary(scenario.source_path or "<in memory>", scenario.task, done.record,
                             str(outputs.path("replay.html")), _drift(done))
        # The outputs, all or nothing.
        outputs.stage("replay.html", done.replay_html)
        for name, data in trial_export(done).items():
            if callable(data):
                if save_views:
                    outputs.stage_folder(name, data)
            else:
                outputs.stage(name, data)
        outputs.stage("scenario.yaml", dump_resolved(scenario))
        outputs.stage("summary.yaml", yaml.safe_dump(
            {"scenario": summary.scenario, "task": summary.task, "replay": summary.replay,
             "settle_drift": summary.settle_drift, **plain(asdict(done.record))},
            sort_keys=False))
        outputs.commit()
    return summary


def _drift(done: TrialRun) -> float:
    """How far (m, horizontally) the object moved while settling: to the end of a ``settle``
    task, else until it was scanned."""
    if done.trial.scenario.task != "settle":
        return _settle_drift(done.record)
    station = done.trial.station
    plant = station.plant
    context = plant.GetMyContextFromRoot(done.simulator.get_context())
    p_WO = plant.GetFreeBodyPose(context, station.object_body()).translation()
    return float(np.linalg.norm((p_WO - station.X_WO_initial.translation())[:2]))


def _settle_drift(record: TrialRecord) -> float:
    """How far (m, horizontally) the object moved between its start and the scan."""
    settled = record.verdict.settled_at or record.pose[:3]
    return float(np.linalg.norm(np.subtract(settled[:2], record.pose[:2])))
