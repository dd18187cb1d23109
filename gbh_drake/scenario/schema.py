"""The scenario's schema: :class:`Scenario` and the configuration dataclasses it composes.

Plain dataclasses on the ground floor (they import nothing of the pipeline: perception,
planning, systems), loadable with Drake's ``yaml_load_typed`` (no ``from __future__ import
annotations`` here: the loader needs real types). Each field documents its unit and default and
declares its range beside it (:func:`gbh_drake.core.ranges.ranged`); rules between fields of one
dataclass are its ``check_relations``. :class:`Scenario` composes them with Drake's own config
structs and the two other ground-floor configs, :class:`gbh_drake.core.params.GbhParams` and
:class:`gbh_drake.perception.config.ScanConfig`. Frames: W is the world (z up, the table top is
the plane z = 0); lengths in metres, angles in radians unless a name says ``_deg``, forces in
newtons, times in seconds, masses in kilograms.
"""

from dataclasses import dataclass, field
from pathlib import Path

from pydrake.multibody.parsing import ModelDirective
from pydrake.multibody.plant import MultibodyPlantConfig
from pydrake.systems.analysis import SimulatorConfig
from pydrake.systems.sensors import CameraConfig
from pydrake.visualization import VisualizationConfig

from gbh_drake.core.params import (
    AntipodalParams,
    CompletionParams,
    GbhParams,
    RegraspParams,
    ScoopParams,
)
from gbh_drake.core.pick_config import PickConfig  # noqa: F401  (re-exported: the scenario's pick)
from gbh_drake.core.ranges import (
    FilePath,
    Int,
    Items,
    NonNeg,
    OneOf,
    Pos,
    Range,
    Registered,
    Relation,
    ranged,
    section,
)
from gbh_drake.method_spec import method_names, method_spec
from gbh_drake.modeling.directives import (  # noqa: F401  (re-exported: the scenario's defaults)
    DEFAULT_DIRECTIVES,
    DEFAULT_Q_HOME,
    default_directives,
    without_table,
)
from gbh_drake.modeling.names import GRIPPER_FILES
from gbh_drake.modeling.object_config import RESTS, ObjectConfig, RandomRestingPose  # noqa: F401
from gbh_drake.perception.config import ScanConfig

#: The hook gripper's variants (``RobotConfig.gripper``): ``auto`` is the grasp method's.
GRIPPER_VARIANTS = ("auto", *GRIPPER_FILES)


#: What a run does: ``pick`` = settle, scan, detect, synthesise, score, pick the best reachable
#: grasp, carry, release and judge it; ``settle`` = only let the object settle (a smoke test of
#: the station).
TASKS = ("pick", "settle")


@dataclass
class HandConfig:
    """The Franka Hand's finger drive: force-limited like the real hand (70 N continuous, 140 N
    peak grasp force, about 0.05 m/s per finger). Each finger's joint is a position-controlled
    actuator (the plant's implicit PD, stiffness ``kp``) whose effort is limited to
    ``max_force`` by the plant; the hand driver moves its set point at ``speed`` and keeps it
    within ``force / kp`` of the measured finger, so a blocked finger squeezes with ``force``."""

    force: float = ranged(70.0, Pos(1000.0, "N"), relations=(
        Relation("<=", "max_force", "the fingers' actuators apply at most that"),))
    """Grasp force (N) each finger applies once it is blocked (Franka: 70 N continuous)."""
    max_force: float = ranged(140.0, Pos(1000.0, "N"))
    """Effort limit (N) of each finger's actuator (Franka: 140 N peak)."""
    speed: float = ranged(0.05, Pos(1.0, "m/s"))
    """Finger speed (m/s, each finger) while opening or closing."""
    kp: float = ranged(20000.0, Pos(1e7, "N/m"))
    """Finger position stiffness (N/m) of the drive."""
    kd: float = ranged(60.0, Pos(1e5, "N s/m"))
    """Finger damping (N s/m) of the drive."""



@dataclass
class RobotConfig:
    """The Franka arm with the hook gripper."""

    q_home: list[float] = ranged(
        lambda: list(DEFAULT_Q_HOME), Items(7, what="joint positions (rad, panda_joint1..7)"))
    """Arm joint positions (rad, 7 values, panda_joint1..7) at the start and when idle."""
    gripper_open: bool = True
    """Whether the gripper starts open (q = l_w / 2) or closed."""
    arm_kp: list[float] = ranged(
        lambda: [4000.0] * 4 + [1500.0] * 3, Items(7, Pos(1e6, "N m/rad"), what="gains (panda_joint1..7)"))
    """Joint PD stiffness (N m / rad) of panda_joint1..7 (set on the actuators by name)."""
    arm_kd: list[float] = ranged(
        lambda: [200.0] * 4 + [60.0] * 3, Items(7, Pos(1e5, "N m s/rad"), what="gains (panda_joint1..7)"))
    """Joint PD damping (N m s / rad) of panda_joint1..7."""
    hand: HandConfig = field(default_factory=HandConfig)
    """The fingers' force-limited drive."""
    gripper: str = ranged("auto", OneOf(GRIPPER_VARIANTS))
    """The hook gripper's bar: ``paper`` (the paper's square bar), ``wedge`` (beyond the paper:
    the bar's tip is chamfered underneath, a 16 mm ramp at 26.6 deg inside the paper's bar
    (``core.gripper.WEDGE_GRIPPER``, docs/scoop.md), so that it can slide under material lying
    on the table, as the scoop does) or ``auto``: the grasp method's
    (its :attr:`~gbh_drake.method_spec.MethodSpec.gripper`: the wedge for the methods that
    scoop, else the paper's). It picks
    the gripper's model file where the directives add a packaged one."""


@dataclass
class MonitorConfig:
    """The success rules of the ``CageMonitor``, fixed before any experiment."""

    lifted_height: float = ranged(0.02, Pos(1.0, "m"))
    """The object counts as lifted when its lowest point is this far (m) above the table."""
    closed_tolerance: float = ranged(0.002, Pos(0.02, "m"))
    """The hook's loop is recorded as closed (``Verdict.loop_closed``) when each finger is
    within this distance (m) of its closed position (the bar's tip on the straight rod). It no
    longer decides a cage: what the loop encloses does (docs/cage_test.md)."""
    period: float = ranged(0.01, Range(1e-3, 1.0, unit="s"))
    """Update period (s) of the monitor."""


@dataclass
class Scenario:
    """One run of gbh_drake. Units: metres, radians, seconds, kilograms."""

    seed: int = ranged(0, Int(0, 2**64 - 1, "seeds are unsigned 64-bit integers"))
    """Seeds every random choice of the run (object pose, sampling, depth noise): same seed, same run."""
    object: ObjectConfig = field(default_factory=ObjectConfig)
    robot: RobotConfig = field(default_factory=RobotConfig)
    directives: list[ModelDirective] = field(default_factory=default_directives)
    """The fixed models (Drake ``ModelDirectives``): by default the arm ``panda`` on the table,
    the ``hook_gripper`` on its flange and the ``table`` whose top is the plane z = 0 of W.
    Add models here; keep those three names."""
    cameras: list[CameraConfig] = field(default_factory=list)
    """Extra RGB-D cameras added to the station (Drake's ``CameraConfig``)."""
    plant_config: MultibodyPlantConfig = field(
        default_factory=lambda: MultibodyPlantConfig(
            time_step=0.002,
            contact_model="hydroelastic_with_fallback",
            discrete_contact_approximation="sap",
        )
    )
    """The MultibodyPlant (discrete, hydroelastic contact). A 2 ms step: measured against 1 ms
    and 4 ms on every object of the set at two random poses (scenarios/
    experiment_time_step.yaml), the verdicts agreed in 43 of 46 trials, the differences went
    both ways (successes 12, 13, 14 of 46), and 2 ms runs the carry 1.9x faster than 1 ms."""
    simulator_config: SimulatorConfig = field(
        default_factory=lambda: SimulatorConfig(publish_every_time_step=False)
    )
    visualization: VisualizationConfig = field(
        default_factory=lambda: VisualizationConfig(publish_period=1 / 32)
    )
    """Meshcat visualisation (illustration, contact forces); see Drake's VisualizationConfig."""
    task: str = ranged("pick", OneOf(TASKS))
    """``pick`` (the whole GbH pipeline) or ``settle`` (only the station)."""
    settle_time: float = ranged(0.5, NonNeg(60.0, "s"))
    """Simulated time (s) to let the object settle on the table before anything else."""
    scan_target: list[float] = ranged(lambda: [0.55, 0.0, 0.06],
                                      Items(3, what="coordinates (x, y, z in m)"))
    """p_WT (m): where the object is expected (the nominal spot, not its true pose): a first
    look searches around it (the object must be within ``scan.object_search_radius``) and the
    views are then aimed at what it found."""
    scan: ScanConfig = field(default_factory=ScanConfig)
    """Depth scan of the object (views, camera, TSDF, segmentation, cap, noise); 1 view:
    ``{num_views: 1}``. Its noise is seeded from the scenario's ``seed``."""
    gbh: GbhParams = field(default_factory=GbhParams)
    """Grasping-by-Hanging parameters (paper values by default). Its surface sampling is seeded
    from the scenario's ``seed``."""
    grasp_method: str = ranged("gbh", Registered(method_names, "registered in gbh_drake/method_spec.py"))
    """How grasps are chosen: a registered method (:mod:`gbh_drake.method_spec`): ``gbh`` (the
    paper), ``antipodal`` (the two-straight-finger baseline), ``gbh_fallback`` (GbH, then an
    antipodal grasp with the bar folded), and beyond the paper ``gbh_scoop``, ``gbh_regrasp``,
    ``gbh_plus`` (GbH, scoop, regrasp, tall scoop, fallback, one retry) and ``gbh_completed``
    (GbH on the scan completed by symmetry, ``completion``)."""
    antipodal: AntipodalParams = field(default_factory=AntipodalParams)
    """The antipodal grasp sampler (methods ``antipodal`` and ``gbh_fallback``)."""
    scoop: ScoopParams = section(ScoopParams, Relation(
        "<=", "pick.max_lift", "a scoop lifts at least scoop.min_lift; the gripper rises at "
        "most pick.max_lift", field="min_lift"))
    """The scoop of material lying flat (methods ``gbh_scoop``, ``gbh_plus``): which structures,
    the wedge's rules, the press on the table."""
    regrasp: RegraspParams = field(default_factory=RegraspParams)
    """The regrasp (methods ``gbh_regrasp``, ``gbh_plus``): how often, which resting poses, how
    many pinches are planned for."""
    completion: CompletionParams = field(default_factory=CompletionParams)
    """Shape completion of the scan's unseen side (method ``gbh_completed``, beyond the paper):
    the completion, its confidence, its grid."""
    pick: PickConfig = section(
        PickConfig, Relation("<=", "robot.hand.max_force", "the fingers' actuators apply at "
                             "most that", field="cage_test_force"),
        Relation("<", "robot.hand.force", "the cage test relaxes the squeeze to this force: at "
                 "the grasp force a pinch would pass it as a cage", field="cage_test_force"))
    """How the chosen grasp is executed (approach, lift until clear, carry, cage test, release)."""
    monitor: MonitorConfig = section(
        MonitorConfig,
        Relation("<", "pick.max_lift", "the gripper rises at most that far, so no object could "
                 "ever count as lifted", field="lifted_height", when=("task", "pick")),
        Relation("<=", "pick.lift_clearance", "the pick lifts the object's lowest point that "
                 "high: a higher threshold would judge a lift that went as planned not lifted",
                 field="lifted_height", when=("task", "pick")))
    """The success rules (lifted height, closed-loop tolerance)."""
    max_time: float = ranged(60.0, Pos(600.0, "s", "a pick takes about 10-20 simulated seconds"),
                             relations=(Relation(">", "settle_time", "the pick starts when "
                                                 "settling ends", when=("task", "pick")),))
    """Simulated seconds after which a trial is cut off, for each pick its machine may start (a
    method that retries or regrasps may start several: ``PickAndCarry.max_attempts``); a trial
    normally ends when the pick-and-carry machine has finished."""
    replay_fps: float = ranged(16.0, Pos(120.0, "frames/s"))
    """Frames per second of the saved Meshcat replay (fewer frames, smaller file)."""
    output_dir: str = ranged("", FilePath("folder"))
    """Where a run writes its replay and summary, relative to the scenario file's folder (given
    in an override: to the current folder); empty: ``output/<scenario file stem>`` under the
    current folder."""
    source_path: str = ""
    """Set by the loader: the scenario file itself (do not write it in YAML)."""

    @property
    def gripper(self) -> str:
        """The gripper variant this scenario runs: ``robot.gripper``, or the grasp method's
        (:attr:`~gbh_drake.method_spec.MethodSpec.gripper`) when that is ``auto``."""
        if self.robot.gripper != "auto":
            return self.robot.gripper
        return method_spec(self.grasp_method).gripper

    def station_directives(self) -> list[ModelDirective]:
        """The directives the station and the planner build from: ``directives`` with the
        gripper variant of :attr:`gripper` (:func:`gbh_drake.modeling.directives.with_gripper`)."""
        from gbh_drake.modeling.directives import with_gripper

        return with_gripper(self.directives, self.gripper)

    @property
    def directory(self) -> Path:
        """The folder of the scenario file (relative paths in the file resolve against it)."""
        return Path(self.source_path).resolve().parent if self.source_path else Path.cwd()

    def resolve(self, path: str) -> Path:
        p = Path(path).expanduser()
        return p if p.is_absolute() else self.directory / p

    def output_path(self) -> Path:
        if self.output_dir:
            return self.resolve(self.output_dir)
        stem = Path(self.source_path).stem if self.source_path else "scenario"
        return Path.cwd() / "output" / stem
