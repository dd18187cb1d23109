"""Scenario files: one YAML file describes one run (robot, table, object, cameras, simulation).

The schema is the :class:`Scenario` dataclass; loading uses Drake's ``yaml_load_typed`` (so typos
fail loudly) after a field-by-field check that names the file, the field and the line of any
problem (:class:`ScenarioError`). Drake's own config structs are reused where they exist
(``MultibodyPlantConfig``, ``SimulatorConfig``, ``VisualizationConfig``, ``CameraConfig``,
``schema.Transform`` for poses, which also takes distributions such as ``!UniformVector``, sampled
from the scenario's ``seed``).
"""


from dataclasses import dataclass, field
from pathlib import Path

from pydrake.common.yaml import yaml_load_typed
from pydrake.multibody.parsing import LoadModelDirectivesFromString, ModelDirective
from pydrake.multibody.plant import MultibodyPlantConfig
from pydrake.systems.analysis import SimulatorConfig
from pydrake.systems.sensors import CameraConfig
from pydrake.visualization import VisualizationConfig

from gbh_drake.config import (
    GRASP_METHODS,
    MonitorConfig,
    ObjectConfig,
    PickConfig,
    RobotConfig,
)
from gbh_drake.core.antipodal import AntipodalParams
from gbh_drake.core.params import GbhParams
from gbh_drake.perception.config import ScanConfig
from gbh_drake.yaml_check import YamlFieldError, check_yaml_against_schema

#: What a run does: ``pick`` = settle, scan, detect, synthesise, score, pick the best reachable
#: grasp, carry, release and judge it; ``settle`` = only let the object settle (a smoke test of
#: the station).
TASKS = ("pick", "settle")


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


def default_directives() -> list[ModelDirective]:
    return LoadModelDirectivesFromString(DEFAULT_DIRECTIVES).directives


class ScenarioError(ValueError):
    """A scenario file is invalid; the message names the file and the field."""


@dataclass
class Scenario:
    """One run of gbh_drake. Units: metres, radians, seconds, kilograms."""

    seed: int = 0
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
            time_step=0.001,
            contact_model="hydroelastic_with_fallback",
            discrete_contact_approximation="sap",
        )
    )
    """The MultibodyPlant (discrete, hydroelastic contact)."""
    simulator_config: SimulatorConfig = field(
        default_factory=lambda: SimulatorConfig(publish_every_time_step=False)
    )
    visualization: VisualizationConfig = field(
        default_factory=lambda: VisualizationConfig(publish_period=1 / 32)
    )
    """Meshcat visualisation (illustration, contact forces); see Drake's VisualizationConfig."""
    task: str = "pick"
    """``pick`` (the whole GbH pipeline) or ``settle`` (only the station)."""
    settle_time: float = 0.5
    """Simulated time (s) to let the object settle on the table before anything else."""
    scan_target: list[float] = field(default_factory=lambda: [0.55, 0.0, 0.06])
    """p_WT (m): the workspace point the cameras look at and crop around (the nominal object spot,
    not the object's true pose)."""
    scan: ScanConfig = field(default_factory=ScanConfig)
    """Depth scan of the object (views, camera, TSDF, crop, noise); 1 view: ``{num_views: 1}``.
    Its ``noise_seed`` is replaced by the scenario's ``seed``."""
    gbh: GbhParams = field(default_factory=GbhParams)
    """Grasping-by-Hanging parameters (paper values by default). Its ``seed`` is replaced by the
    scenario's ``seed``."""
    grasp_method: str = "gbh"
    """``gbh`` (the paper), ``antipodal`` (the two-straight-finger baseline) or ``gbh_fallback``
    (GbH, then an antipodal grasp with the bar folded when GbH has nothing reachable)."""
    antipodal: AntipodalParams = field(default_factory=AntipodalParams)
    """The antipodal grasp sampler (methods ``antipodal`` and ``gbh_fallback``)."""
    pick: PickConfig = field(default_factory=PickConfig)
    """How the chosen grasp is executed (approach, lift until clear, carry, cage test, release)."""
    monitor: MonitorConfig = field(default_factory=MonitorConfig)
    """The success rules (lifted height, closed-loop tolerance)."""
    max_time: float = 60.0
    """Simulated seconds after which a trial is cut off (it normally ends when the pick-and-carry
    machine has finished)."""
    replay_fps: float = 16.0
    """Frames per second of the saved Meshcat replay (fewer frames, smaller file)."""
    output_dir: str = ""
    """Where a run writes its replay and summary; empty: ``output/<scenario file stem>``."""
    source_path: str = ""
    """Set by the loader: the scenario file itself (do not write it in YAML)."""

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


def load_scenario(filename: str | Path, *, overrides: str = "") -> Scenario:
    """Loads and validates a scenario file; ``overrides`` is YAML text applied on top of it.

    Raises :class:`ScenarioError` naming the file and field on any problem."""
    path = Path(filename)
    if not path.is_file():
        raise ScenarioError(f"{path}: scenario file not found")
    text = path.read_text()
    scenario = _load_text(text, str(path), Scenario())
    if overrides:
        scenario = _load_text(overrides, f"{path} (overrides)", scenario)
    scenario.source_path = str(path.resolve())
    validate_scenario(scenario, str(path))
    return scenario


def _load_text(text: str, origin: str, defaults: Scenario) -> Scenario:
    try:
        check_yaml_against_schema(text, Scenario)
    except YamlFieldError as e:
        raise ScenarioError(f"{origin}: {e}") from e
    try:
        return yaml_load_typed(schema=Scenario, data=text or "{}", defaults=defaults)
    except Exception as e:  # what the field check did not catch
        raise ScenarioError(f"{origin}: {type(e).__name__}: {e}") from e


def validate_scenario(scenario: Scenario, origin: str) -> None:
    """Semantic checks that the schema cannot express. Raises :class:`ScenarioError`."""

    def fail(field_path: str, message: str):
        raise ScenarioError(f"{origin}: {field_path}: {message}")

    obj = scenario.object
    if obj.mesh:
        mesh_path = scenario.resolve(obj.mesh)
        if not mesh_path.is_file():
            fail("object.mesh", f"file not found: {mesh_path}")
        from gbh_drake.objects import MeshImportError, load_mesh_file

        try:
            load_mesh_file(mesh_path, scale=obj.scale if obj.scale > 0 else 1.0)
        except MeshImportError as e:
            fail("object.mesh", str(e))
    elif not obj.name:
        fail("object", "give either a named object (object.name) or a mesh file (object.mesh)")
    else:
        from gbh_drake.objects import list_objects  # the object set (generators) on demand

        if obj.name not in list_objects():
            fail("object.name", f"unknown object {obj.name!r} (known: {', '.join(list_objects())})")
    if obj.scale <= 0:
        fail("object.scale", f"must be positive, got {obj.scale}")
    if obj.density < 0:
        fail("object.density", f"must be >= 0, got {obj.density}")
    if len(scenario.robot.q_home) != 7:
        fail("robot.q_home", f"needs 7 joint positions, got {len(scenario.robot.q_home)}")
    for name in ("arm_kp", "arm_kd"):
        if len(getattr(scenario.robot, name)) != 7:
            fail(f"robot.{name}", "needs 7 values")
    if scenario.settle_time < 0:
        fail("settle_time", "must be >= 0")
    if scenario.task not in TASKS:
        fail("task", f"must be one of {', '.join(TASKS)}, got {scenario.task!r}")
    if len(scenario.scan_target) != 3:
        fail("scan_target", "needs 3 coordinates (m)")
    for name, check in (("scan", scenario.scan.validate), ("gbh", scenario.gbh.check)):
        try:
            check()
        except ValueError as e:
            fail(name, str(e))
    # One seed for the whole run: the stages' own seeds are derived from it.
    if scenario.gbh.seed != 0:
        fail("gbh.seed", "set the scenario's seed instead (it seeds every stage)")
    if scenario.scan.noise_seed != 0:
        fail("scan.noise_seed", "set the scenario's seed instead (it seeds every stage)")
    if obj.drop_height < 0:
        fail("object.drop_height", f"must be >= 0, got {obj.drop_height}")
    robot = scenario.robot
    gains = [*robot.arm_kp, *robot.arm_kd, robot.hand.kp, robot.hand.kd]
    if min(gains) <= 0:
        fail("robot", "PD gains (arm_kp, arm_kd, hand.kp, hand.kd) must be positive")
    if scenario.grasp_method not in GRASP_METHODS:
        fail("grasp_method", f"must be one of {', '.join(GRASP_METHODS)}, got "
                             f"{scenario.grasp_method!r}")
    if scenario.visualization.publish_period <= 0:
        fail("visualization.publish_period", "must be positive (s)")
    names = [d.add_model.name for d in scenario.directives if d.add_model is not None]
    for required in ("panda", "hook_gripper", "table"):
        if required not in names:
            fail("directives", f"must add a model named {required!r} (the station needs it)")
    problem = directive_problem(scenario.directives)
    if problem:
        fail("directives", problem)
    if scenario.plant_config.time_step <= 0:
        fail("plant_config.time_step", "gbh_drake needs a discrete plant (time_step > 0)")


def directive_problem(directives: list[ModelDirective]) -> str:
    """What Drake's parser says of ``directives`` (a missing file, a bad frame name...), or ""."""
    from pydrake.multibody.parsing import ModelDirectives, ProcessModelDirectives
    from pydrake.multibody.plant import MultibodyPlant

    from gbh_drake.modeling.package_map import make_parser

    plant = MultibodyPlant(0.0)
    try:
        ProcessModelDirectives(ModelDirectives(directives=directives), plant, make_parser(plant))
    except RuntimeError as e:
        return str(e)
    return ""
