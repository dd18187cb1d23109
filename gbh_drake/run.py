"""Runs a scenario: the whole Grasping-by-Hanging trial, or only the station's settling.

The steps of :func:`run`, in order:

1. build the diagram: station (plant, scene graph, cameras, Meshcat), trajectory sources for the
   arm and fingers, and the GbH systems ``Scanner -> HangabilityDetector -> GraspSynthesizer ->
   GraspScorer``;
2. simulate the settle phase (the robot holds its home configuration);
3. (task ``pick``) evaluate ``ranked_grasps``: the scene is scanned as it is now, fused by TSDF,
   and GbH runs on the scanned mesh; then take the first of the top-k grasps whose pick motion
   has an IK solution at every waypoint, load that motion into the trajectory sources, simulate
   it, and judge from the object's and gripper's poses whether the object was carried
   (:mod:`gbh_drake.verdict`: contact only, the object is never welded);
4. write ``replay.html`` (a self-contained Meshcat recording) and ``summary.yaml``.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import asdict, dataclass, field

import numpy as np
import yaml
from pydrake.geometry import Meshcat
from pydrake.math import RigidTransform
from pydrake.systems.analysis import ApplySimulatorConfig, Simulator
from pydrake.systems.framework import Diagram, DiagramBuilder
from pydrake.systems.primitives import TrajectorySource

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.core.results import VERTICAL
from gbh_drake.planning.collision import make_planning_model
from gbh_drake.planning.pick import PickPlanning, pick_script
from gbh_drake.planning.trajectories import MotionScript
from gbh_drake.scenario import Scenario
from gbh_drake.station import ObjectAsset, Station, add_station
from gbh_drake.systems.grasp_scorer import GraspScorer
from gbh_drake.systems.grasp_synthesizer import GraspSynthesizer
from gbh_drake.systems.hangability_detector import HangabilityDetector
from gbh_drake.systems.scanner import Scanner
from gbh_drake.verdict import Sample, Verdict, judge
from gbh_drake.viz.meshcat_server import local_meshcat


@dataclass
class Built:
    """A built scenario diagram and handles to its parts."""

    diagram: Diagram
    station: Station
    script: MotionScript
    """The motion loaded at build time (the settle phase)."""
    arm_source: TrajectorySource
    finger_source: TrajectorySource
    scanner: Scanner
    detector: HangabilityDetector
    synthesizer: GraspSynthesizer
    scorer: GraspScorer


@dataclass
class PickOutcome:
    """What the GbH pipeline found and what came of it."""

    scan_faces: int = 0
    scan_message: str = ""
    n_structures: int = 0
    n_candidates: int = 0
    n_ranked: int = 0
    chosen_rank: int = -1
    """Rank (0 = best) of the executed grasp among the top-k; -1 if none was reachable."""
    chosen_kind: str = ""
    chosen_score: float = 0.0
    success: bool = False
    reason: str = ""
    lift: float = 0.0
    clearance: float = 0.0
    """Lowest point of the object above the table at the end (m)."""
    timings: dict[str, float] = field(default_factory=dict)
    """Wall seconds: scan (render + fusion), gbh (detect + synthesise + score), plan (IK,
    collision checks and RRT-Connect over the tried grasps)."""


@dataclass
class RunSummary:
    """What a run did. Lengths in metres, times in seconds."""

    scenario: str
    object: str
    object_mass: float
    seed: int
    task: str
    sim_time: float
    wall_time: float
    realtime_rate: float
    p_WO_initial: list[float]
    p_WO_final: list[float]
    settle_drift: float
    """Horizontal distance the object moved while settling (should be ~0)."""
    replay: str
    phases: list[str] = field(default_factory=list)
    pick: PickOutcome | None = None

    def to_text(self) -> str:
        lines = [
            f"scenario {self.scenario}",
            f"  object {self.object} ({self.object_mass * 1000:.0f} g), seed {self.seed}, "
            f"task {self.task}",
            f"  simulated {self.sim_time:.2f} s in {self.wall_time:.2f} s wall "
            f"({self.realtime_rate:.2f}x real time); phases: {', '.join(self.phases)}",
            f"  settling moved the object {self.settle_drift * 1000:.1f} mm",
        ]
        p = self.pick
        if p is not None:
            lines.append(f"  scan: {p.scan_faces} triangles {p.scan_message}".rstrip())
            lines.append(f"  GbH: {p.n_structures} hanging structures, {p.n_candidates} grasps, "
                         f"{p.n_ranked} ranked")
            if p.chosen_rank >= 0:
                lines.append(f"  executed grasp #{p.chosen_rank + 1} ({p.chosen_kind}, "
                             f"score {p.chosen_score:.3f})")
            verdict = "SUCCESS" if p.success else "FAILURE"
            lines.append(f"  verdict: {verdict}: {p.reason} (lift {p.lift * 100:.1f} cm, "
                         f"clearance {p.clearance * 100:.1f} cm)")
            lines.append("  timings: " + ", ".join(f"{k} {v:.2f} s" for k, v in p.timings.items()))
        lines.append(f"  replay: {self.replay}")
        return "\n".join(lines)


def settle_script(station: Station, duration: float) -> MotionScript:
    """Holds the home configuration with the gripper as the scenario says, for ``duration`` s."""
    opened = station.plant.GetDefaultPositions(station.gripper)[0] > HOOK_GRIPPER.q_closed + 1e-6
    q_f = HOOK_GRIPPER.q_open if opened else HOOK_GRIPPER.q_closed
    return MotionScript().start(station.q_home, q_f).hold(max(duration, 1e-3), "settle")


def build_diagram(scenario: Scenario, script_fn=None, *, meshcat: Meshcat | None = None,
                  object_asset: ObjectAsset | None = None) -> Built:
    """The diagram of ``scenario`` (see the module docstring).

    ``script_fn(station) -> MotionScript`` chooses the initial motion (default: settle in place);
    ``object_asset`` replaces the scenario's object."""
    builder = DiagramBuilder()
    station = add_station(builder, scenario, meshcat=meshcat, object_asset=object_asset)
    script = (script_fn or (lambda s: settle_script(s, scenario.settle_time)))(station)

    # Robot commands: joint trajectories into the PD controllers' desired states.
    arm = builder.AddNamedSystem(
        "arm_trajectory", TrajectorySource(script.arm_trajectory(), output_derivative_order=1))
    fingers = builder.AddNamedSystem(
        "finger_trajectory",
        TrajectorySource(script.finger_trajectory(), output_derivative_order=1))
    builder.Connect(arm.get_output_port(), station.arm_desired_state)
    builder.Connect(fingers.get_output_port(), station.gripper_desired_state)

    # Perception and GbH: scan -> hanging structures -> grasps -> ranked grasps.
    scan_config = dataclasses.replace(scenario.scan, noise_seed=scenario.seed)
    gbh_params = dataclasses.replace(scenario.gbh, seed=scenario.seed)
    scanner = builder.AddNamedSystem("scanner", Scanner(scan_config, scenario.scan_target))
    detector = builder.AddNamedSystem("hangability_detector", HangabilityDetector(gbh_params))
    synthesizer = builder.AddNamedSystem("grasp_synthesizer", GraspSynthesizer(gbh_params))
    scorer = builder.AddNamedSystem("grasp_scorer", GraspScorer(gbh_params))
    builder.Connect(station.scene_graph.get_query_output_port(), scanner.get_input_port())
    builder.Connect(scanner.get_output_port(), detector.get_input_port())
    builder.Connect(detector.get_output_port(), synthesizer.get_input_port())
    builder.Connect(synthesizer.get_output_port(), scorer.get_input_port())

    diagram = builder.Build()
    diagram.set_name("gbh_station")
    return Built(diagram, station, script, arm, fingers, scanner, detector, synthesizer, scorer)


def run(scenario: Scenario, *, meshcat: Meshcat | None = None,
        object_asset: ObjectAsset | None = None) -> RunSummary:
    """Simulates ``scenario`` and writes its replay and summary (see the module docstring)."""
    out = scenario.output_path()
    out.mkdir(parents=True, exist_ok=True)
    meshcat = meshcat or local_meshcat()
    built = build_diagram(scenario, meshcat=meshcat, object_asset=object_asset)
    station = built.station

    simulator = Simulator(built.diagram)
    ApplySimulatorConfig(scenario.simulator_config, simulator)
    context = simulator.get_mutable_context()
    plant, body = station.plant, station.object_body()
    plant_context = plant.GetMyContextFromRoot(context)
    X_WO_0 = plant.EvalBodyPoseInWorld(plant_context, body)

    # A view of the work area from the front right (the user can orbit it in the browser).
    meshcat.SetCameraPose(camera_in_world=[1.3, -1.0, 0.8], target_in_world=[0.45, 0.0, 0.15])
    meshcat.StartRecording(frames_per_second=1.0 / scenario.visualization.publish_period)
    start = time.perf_counter()
    simulator.Initialize()
    simulator.AdvanceTo(built.script.end_time)
    X_WO_settled = plant.EvalBodyPoseInWorld(plant_context, body)
    phases = list(built.script.labels[1:])
    outcome = None
    if scenario.task == "pick":
        outcome = attempt_pick(built, simulator, scenario, meshcat, phases)
    wall = time.perf_counter() - start
    meshcat.StopRecording()
    meshcat.PublishRecording()
    replay = out / "replay.html"
    replay.write_text(meshcat.StaticHtml())

    X_WO_1 = plant.EvalBodyPoseInWorld(plant_context, body)
    sim_time = context.get_time()
    summary = RunSummary(
        scenario=scenario.source_path or "<in memory>",
        object=station.object_asset.source,
        object_mass=station.object_model.mass,
        seed=scenario.seed,
        task=scenario.task,
        sim_time=sim_time,
        wall_time=wall,
        realtime_rate=sim_time / wall if wall > 0 else float("inf"),
        p_WO_initial=X_WO_0.translation().tolist(),
        p_WO_final=X_WO_1.translation().tolist(),
        settle_drift=float(np.linalg.norm((X_WO_settled.translation() - X_WO_0.translation())[:2])),
        replay=str(replay),
        phases=phases,
        pick=outcome,
    )
    (out / "summary.yaml").write_text(yaml.safe_dump(asdict(summary), sort_keys=False))
    return summary


def attempt_pick(built: Built, simulator: Simulator, scenario: Scenario, meshcat: Meshcat,
                 phases: list[str]) -> PickOutcome:
    """Scans now, runs GbH, executes the first reachable top-k grasp and judges it."""
    context = simulator.get_mutable_context()
    outcome = PickOutcome()

    def evaluate(system):
        return system.get_output_port().Eval(system.GetMyContextFromRoot(context))

    t = time.perf_counter()
    scan = evaluate(built.scanner)
    outcome.timings["scan"] = time.perf_counter() - t
    outcome.scan_faces = len(scan.mesh_W.faces)
    outcome.scan_message = scan.message
    t = time.perf_counter()
    hangability = evaluate(built.detector)
    candidates = evaluate(built.synthesizer)
    ranked = evaluate(built.scorer)
    outcome.timings["gbh"] = time.perf_counter() - t
    outcome.n_structures, outcome.n_candidates = len(hangability.structures), len(candidates)
    outcome.n_ranked = len(ranked)
    _draw(meshcat, scan, hangability.structures, ranked)
    if not hangability.structures:
        outcome.reason = hangability.message or "no hangable structure found"
        return outcome
    if not ranked:
        outcome.reason = f"no collision-free grasp (N_c < {scenario.gbh.p_c}) among " \
                         f"{len(candidates)} candidates"
        return outcome

    # The first grasp of the top-k whose whole pick motion has IK solutions and (by default) a
    # collision-free plan.
    station, plant = built.station, built.station.plant
    ik_context = plant.CreateDefaultContext()
    plant.SetPositions(ik_context, plant.GetPositions(plant.GetMyContextFromRoot(context)))
    params = scenario.pick
    t = time.perf_counter()
    planning = None
    if params.plan_paths:
        X_WO = plant.EvalBodyPoseInWorld(plant.GetMyContextFromRoot(context),
                                         station.object_body())
        planning = PickPlanning(
            with_object=make_planning_model(scenario, str(station.object_model.sdf), X_WO),
            # The segments near the grasp may graze the table top (GbH already keeps grasps within
            # ground_margin of it); the transfer keeps 5 mm from everything.
            without_object=make_planning_model(scenario, None, None, padding=0.0),
            seed=scenario.seed)
    script = None
    for rank, grasp in enumerate(ranked):
        script = pick_script(station, ik_context, RigidTransform(grasp.X_WG), params,
                             keep_straight_rod=grasp.kind == VERTICAL, planning=planning)
        if script is not None:
            outcome.chosen_rank, outcome.chosen_kind = rank, grasp.kind
            outcome.chosen_score = float(grasp.score)
            break
    outcome.timings["plan"] = time.perf_counter() - t
    if script is None:
        how = "IK and collision-free planning" if planning else "IK"
        outcome.reason = f"none of the {len(ranked)} ranked grasps is reachable ({how})"
        return outcome

    # Execute: the pick motion starts now.
    t0 = context.get_time()
    for source, trajectory in ((built.arm_source, script.arm_trajectory()),
                               (built.finger_source, script.finger_trajectory())):
        trajectory.shiftRight(t0)
        source.UpdateTrajectory(trajectory)
    G = plant.GetFrameByName("G", station.gripper)
    plant_context = plant.GetMyContextFromRoot(context)
    samples = []
    for label, t_end in zip(script.labels[1:], script.times[1:], strict=True):
        simulator.AdvanceTo(t0 + t_end)
        samples.append(Sample(
            t0 + t_end, label,
            plant.EvalBodyPoseInWorld(plant_context, station.object_body()).GetAsMatrix4(),
            G.CalcPoseInWorld(plant_context).GetAsMatrix4()))
        phases.append(label)
    p_OV = np.asarray(station.object_asset.mesh.vertices)
    verdict: Verdict = judge(samples, p_OV, lift_height=scenario.pick.lift_height)
    outcome.success, outcome.reason = verdict.success, verdict.reason
    outcome.lift, outcome.clearance = verdict.lift, verdict.clearance
    return outcome


def _draw(meshcat: Meshcat, scan, structures, ranked) -> None:
    """The scan, the hanging structures and the ranked grasps in Meshcat (paper Figs. 4-5)."""
    from gbh_drake.viz.gbh_meshcat import draw_grasps, draw_object, draw_structures

    if len(scan.mesh_W.faces):
        draw_object(meshcat, scan.mesh_W)
    draw_structures(meshcat, structures)
    draw_grasps(meshcat, ranked)
