"""One trial of the paper's experiment as one Drake diagram, run by one ``Simulator``.

:func:`build_trial` wires, from a :class:`~gbh_drake.scenario.Scenario`::

    Station --query_object--> Scanner --mesh_W--> HangabilityDetector --> GraspSynthesizer
        ^                                                                    |
        |                                    GraspScorer <--grasp_candidates-+
        |                                        | ranked_grasps
        +--panda.desired_state, hook_gripper.command-- PickAndCarry <--panda.state, ...
                                                         | status
    body_poses, contact_results, hook_gripper.* -----> CageMonitor --> verdict

(``antipodal`` and ``gbh_fallback`` add the ``AntipodalGraspSampler`` on the same scan.)
:func:`simulate_trial` advances the simulator until the machine has finished (plus a second for
the object to come to rest) and returns a :class:`TrialRecord`: what was seen, chosen, refused
and judged, and how long each stage took.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import Meshcat
from pydrake.math import RollPitchYaw
from pydrake.systems.analysis import ApplySimulatorConfig, Simulator
from pydrake.systems.framework import Diagram, DiagramBuilder, EventStatus
from pydrake.systems.primitives import ConstantValueSource

from gbh_drake.modeling.gripper_sdf import BAR_DEPLOYED, BAR_RETRACTED
from gbh_drake.modeling.object_asset import ObjectAsset, initial_object_pose, load_object_asset
from gbh_drake.scenario import Scenario
from gbh_drake.seeds import Seeds, derive_seeds
from gbh_drake.station import Station
from gbh_drake.systems.cage_monitor import NO_GRASP, CageMonitor, Verdict
from gbh_drake.systems.grasp_scorer import GraspScorer
from gbh_drake.systems.grasp_synthesizer import GraspSynthesizer
from gbh_drake.systems.grasp_visualizer import GraspVisualizer
from gbh_drake.systems.hangability_detector import HangabilityDetector
from gbh_drake.systems.pick_and_carry import PickAndCarry, PickStatus
from gbh_drake.systems.scanner import Scanner

#: Simulated seconds after the machine has finished (the released object comes to rest).
AFTERMATH = 0.5


@dataclass
class Trial:
    """A built trial diagram and its parts (for reading their outputs after a run)."""

    diagram: Diagram
    station: Station
    scanner: Scanner
    detector: HangabilityDetector
    synthesizer: GraspSynthesizer
    scorer: GraspScorer
    pick: PickAndCarry
    monitor: CageMonitor
    seeds: Seeds
    scenario: Scenario
    antipodal: object = None


@dataclass
class TrialRecord:
    """What one trial did. Lengths in metres, times in seconds, masses in kilograms."""

    object: str
    source: str
    object_mass: float
    seed: int
    method: str
    num_views: int
    pose: list[float]
    """The object's start pose: x, y, z (m), roll, pitch, yaw (rad) in W."""
    outcome: str
    success: bool
    reason: str
    held_by: str
    scan_faces: int = 0
    scan_message: str = ""
    scan_warnings: list[str] = field(default_factory=list)
    n_structures: int = 0
    n_candidates: int = 0
    n_ranked: int = 0
    n_grasps_offered: int = 0
    true_parts: int = 0
    """Ground-truth hangable parts of the object (0 for controls and mesh files)."""
    true_part_found: bool | None = None
    """Whether a hanging structure lies on a true hangable part (its c within half the part's
    clear diameter + 2 cm of the part's centre); None without ground truth."""
    grasped_true_part: bool | None = None
    """Whether the executed GbH grasp hooked a structure on a true part; None without ground
    truth or a GbH grasp."""
    grasp_rank: int = -1
    """0-based rank of the executed grasp in its list; -1 if none."""
    grasp_kind: str = ""
    grasp_score: float = float("nan")
    fallback: bool = False
    refusals: dict[str, int] = field(default_factory=dict)
    """How many tried grasps were refused for each reason (``ik:lift``, ``planner:transfer``)."""
    refusal_texts: list[str] = field(default_factory=list)
    lift: float = float("nan")
    """How far the gripper rose after closing."""
    place: list[float] = field(default_factory=list)
    """Where the hook point was when the object was released (W)."""
    verdict: dict = field(default_factory=dict)
    """Every field of the :class:`~gbh_drake.systems.cage_monitor.Verdict`."""
    phases: dict[str, float] = field(default_factory=dict)
    """Simulated time at which each phase began."""
    sim_time: float = 0.0
    timings: dict[str, float] = field(default_factory=dict)
    """Wall seconds: scan; grasps (GbH or the sampler on the scan); plan (IK, collision checks,
    RRT-Connect over the grasps tried) and plan_per_grasp (its median per grasp); simulate (the
    whole simulation, the above included)."""
    warnings: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


def build_trial(scenario: Scenario, *, meshcat: Meshcat | None = None,
                asset: ObjectAsset | None = None, grasps: list | None = None) -> Trial:
    """The trial diagram of ``scenario`` (see the module docstring); ``asset`` replaces the
    scenario's object; ``grasps`` (each with ``X_WG`` and ``kind``) are executed instead of the
    method's own (e.g. a grasp of your own, through the same planner, physics and judge)."""
    seeds = derive_seeds(scenario.seed)
    asset = asset or load_object_asset(scenario.object, scenario.directory)
    X_WO = initial_object_pose(scenario.object, asset, seeds.pose)
    method = scenario.grasp_method
    bar = BAR_RETRACTED if method == "antipodal" else BAR_DEPLOYED
    builder = DiagramBuilder()

    # The station: robot, table, object, cameras, visualisation.
    station = builder.AddSystem(Station(
        directives=scenario.directives, plant_config=scenario.plant_config,
        robot=scenario.robot, asset=asset, X_WO=X_WO, bar_angle=bar, cameras=scenario.cameras,
        visualization=scenario.visualization, meshcat=meshcat))

    # Perception and GbH: one scan once the object has settled -> structures -> ranked grasps.
    scanner = builder.AddNamedSystem("scanner", Scanner(
        scenario.scan, scenario.scan_target, scan_time=scenario.settle_time,
        noise_seed=seeds.noise))
    detector = builder.AddNamedSystem("hangability_detector",
                                      HangabilityDetector(scenario.gbh, seed=seeds.sampling))
    synthesizer = builder.AddNamedSystem("grasp_synthesizer", GraspSynthesizer(scenario.gbh))
    scorer = builder.AddNamedSystem("grasp_scorer", GraspScorer(scenario.gbh))
    builder.Connect(station.GetOutputPort("query_object"), scanner.GetInputPort("query_object"))
    builder.Connect(scanner.GetOutputPort("mesh_W"), detector.GetInputPort("mesh_W"))
    builder.Connect(detector.get_output_port(), synthesizer.get_input_port())
    builder.Connect(synthesizer.get_output_port(), scorer.get_input_port())

    # Execution: the pick-and-carry machine drives the robot.
    pick = builder.AddNamedSystem("pick_and_carry", PickAndCarry(
        scenario.directives, scenario.pick, scenario.robot.hand,
        settle_time=scenario.settle_time, ground_clearance=scenario.gbh.ground_clearance,
        seed=seeds.planner, bar_angle=bar))
    antipodal = None
    if method != "gbh":
        from gbh_drake.systems.antipodal_sampler import AntipodalGraspSampler

        antipodal = builder.AddNamedSystem("antipodal_sampler", AntipodalGraspSampler(
            scenario.antipodal, seed=seeds.grasps,
            ground_clearance=scenario.gbh.ground_clearance))
        builder.Connect(scanner.GetOutputPort("mesh_W"), antipodal.get_input_port())
    primary = antipodal if method == "antipodal" else scorer
    if grasps is not None:
        primary = builder.AddNamedSystem("given_grasps",
                                         ConstantValueSource(AbstractValue.Make(list(grasps))))
    builder.Connect(primary.get_output_port(), pick.GetInputPort("grasps"))
    if method == "gbh_fallback":
        builder.Connect(antipodal.get_output_port(), pick.GetInputPort("fallback_grasps"))
    builder.Connect(scanner.GetOutputPort("mesh_W"), pick.GetInputPort("scan"))
    for name in ("panda.state", "hook_gripper.state", "hook_gripper.load"):
        builder.Connect(station.GetOutputPort(name), pick.GetInputPort(name))
    for name in ("panda.desired_state", "hook_gripper.command"):
        builder.Connect(pick.GetOutputPort(name), station.GetInputPort(name))

    # The judge.
    p_OV = np.asarray(asset.mesh.convex_hull.vertices)
    monitor = builder.AddNamedSystem("cage_monitor", CageMonitor(
        station.plant, station.object_name, p_OV, scenario.monitor))
    for name in ("body_poses", "contact_results", "hook_gripper.state",
                 "hook_gripper.actuation"):
        builder.Connect(station.GetOutputPort(name), monitor.GetInputPort(name))
    builder.Connect(pick.GetOutputPort("status"), monitor.GetInputPort("pick_status"))

    if meshcat is not None:
        viz = builder.AddNamedSystem("grasp_visualizer", GraspVisualizer(meshcat))
        builder.Connect(scanner.GetOutputPort("mesh_W"), viz.GetInputPort("scan"))
        builder.Connect(detector.get_output_port(), viz.GetInputPort("hanging_structures"))
        builder.Connect(primary.get_output_port(), viz.GetInputPort("grasps"))
        builder.Connect(pick.GetOutputPort("status"), viz.GetInputPort("pick_status"))

    diagram = builder.Build()
    diagram.set_name("gbh_trial")
    return Trial(diagram, station, scanner, detector, synthesizer, scorer, pick, monitor, seeds,
                 scenario, antipodal)


def simulate_trial(trial: Trial, *, max_time: float = 60.0) -> tuple[Simulator, TrialRecord]:
    """Runs ``trial`` until its machine has finished and the object had ``AFTERMATH`` seconds to
    come to rest (at most ``max_time`` simulated seconds); returns the simulator and the record.
    A simulator monitor ends the run, as Drake's ``Simulator`` idiom has it."""
    simulator = Simulator(trial.diagram)
    ApplySimulatorConfig(trial.scenario.simulator_config, simulator)
    status_port = trial.pick.GetOutputPort("status")

    def monitor(root_context):
        status = status_port.Eval(trial.pick.GetMyContextFromRoot(root_context))
        if status.finished and root_context.get_time() >= \
                status.phase_start[status.mode.value] + AFTERMATH:
            return EventStatus.ReachedTermination(trial.pick, "the pick has finished")
        return EventStatus.Succeeded()

    simulator.set_monitor(monitor)
    start = time.perf_counter()
    simulator.Initialize()
    simulator.AdvanceTo(max_time)
    wall = time.perf_counter() - start
    return simulator, make_record(trial, simulator, wall)


def make_record(trial: Trial, simulator: Simulator, wall: float) -> TrialRecord:
    """The :class:`TrialRecord` of a simulated ``trial`` (outputs read from its context)."""
    scenario, station = trial.scenario, trial.station
    context = simulator.get_context()

    def value(system, port):
        return system.GetOutputPort(port).Eval(system.GetMyContextFromRoot(context))

    status: PickStatus = value(trial.pick, "status")
    verdict: Verdict = value(trial.monitor, "verdict")
    scan = value(trial.scanner, "mesh_W")
    hangability = value(trial.detector, "hanging_structures")
    candidates = value(trial.synthesizer, "grasp_candidates")
    ranked = value(trial.scorer, "ranked_grasps")
    X = station.X_WO_initial
    outcome, reason = verdict.outcome, verdict.reason
    if outcome == NO_GRASP:  # say why there was nothing to try
        outcome, reason = _why_no_grasp(scenario, scan, hangability, candidates)
    refusals: dict[str, int] = {}
    for r in status.refusals:
        refusals[r.key] = refusals.get(r.key, 0) + 1
    plan = status.plan
    on_part = _on_true_part(station.asset, X)
    executed = ranked[plan.rank] if plan and not status.fallback and \
        plan.rank < len(ranked) and hasattr(ranked[plan.rank], "structure") else None
    return TrialRecord(
        object=station.asset.name, source=station.asset.source,
        object_mass=float(station.asset.mass), seed=scenario.seed,
        method=scenario.grasp_method, num_views=scenario.scan.num_views,
        pose=[*X.translation().tolist(), *RollPitchYaw(X.rotation()).vector().tolist()],
        outcome=outcome, success=verdict.success, reason=reason, held_by=verdict.held_by,
        scan_faces=len(scan.mesh_W.faces), scan_message=scan.message,
        scan_warnings=list(getattr(scan, "warnings", [])),
        n_structures=len(hangability.structures), n_candidates=len(candidates),
        n_ranked=len(ranked), n_grasps_offered=status.n_grasps,
        true_parts=len(station.asset.hangable_parts),
        true_part_found=None if not station.asset.hangable_parts else
        any(on_part(s.c) for s in hangability.structures),
        grasped_true_part=None if not station.asset.hangable_parts or executed is None else
        on_part(executed.structure.c),
        grasp_rank=plan.rank if plan else -1, grasp_kind=plan.kind if plan else "",
        grasp_score=status.score, fallback=status.fallback, refusals=refusals,
        refusal_texts=[r.text() for r in status.refusals],
        lift=plan.lift if plan else float("nan"),
        place=plan.place_W.tolist() if plan else [],
        verdict=asdict(verdict), phases=dict(status.phase_start),
        sim_time=context.get_time(),
        timings={"scan": float(sum(scan.timing.values())) if scan.timing else 0.0,
                 "grasps": status.grasps_seconds,
                 "plan": status.plan_seconds - status.grasps_seconds,
                 "plan_per_grasp": float(np.median(status.grasp_seconds))
                 if status.grasp_seconds else 0.0,
                 "simulate": wall},
        warnings=list(station.asset.warnings),
    )


def _on_true_part(asset: ObjectAsset, X_WO):
    """A test: does point c (W) lie on one of ``asset``'s true hangable parts (at X_WO)?"""
    parts = [(X_WO.multiply(p.center_O), 0.5 * p.clear_diameter + 0.02)
             for p in asset.hangable_parts]

    def on_part(c) -> bool:
        return any(np.linalg.norm(np.asarray(c) - center) <= radius for center, radius in parts)

    return on_part


def _why_no_grasp(scenario: Scenario, scan, hangability, candidates) -> tuple[str, str]:
    """Outcome and reason when the machine had no grasp to try."""
    if scan.empty:
        return "empty_scan", scan.message
    if scenario.grasp_method == "antipodal":
        return "no_grasp_found", "the antipodal sampler found no grasp on the scan"
    also = "; the antipodal fallback found no grasp either" \
        if scenario.grasp_method == "gbh_fallback" else ""
    if not hangability.structures:
        return "no_hangable_structure", (hangability.message or
                                         "no hangable structure found") + also
    return "no_grasp_found", (f"no collision-free grasp among {len(candidates)} candidates on "
                              f"{len(hangability.structures)} hanging structures{also}")
