"""One trial of the paper's experiment as one Drake diagram, run by one ``Simulator``.

:func:`build_trial` wires, from a :class:`~gbh_drake.scenario.Scenario`::

    Station --query_object--> Scanner --mesh_W--> [grasp method] --grasps--> PickAndCarry
        ^                                              | grasp_search          | status
        +--panda.desired_state, hook_gripper.command---+-----------------------+
    body_poses, contact_results, hook_gripper.* -----> CageMonitor --> verdict

The grasp method (:mod:`gbh_drake.methods`, by the scenario's ``grasp_method``) adds its own
systems: GbH's ``HangabilityDetector -> GraspSynthesizer -> GraspScorer``, the
``AntipodalGraspSampler``, or both (the fallback); it tells the monitor why it has no grasp
when it has none. :func:`simulate_trial` advances the simulator until the machine has finished
(plus :data:`AFTERMATH` for the object to come to rest) and returns a :class:`TrialRecord`:
what was seen, chosen, refused and judged (the monitor's verdict, copied), and how long each
stage took. :func:`record_trial` does both and draws its Meshcat replay afterwards, from the body
poses recorded during the trial (:mod:`gbh_drake.replay`): the one way ``gbh run`` and the
experiment's workers run a trial.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

import numpy as np
from pydrake.geometry import Meshcat
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.analysis import ApplySimulatorConfig, Simulator
from pydrake.systems.framework import Diagram, DiagramBuilder, EventStatus

from gbh_drake import interrupts
from gbh_drake.core.arguments import argument_problem, require
from gbh_drake.core.gripper import GRIPPERS
from gbh_drake.core.ranges import is_number
from gbh_drake.messages import HeldBy, Outcome, PickStatus, Verdict, verdict_final
from gbh_drake.method_spec import Tier
from gbh_drake.methods import GivenGrasps, GraspMethod, GraspSource, method_named
from gbh_drake.modeling.names import ARM, GRIPPER
from gbh_drake.modeling.object_asset import ObjectAsset
from gbh_drake.replay import PoseLog, add_pose_log, draw_replay, replay_page
from gbh_drake.scenario import Scenario
from gbh_drake.scenario.loader import require_scenario
from gbh_drake.seeds import Seeds, derive_seeds
from gbh_drake.station import Station, make_station, scene_query_port
from gbh_drake.systems.cage_monitor import CageMonitor
from gbh_drake.systems.grasp_visualizer import GraspVisualizer
from gbh_drake.systems.pick_and_carry import PickAndCarry
from gbh_drake.systems.ports import build_checked
from gbh_drake.systems.scanner import Scanner

#: Simulated seconds after the machine has finished (the released object comes to rest).
AFTERMATH = 0.5
#: How Drake's message starts when SAP fails on a step (the trial then ends with a record:
#: ``error`` before the cage test is over, the verdict with a warning after it).
SOLVER_FAILED = "The SAP solver failed to converge"
#: Where a live view's camera starts: the work area from the front right (orbit it in the
#: browser; a replay is framed on the object: :mod:`gbh_drake.replay`).
REPLAY_CAMERA = {"camera_in_world": [1.3, -1.0, 0.8], "target_in_world": [0.45, 0.0, 0.15]}


@dataclass
class Trial:
    """A built trial diagram and its parts (for reading their outputs after a run)."""

    diagram: Diagram
    station: Station
    scanner: Scanner
    method: GraspMethod
    source: GraspSource
    """Where the method's grasps come from (its ports and systems)."""
    pick: PickAndCarry
    monitor: CageMonitor
    seeds: Seeds
    scenario: Scenario
    poses: PoseLog | None = None
    """The arm's, gripper's and object's states as recorded for the replay."""


@dataclass
class TrialRecord:
    """What one trial did. Lengths in metres, times in seconds, masses in kilograms."""

    object: str
    source: str
    object_mass: float
    seed: int
    method: str
    num_views: int
    gbh_preset: str
    """Where GbH's beyond-the-paper defaults came from: ``""`` (gbh_drake's) or ``"paper"``."""
    pose: list[float]
    """The object's start pose: x, y, z (m), roll, pitch, yaw (rad) in W."""
    outcome: Outcome
    """The monitor's outcome (copied from ``verdict``)."""
    success: bool
    reason: str
    held_by: HeldBy
    scan_faces: int = 0
    scan_message: str = ""
    scan_warnings: list[str] = field(default_factory=list)
    """The warnings of the scan GbH ran on: the Scanner's and, for ``gbh_completed``, the shape
    completion's."""
    n_structures: int = 0
    """Hanging structures GbH found (0 for a method without GbH)."""
    n_candidates: int = 0
    n_ranked: int = 0
    """Grasps the method offered (GbH: the ranked top k; antipodal: the sampler's)."""
    n_grasps_offered: int = 0
    rejected_by: dict[str, int] = field(default_factory=dict)
    """GbH's candidates each collision rule removed, in the order the rules apply
    (``collision N_c``, ``closing sweep``, ``table clearance``;
    :mod:`gbh_drake.core.rejections`); filled when the method offered no grasp."""
    true_parts: int = 0
    """Ground-truth hangable parts of the object (0 for controls and mesh files)."""
    true_part_found: bool | None = None
    """Whether a hanging structure lies on a true hangable part (its c within half the part's
    clear diameter + 2 cm of the part's centre); None without ground truth or GbH."""
    grasped_true_part: bool | None = None
    """Whether the executed GbH grasp hooked a structure on a true part; None without ground
    truth or a GbH grasp."""
    grasp_rank: int = -1
    """0-based rank of the executed grasp in its list; -1 if none."""
    grasp_kind: str = ""
    grasp_score: float = float("nan")
    best_score: float = float("nan")
    """The best offered grasp's score (rank 0 of the list the executed grasp came from): a
    grasp executed far below it is counted in the report."""
    fallback: bool = False
    grasp_source: str = ""
    """The list the executed grasp came from: ``grasps`` (the method's, e.g. GbH's ranked),
    ``scoop_grasps``, ``tall_scoop_grasps`` or ``fallback_grasps``; "" if none was executed."""
    regrasps: list[dict] = field(default_factory=list)
    """Each regrasp done before the judged pick (beyond the paper): the pinch's rank, the
    resting pose's turn (deg), probability and GbH's best score there, the extra yaw (deg),
    where it was set down (W, m) and when it began and ended (simulated s)."""
    attempts: list[dict] = field(default_factory=list)
    """Each executed grasp whose lift came away empty, a retry following (beyond the paper):
    its kind, rank, score, source, the gripper's origin (W, m), the load the lift added (N) and
    when the lift ended (s)."""
    refusals: dict[str, int] = field(default_factory=dict)
    """How many tried grasps were refused for each reason (``ik:lift``, ``planner:transfer``)."""
    refusal_texts: list[str] = field(default_factory=list)
    lift: float = float("nan")
    """How far the gripper rose after closing."""
    lift_needed: float = float("nan")
    """How far it should have risen for the object, hanging from where its material comes to
    rest on the loop, to clear the table by ``pick.lift_clearance`` (nan: not estimated)."""
    lift_slide: float = float("nan")
    """How far (m) the hooked material may slide through the closed loop (the lift bounds the
    object hanging from anywhere it reaches; ``pick.slide_lift``); nan without a hook plan."""
    carry_dip: float = float("nan")
    """How far (m) the hook point went below its lifted height along the carry."""
    grasp_opening: float = float("nan")
    """m: one finger's position for the approach and insert of the executed grasp (the
    gripper's ``q_open``; a pinch's narrower ``q_pregrasp``, ``antipodal.narrow_pregrasp``)."""
    plan_notes: list[str] = field(default_factory=list)
    """What the plan could not do as wanted (a lift short of the need, a carry that dips)."""
    place: list[float] = field(default_factory=list)
    """Where the hook point was when the object was released (W)."""
    verdict: Verdict = field(default_factory=Verdict)
    """The :class:`~gbh_drake.messages.Verdict` at the end."""
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
                asset: ObjectAsset | None = None, grasps: list | None = None,
                method: GraspMethod | None = None, draw_grasps: bool = True) -> Trial:
    """The trial diagram of ``scenario`` (see the module docstring). ``meshcat``: the station is
    drawn there as it runs, and with ``draw_grasps`` what GbH saw and chose too (the
    ``GraspVisualizer``, once planned). ``asset`` replaces the
    scenario's object; ``method`` its grasp method (default: the registered one it names);
    ``grasps`` (each with ``X_WG`` and ``kind``) are executed instead of the method's own
    (:class:`~gbh_drake.methods.GivenGrasps`: a grasp of your own, through the same planner,
    physics and judge). The arm's, gripper's and object's states are recorded for the replay
    (``Trial.poses``). A ``scenario`` field or an argument of the wrong type raises
    :class:`~gbh_drake.scenario.ScenarioError` or TypeError naming it; the scenario's ranges
    and relations are :func:`~gbh_drake.scenario.validate_scenario`'s (``load_scenario`` and
    ``run_trial`` check them)."""
    require_scenario(scenario, "build_trial")
    _require_common("build_trial", meshcat, asset)
    require("build_trial", "method", method, (GraspMethod, type(None)),
            "a GraspMethod (e.g. gbh_drake.methods.method_named('gbh')) or None")
    seeds = derive_seeds(scenario.seed)
    method = method or method_named(scenario.grasp_method)
    if grasps is not None:
        method = GivenGrasps(_grasps(grasps), method)
    builder = DiagramBuilder()

    # The station: robot, table, object, cameras, visualisation.
    station = builder.AddSystem(make_station(scenario, meshcat=meshcat, object_asset=asset,
                                              seeds=seeds))

    # Perception: one scan once the object has settled; the method's grasps from it.
    # (The robot's own pixels are filtered out of its images by their render labels.)
    plant = station.plant
    scanner = builder.AddNamedSystem("scanner", Scanner(
        scenario.scan, scenario.scan_target, scan_time=scenario.settle_time,
        noise_seed=seeds.noise, robot=[int(plant.GetModelInstanceByName(name))
                                       for name in (ARM, GRIPPER)]))
    builder.Connect(station.GetOutputPort(scene_query_port(scenario.scan.renderer_name)),
                    scanner.GetInputPort("query_object"))
    builder.Connect(station.GetOutputPort("object.state"), scanner.GetInputPort("object.state"))
    scan = scanner.GetOutputPort("mesh_W")
    source = method.add_systems(builder, scenario=scenario, seeds=seeds, scan=scan)

    # Execution: the pick-and-carry machine drives the robot, trying the method's grasp tiers
    # in order.
    spec = method.spec
    pick = builder.AddNamedSystem("pick_and_carry", PickAndCarry(
        scenario.station_directives(), scenario.pick, scenario.robot.hand,
        settle_time=scenario.settle_time, ground_clearance=scenario.gbh.ground_clearance,
        seed=seeds.planner, bar_angle=spec.bar_angle, scoop=scenario.scoop,
        regrasp=scenario.regrasp, scan_height=scenario.scan_target[2],
        max_retries=spec.max_retries if scenario.pick.max_retries is None
        else scenario.pick.max_retries, tiers=[tier.tier for tier in source.tiers],
        gripper=GRIPPERS[scenario.gripper]))
    for tier in source.tiers:
        ports = (tier.poses, tier.grasps) if tier.tier is Tier.REGRASP else (tier.grasps,)
        for port, name in zip(ports, tier.tier.ports, strict=True):
            builder.Connect(port, pick.GetInputPort(name))
    # A regrasp or a retry asks the Scanner for a new scan.
    builder.Connect(pick.GetOutputPort("scan_request"), scanner.GetInputPort("scan_request"))
    builder.Connect(scan, pick.GetInputPort("scan"))
    for name in ("panda.state", "hook_gripper.state", "hook_gripper.load"):
        builder.Connect(station.GetOutputPort(name), pick.GetInputPort(name))
    for name in ("panda.desired_state", "hook_gripper.command"):
        builder.Connect(pick.GetOutputPort(name), station.GetInputPort(name))

    # The judge.
    p_OV = np.asarray(station.asset.mesh.convex_hull.vertices)
    monitor = builder.AddNamedSystem("cage_monitor", CageMonitor(
        station.plant, station.object_name, p_OV, scenario.monitor, mesh_O=station.asset.mesh,
        gripper=GRIPPERS[scenario.gripper]))
    for name in ("body_poses", "contact_results", "hook_gripper.state",
                 "hook_gripper.actuation"):
        builder.Connect(station.GetOutputPort(name), monitor.GetInputPort(name))
    builder.Connect(pick.GetOutputPort("status"), monitor.GetInputPort("pick_status"))
    builder.Connect(source.search, monitor.GetInputPort("grasp_search"))

    # The replay's record: the moving bodies' states at its frame rate.
    poses = add_pose_log(builder, station, scenario.replay_fps)

    if meshcat is not None and draw_grasps:
        viz = builder.AddNamedSystem("grasp_visualizer",
                                     GraspVisualizer(meshcat, params=scenario.gbh))
        builder.Connect(scan, viz.GetInputPort("scan"))
        if source.hanging_structures is not None:
            builder.Connect(source.hanging_structures, viz.GetInputPort("hanging_structures"))
        if source.candidates is not None:
            builder.Connect(source.candidates, viz.GetInputPort("grasp_candidates"))
        builder.Connect(source.grasps, viz.GetInputPort("grasps"))
        builder.Connect(pick.GetOutputPort("status"), viz.GetInputPort("pick_status"))

    diagram = build_checked(builder)
    diagram.set_name("gbh_trial")
    return Trial(diagram, station, scanner, method, source, pick, monitor, seeds, scenario, poses)


def _require_common(function: str, meshcat, asset) -> None:
    require(function, "meshcat", meshcat, (Meshcat, type(None)), "a pydrake.geometry.Meshcat or None")
    require(function, "asset", asset, (ObjectAsset, type(None)),
            "an ObjectAsset (gbh_drake.modeling.object_asset.load_object_asset) or None")


def _grasps(grasps) -> list:
    """``grasps`` as a list, each with ``X_WG`` (4 x 4, or a RigidTransform) and ``kind`` (a
    str); else TypeError naming the grasp."""
    if isinstance(grasps, str | bytes | dict) or not hasattr(grasps, "__iter__"):
        raise TypeError(argument_problem("build_trial", "grasps", "a list of grasps (each with "
                                         "X_WG and kind) or None", grasps))
    grasps = list(grasps)
    for i, grasp in enumerate(grasps):
        X = getattr(grasp, "X_WG", None)
        if isinstance(X, RigidTransform):
            X = X.GetAsMatrix4()
        if X is None or np.shape(X) != (4, 4):
            raise TypeError(argument_problem("build_trial", f"grasps[{i}]", "a grasp with X_WG "
                                             "(the open gripper's pose in W, 4 x 4) and kind",
                                             grasp))
        require("build_trial", f"grasps[{i}].kind", getattr(grasp, "kind", None), str,
                "'parallel' or 'vertical'")
    return grasps


def trial_duration(trial: Trial) -> float:
    """Simulated seconds ``trial`` may last: its scenario's settle time for task ``settle``,
    else ``max_time`` for each attempt its machine may start (``PickAndCarry.max_attempts``:
    a retry or a regrasp begins a pick anew, and a trial cut off in its last cage test would
    have no verdict)."""
    require("trial_duration", "trial", trial, Trial, "a Trial (build_trial(scenario))")
    scenario = trial.scenario
    if scenario.task == "settle":
        return scenario.settle_time
    return scenario.max_time * trial.pick.max_attempts


def simulate_trial(trial: Trial, *, max_time: float | None = None
                   ) -> tuple[Simulator, TrialRecord]:
    """Runs ``trial`` until its machine has finished and the object had ``AFTERMATH`` seconds to
    come to rest (at most ``max_time`` simulated seconds; default: :func:`trial_duration`, the
    scenario's ``max_time`` per attempt); returns the simulator and the record. A simulator monitor ends the
    run, as Drake's ``Simulator`` idiom has it."""
    require("simulate_trial", "trial", trial, Trial, "a Trial (build_trial(scenario))")
    if max_time is not None and not (is_number(max_time) and 0 < max_time < np.inf):
        raise TypeError(argument_problem("simulate_trial", "max_time", "a positive number of "
                                         "simulated seconds, or None (the scenario's)", max_time))
    max_time = trial_duration(trial) if max_time is None else max_time
    simulator = Simulator(trial.diagram)
    ApplySimulatorConfig(trial.scenario.simulator_config, simulator)
    simulator.Initialize()
    return simulator, finish_trial(trial, simulator, max_time)


def finish_trial(trial: Trial, simulator: Simulator, max_time: float, *,
                 stop: Callable[[], bool] | None = None) -> TrialRecord:
    """Advances ``simulator`` (of ``trial``'s diagram, initialized, in whatever state it is:
    :func:`simulate_trial`'s from the start, the studio's from its scan) until the machine has
    finished and the object had ``AFTERMATH`` seconds to come to rest, or ``stop()`` is true,
    or ``max_time`` (simulated s) is reached; returns the record (wall seconds: this advance).
    The monitor that stops it stays set on ``simulator``."""
    status_port = trial.pick.GetOutputPort("status")

    def monitor(root_context):
        interrupts.check()  # a signal whose exception was dropped ends the run at this step
        status = status_port.Eval(trial.pick.GetMyContextFromRoot(root_context))
        if status.finished and root_context.get_time() >= \
                status.phase_start[status.mode.value] + AFTERMATH:
            return EventStatus.ReachedTermination(trial.pick, "the pick has finished")
        if stop is not None and stop():
            return EventStatus.ReachedTermination(trial.pick, "stopped")
        return EventStatus.Succeeded()

    simulator.set_monitor(monitor)
    start = time.perf_counter()
    try:
        simulator.AdvanceTo(max_time)
    except RuntimeError as e:
        if not str(e).startswith(SOLVER_FAILED):
            raise
        # The contact solver gave up. The record (the context holds the last step that was
        # solved) says so and where, instead of a crash: after the cage test the verdict was
        # final and stands, with a warning; before it the trial has no outcome (``error``).
        record = make_record(trial, simulator, time.perf_counter() - start)
        status: PickStatus = _value(trial.pick, "status", simulator.get_context())
        what = (f"Drake's contact solver (SAP) did not converge after t = "
                f"{record.sim_time:.3f} s, in the {status.mode.value} phase")
        if verdict_final(status.mode):
            record.warnings = [*record.warnings, f"the simulation stopped: {what}; the verdict "
                               "was final by then (the cage test was over)"]
        else:
            record.outcome, record.success, record.held_by = Outcome.ERROR, False, HeldBy.NONE
            record.reason = f"the simulation failed: {what}; no outcome"
        return record
    return make_record(trial, simulator, time.perf_counter() - start)


@dataclass
class TrialRun:
    """A trial that ran: its diagram, simulator and record, its replay (a self-contained Meshcat
    HTML page, or None when none was kept) and wall seconds by step (``build``, ``simulate``,
    ``replay``)."""

    trial: Trial
    simulator: Simulator
    record: TrialRecord
    replay_html: str | None
    seconds: dict[str, float]


def record_trial(scenario: Scenario, *, meshcat: Meshcat | None = None,
                 asset: ObjectAsset | None = None,
                 keep_replay: Callable[[TrialRecord], bool] | bool = True,
                 live: bool = False) -> TrialRun:
    """Builds, simulates and records one trial of ``scenario``: the one way a trial is run
    (``gbh run``, the experiment's workers). With ``meshcat`` (whose scene, recording and
    controls are cleared first: a worker reuses one), the replay is drawn there after the
    trial, from the body poses recorded during it (:mod:`gbh_drake.replay`), when
    ``keep_replay`` is true or returns true for the record, and kept as HTML (``replay_html``).
    ``live``: the trial is also drawn in ``meshcat`` while it runs (the station's visualisers
    and what GbH saw and chose), at a cost to its speed; the replay then replaces it."""
    require_scenario(scenario, "record_trial")
    _require_common("record_trial", meshcat, asset)
    if not (callable(keep_replay) or isinstance(keep_replay, bool)):
        raise TypeError(argument_problem("record_trial", "keep_replay", "True, False or a "
                                         "function of the record", keep_replay))
    if live and meshcat is None:
        raise TypeError(argument_problem("record_trial", "meshcat", "a Meshcat to draw the "
                                         "live trial in (live=True)", meshcat))
    start = time.perf_counter()
    if meshcat is not None:  # a clean scene for this trial
        meshcat.Delete()
        meshcat.DeleteRecording()
        meshcat.DeleteAddedControls()
    trial = build_trial(scenario, meshcat=meshcat if live else None, asset=asset)
    built = time.perf_counter()
    if live:
        meshcat.SetCameraPose(**REPLAY_CAMERA)
    simulator, record = simulate_trial(trial)
    simulated = time.perf_counter()
    html = None
    if meshcat is not None and (keep_replay(record) if callable(keep_replay) else keep_replay):
        drawn = draw_replay(meshcat, trial, simulator.get_context(), record)
        html = replay_page(meshcat, record, drawn, _why(trial, simulator, record))
    done = time.perf_counter()
    return TrialRun(trial, simulator, record, html, {"build": built - start,
                                                     "simulate": simulated - built,
                                                     "replay": done - simulated})


def _why(trial: Trial, simulator: Simulator, record: TrialRecord) -> str:
    """The record's reason; for ``no_hangable_structure``, what the detector saw too (as ``gbh
    grasps`` says it)."""
    from gbh_drake.scan_grasps.result import no_structure_message

    port = trial.source.hanging_structures
    if record.outcome != Outcome.NO_HANGABLE_STRUCTURE or port is None:
        return record.reason
    report = _port_value(port, simulator.get_context()).report
    return record.reason if report is None else no_structure_message(report)


def _value(system, port: str, context):
    return system.GetOutputPort(port).Eval(system.GetMyContextFromRoot(context))


def _port_value(port, context):
    return port.Eval(port.get_system().GetMyContextFromRoot(context))


def make_record(trial: Trial, simulator: Simulator, wall: float) -> TrialRecord:
    """The :class:`TrialRecord` of a simulated ``trial`` (outputs read from its context; the
    outcome and reason are the monitor's)."""
    scenario, station, source = trial.scenario, trial.station, trial.source
    context = simulator.get_context()
    status: PickStatus = _value(trial.pick, "status", context)
    verdict: Verdict = _value(trial.monitor, "verdict", context)
    scan = _value(trial.scanner, "mesh_W", context)
    completer = source.systems.get("shape_completer")
    gbh_scan = _value(completer, "completed_mesh_W", context) if completer is not None else scan
    hangability = _port_value(source.hanging_structures, context) \
        if source.hanging_structures is not None else None
    structures = hangability.structures if hangability is not None else []
    n_candidates = len(_port_value(source.candidates, context)) \
        if source.candidates is not None else 0
    offered = _port_value(source.grasps, context)
    search = _port_value(source.search, context) if not offered else None
    X = station.X_WO_initial
    X_scanned = X  # where it was scanned last (after a regrasp: set down anew)
    if verdict.planned_poses:
        x, y, z, roll, pitch, yaw = verdict.planned_poses[-1]
        X_scanned = RigidTransform(RollPitchYaw(roll, pitch, yaw), [x, y, z])
    refusals: dict[str, int] = {}
    for r in status.refusals:
        refusals[r.key] = refusals.get(r.key, 0) + 1
    plan = status.plan
    on_part = _on_true_part(station.asset, X_scanned)
    tier = source.tier(Tier(status.source)) if status.source else None
    chosen = _port_value(tier.grasps, context) if tier is not None else offered
    executed = chosen[plan.rank] if plan and plan.rank < len(chosen) and \
        hasattr(chosen[plan.rank], "structure") else None
    known = bool(station.asset.hangable_parts) and hangability is not None
    return TrialRecord(
        object=station.asset.name, source=station.asset.source,
        object_mass=float(station.asset.mass), seed=scenario.seed,
        method=scenario.grasp_method, num_views=scenario.scan.num_views,
        gbh_preset=scenario.gbh.preset,
        pose=[*X.translation().tolist(), *RollPitchYaw(X.rotation()).vector().tolist()],
        outcome=verdict.outcome, success=verdict.success, reason=verdict.reason,
        held_by=verdict.held_by,
        scan_faces=len(scan.mesh_W.faces), scan_message=scan.message,
        scan_warnings=list(getattr(gbh_scan, "warnings", [])),  # the completion's too
        n_structures=len(structures), n_candidates=n_candidates,
        n_ranked=len(offered), n_grasps_offered=status.n_grasps,
        rejected_by=dict(getattr(search, "rejected_by", {}) or {}),
        true_parts=len(station.asset.hangable_parts),
        true_part_found=any(on_part(s.c) for s in structures) if known else None,
        grasped_true_part=None if not station.asset.hangable_parts or executed is None else
        on_part(executed.structure.c),
        grasp_rank=plan.rank if plan else -1, grasp_kind=plan.kind if plan else "",
        grasp_score=status.score, best_score=_best_score(chosen),
        fallback=status.fallback, grasp_source=status.source,
        regrasps=[_regrasp_entry(r, status) for r in status.regrasps],
        attempts=[a.as_dict() for a in status.attempts],
        refusals=refusals,
        refusal_texts=[r.text() for r in status.refusals],
        lift=plan.lift if plan else float("nan"),
        lift_needed=float(getattr(plan, "lift_needed", float("nan"))) if plan else float("nan"),
        lift_slide=float(getattr(plan, "slide", float("nan"))) if plan else float("nan"),
        carry_dip=float(getattr(plan, "carry_dip", float("nan"))) if plan else float("nan"),
        grasp_opening=float(getattr(plan, "opening", float("nan"))) if plan else float("nan"),
        plan_notes=list(getattr(plan, "notes", [])) if plan else [],
        place=plan.place_W.tolist() if plan else [],
        verdict=verdict, phases=dict(status.phase_start),
        sim_time=context.get_time(),
        timings={"scan": float(sum(scan.timing.values())) if scan.timing else 0.0,
                 "grasps": status.grasps_seconds,
                 "plan": status.plan_seconds - status.grasps_seconds,
                 "plan_per_grasp": float(np.median(status.grasp_seconds))
                 if status.grasp_seconds else 0.0,
                 "simulate": wall},
        warnings=list(station.asset.warnings),
    )


def _regrasp_entry(plan, status: PickStatus) -> dict:
    """A regrasp's record entry (see :attr:`TrialRecord.regrasps`)."""
    return {"pinch_rank": plan.rank, "turn_deg": float(plan.pose.turn_deg),
            "probability": float(plan.pose.probability),
            "best_score": float(plan.pose.best_score), "yaw_deg": float(plan.yaw_deg),
            "place": [float(v) for v in plan.place_W],
            "started": float(status.phase_start.get("regrasp_approach", float("nan"))),
            "rescanned": float(status.phase_start.get("rescan", float("nan")))}


def _best_score(grasps) -> float:
    return float(getattr(grasps[0], "score", float("nan"))) if grasps else float("nan")


def _on_true_part(asset: ObjectAsset, X_WO):
    """A test: does point c (W) lie on one of ``asset``'s true hangable parts (at X_WO)?"""
    parts = [(X_WO.multiply(p.center_O), 0.5 * p.clear_diameter + 0.02)
             for p in asset.hangable_parts]

    def on_part(c) -> bool:
        return any(np.linalg.norm(np.asarray(c) - center) <= radius for center, radius in parts)

    return on_part
