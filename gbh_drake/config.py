"""The configuration of a trial, on the ground floor: plain dataclasses that import nothing of
the pipeline (perception, planning, systems).

Each dataclass is loadable with Drake's ``yaml_load_typed`` (no ``from __future__ import
annotations`` here: the loader needs real types) and documents every field with its unit and
default. :class:`gbh_drake.scenario.Scenario` composes them with Drake's own config structs and
the two other ground-floor configs, :class:`gbh_drake.core.params.GbhParams` and
:class:`gbh_drake.perception.config.ScanConfig`. Frames: W is the world (z up, the table top is
the plane z = 0); lengths in metres, angles in radians unless a name says ``_deg``, forces in
newtons, times in seconds, masses in kilograms.
"""

from dataclasses import dataclass, field

from pydrake.common.schema import Transform
from pydrake.multibody.parsing import LoadModelDirectivesFromString, ModelDirective

#: Franka's "ready" pose, the gripper pointing down over the table (rad).
DEFAULT_Q_HOME = [0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785398]

#: The station's fixed models. G of the hook gripper is 5.84 cm past panda_hand along its z.
DEFAULT_DIRECTIVES = """
directives:
- add_model: {name: panda, file: "package://gbh_drake/panda_arm.urdf"}
- add_weld: {parent: world, child: panda::panda_link0}
- add_model: {name: hook_gripper, file: "package://gbh_drake/hook_gripper.sdf"}
- add_weld:
    parent: panda::panda_link8
    child: hook_gripper::panda_hand
    X_PC: {rotation: !Rpy {deg: [0, 0, -45]}}
- add_model: {name: table, file: "package://gbh_drake/table.sdf"}
- add_weld:
    parent: world
    child: table::table_top
    X_PC: {translation: [0.35, 0, 0]}
"""


def default_directives(*, table: bool = True) -> list[ModelDirective]:
    """The station's fixed models (without the table's two directives when not ``table``)."""
    directives = LoadModelDirectivesFromString(DEFAULT_DIRECTIVES).directives
    if table:
        return directives
    return [d for d in directives
            if not (d.add_model and d.add_model.name == "table")
            and not (d.add_weld and d.add_weld.child.startswith("table::"))]

#: How grasps are chosen (``Scenario.grasp_method``):
#:
#: * ``gbh``: Grasping by Hanging (the paper): the hook gripper's bar deployed;
#: * ``antipodal``: a learning-free antipodal baseline with two straight fingers (the bar
#:   retracted), the paper's fairness rule for its baseline;
#: * ``gbh_fallback``: GbH, and when it finds nothing hangable or nothing reachable, an antipodal
#:   grasp with the bar retracted (the revolute joint the paper proposes in Sec. 4).
GRASP_METHODS = ("gbh", "antipodal", "gbh_fallback")


@dataclass
class RandomRestingPose:
    """A random start pose: one of the object's stable resting orientations (drawn by its
    probability), a uniform yaw and a uniform position on the table, from the scenario's seed."""

    x: list[float] = field(default_factory=lambda: [0.45, 0.62])
    """Range [min, max] (m) of the object's x in W (its footprint's centre)."""
    y: list[float] = field(default_factory=lambda: [-0.18, 0.18])
    """Range [min, max] (m) of the object's y in W."""
    yaw_deg: list[float] = field(default_factory=lambda: [-180.0, 180.0])
    """Range [min, max] (deg) of the yaw about +z_W."""
    stable: bool = True
    """Draw among the object's stable resting orientations (trimesh); False: as modelled."""


@dataclass
class ObjectConfig:
    """The object to pick."""

    name: str = "mug_classic"
    """A named object of the object set (``gbh objects list``); ignored when ``mesh`` is set."""
    mesh: str = ""
    """Path to any mesh file (obj/stl/ply/glb/gltf/off), relative to the scenario file; ``scale``
    turns its units into metres. It is placed resting on the table whatever its origin."""
    scale: float = 1.0
    """Uniform scale applied to ``mesh`` (e.g. 0.001 for a file in millimetres)."""
    orientation: str = "keep"
    """How a ``mesh`` file stands on the table: ``keep`` (the file's z is up), ``nearest_stable``
    (its stable resting pose nearest to that) or ``most_probable`` (its likeliest resting
    pose)."""
    density: float = 0.0
    """kg/m^3 for mass and inertia; 0: the named object's own density (600 for a mesh)."""
    mass: float = 0.0
    """kg; when positive, the object's mass (inertia scaled to it) instead of ``density``."""
    pose: Transform = field(default_factory=lambda: Transform(translation=[0.55, 0.0, 0.0]))
    """X_WO, the object's pose on the table (its lowest point at z = 0 when the translation's z
    is 0). Takes Drake's distributions (``!UniformVector``, ``!Rpy {deg: !UniformVector ...}``),
    sampled from the scenario's seed. Ignored when ``random_pose`` is given."""
    random_pose: RandomRestingPose | None = None
    """When given: a stable resting pose, yaw and position drawn from the seed."""
    drop_height: float = 0.002
    """Extra height (m) above the resting pose at the start, so the object settles onto the
    table."""


@dataclass
class HandConfig:
    """The Franka Hand's finger drive: force-limited like the real hand (70 N continuous, 140 N
    peak grasp force, about 0.05 m/s per finger). Each finger's joint is a position-controlled
    actuator (the plant's implicit PD, stiffness ``kp``) whose effort is limited to
    ``max_force`` by the plant; the hand driver moves its set point at ``speed`` and keeps it
    within ``force / kp`` of the measured finger, so a blocked finger squeezes with ``force``."""

    force: float = 70.0
    """Grasp force (N) each finger applies once it is blocked (Franka: 70 N continuous)."""
    max_force: float = 140.0
    """Effort limit (N) of each finger's actuator (Franka: 140 N peak)."""
    speed: float = 0.05
    """Finger speed (m/s, each finger) while opening or closing."""
    kp: float = 20000.0
    """Finger position stiffness (N/m) of the drive."""
    kd: float = 60.0
    """Finger damping (N s/m) of the drive."""


@dataclass
class RobotConfig:
    """The Franka arm with the hook gripper."""

    q_home: list[float] = field(default_factory=lambda: list(DEFAULT_Q_HOME))
    """Arm joint positions (rad, 7 values, panda_joint1..7) at the start and when idle."""
    gripper_open: bool = True
    """Whether the gripper starts open (q = l_w / 2) or closed."""
    arm_kp: list[float] = field(default_factory=lambda: [4000.0] * 4 + [1500.0] * 3)
    """Joint PD stiffness (N m / rad) of panda_joint1..7 (set on the actuators by name)."""
    arm_kd: list[float] = field(default_factory=lambda: [200.0] * 4 + [60.0] * 3)
    """Joint PD damping (N m s / rad) of panda_joint1..7."""
    hand: HandConfig = field(default_factory=HandConfig)
    """The fingers' force-limited drive."""


@dataclass
class PickConfig:
    """How a chosen grasp is planned and executed: approach, insert, close, lift until clear,
    carry to ``place_position``, cage test, lower, release, retreat."""

    approach_distance: float = 0.10
    """Pre-grasp offset (m) back along the approach direction (-z_G)."""
    max_approach_distance: float = 0.25
    """The pre-grasp pose backs off in 5 cm steps up to this distance (m) until the gripper is
    clear of the scanned object's convex hull."""
    lift_clearance: float = 0.05
    """After the lift, the object's lowest point (estimated from the scan, hanging from the
    grasp) is at least this far (m) above the table."""
    min_lift: float = 0.10
    """The gripper rises at least this much (m)."""
    max_lift: float = 0.40
    """The gripper rises at most this much (m); lower when the arm cannot reach higher."""
    place_position: list[float] = field(default_factory=lambda: [0.40, 0.30])
    """Where (x, y in W, m) the object is carried, lowered and released."""
    place_depth: float = 0.03
    """The gripper is lowered until the hand's load drops (the object stands on the table: a
    hook that still carries the object would drag it along as it opens), at most until the
    object's estimated lowest point is this far (m) below the table top."""
    unloaded_fraction: float = 0.4
    """The object counts as set down when the hand's vertical load falls below this fraction of
    what it was while carried (as Franka senses its external force)."""
    unload_depth: float = 0.006
    """Once set down, the gripper goes on down this far (m) so that the hook hangs free in the
    hole before the fingers open (a bar pressed against the material would drag it along)."""
    cage_test_force: float = 2.0
    """Grasp force (N) during the cage test after the carry: with the squeeze relaxed to this
    force, a caged object keeps hanging on the closed loop and a pinched one slides out."""
    cage_test_time: float = 1.0
    """Duration (s) of the cage test."""
    hold_time: float = 0.5
    """Time (s) the object is held still at the place position, full grasp force, before the
    cage test."""
    release_depth: float = 0.02
    """After opening, a parallel hook grasp goes this far (m) on along +z_G (less where the hand
    would come closer to the table than the grasp clearance), so that the bar leaves the
    material it was under, ..."""
    release_shift: float = 0.015
    """... then slides this far (m) along -y_G (toward the L rod's side), so that the bar comes
    out of the hole tip first before the gripper backs off. (A vertical grasp opens about its
    straight rod instead, the reverse of its closing: the bar leaves from under the material.)"""
    retreat_distance: float = 0.10
    """After releasing, the gripper backs off this far (m) along -z_G."""
    plan_paths: bool = True
    """Plan the transfer by RRT-Connect and collision-check every segment (False: IK only,
    straight joint-space moves)."""
    planner_iterations: int = 3000
    """RRT-Connect iterations before a transfer is given up."""
    max_grasps: int = 10
    """At most this many ranked grasps are tried, in order, before 'no reachable grasp'."""


@dataclass
class MonitorConfig:
    """The success rules of the ``CageMonitor``, fixed before any experiment."""

    lifted_height: float = 0.02
    """The object counts as lifted when its lowest point is this far (m) above the table."""
    closed_tolerance: float = 0.002
    """The hook's loop counts as closed when each finger is within this distance (m) of its
    closed position (the bar's tip on the straight rod)."""
    period: float = 0.01
    """Update period (s) of the monitor."""
