"""The scenario's model directives, checked offline before anything is built.

:func:`check_models` parses the directives once per distinct directives (cached per process)
into a plant and reads what the station needs of them (:class:`ModelInfo`): the arm
:data:`~gbh_drake.modeling.names.ARM`, the gripper and the table present, the arm's joint
limits, the hand's actuators, the frames a camera may be mounted on, the table top's box. Model
files must be local: ``package://`` of a known local package or ``file://``, never a package
Drake downloads (:data:`REMOTE_PACKAGES`), nested directive files included. Problems raise
:class:`~gbh_drake.core.ranges.FieldError` naming the field.
"""

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydrake.common.yaml import yaml_dump_typed
from pydrake.multibody.parsing import LoadModelDirectivesFromString, ModelDirective

from gbh_drake.core.ranges import FieldError, Path_
from gbh_drake.modeling.names import ARM, GRIPPER, GRIPPER_FILES, HAND_ACTUATORS, TABLE


@dataclass(frozen=True)
class ModelInfo:
    """What the scenario's directives give the station (read from a plant Drake parsed)."""

    model_names: tuple[str, ...]
    arm_limits: tuple[tuple[str, float, float], ...]
    """(joint, lower, upper) of panda_joint1..7 (rad)."""
    frames: frozenset[str]
    """Frame names a camera may be mounted on (scoped ``model::frame``, unique plain names)."""
    table_top: tuple[float, float, float, float, float] | None
    """(x_min, x_max, y_min, y_max, z_top) of the table's top box in W, None if not a box."""
    arm_base_xy: tuple[float, float]


_MODEL_CACHE: dict[str, ModelInfo | FieldError] = {}
_URI = re.compile(r"\b(package|file|model|https?)://([^\s'\"},\]]+)")
#: Drake's package that is downloaded on first use (never here: runs are offline).
REMOTE_PACKAGES = ("drake_models",)


def check_models(directives: list[ModelDirective], *, q_home: list[float],
                 object_model: str) -> ModelInfo:
    """Parses ``directives`` (offline, once per distinct directives) and checks what the
    station needs of them, then that no model is named ``object_model`` (the object's model
    name) and that ``q_home`` (``robot.q_home``) lies within the arm's joint limits."""
    key = yaml_dump_typed(_Directives(list(directives)))
    if key not in _MODEL_CACHE:
        try:
            _MODEL_CACHE[key] = _model_info(directives)
        except FieldError as e:
            _MODEL_CACHE[key] = e
    result = _MODEL_CACHE[key]
    if isinstance(result, FieldError):
        raise FieldError(result.path, result.problem)
    if object_model in result.model_names:
        raise FieldError(("directives",), f"a model is named {object_model!r} like the object: "
                                          "rename one of them")
    for i, (joint, lo, hi) in enumerate(result.arm_limits):
        if not lo <= q_home[i] <= hi:
            raise FieldError(("robot", "q_home", i), f"{q_home[i]:g} rad is outside {joint}'s "
                                                     f"limits [{lo:.4f}, {hi:.4f}] rad")
    return result


def with_gripper(directives: list[ModelDirective], gripper: str) -> list[ModelDirective]:
    """``directives`` with the hook gripper's model file that of the variant ``gripper``
    (``robot.gripper``: ``paper`` or ``wedge``, :data:`~gbh_drake.modeling.names.GRIPPER_FILES`)
    where they add one of the packaged grippers; a gripper file of your own is kept as it is
    for ``paper`` and refused (``robot.gripper``) for another variant. Returns new directives
    (the given ones are not changed)."""
    import copy

    if gripper not in GRIPPER_FILES:
        raise FieldError(("robot", "gripper"), f"must be one of {', '.join(GRIPPER_FILES)}, "
                                               f"got {gripper!r}")
    out = []
    for d in directives:
        if d.add_model and d.add_model.name == GRIPPER:
            if d.add_model.file not in GRIPPER_FILES.values():
                if gripper != "paper":
                    raise FieldError(("robot", "gripper"), f"{gripper}: the directives add "
                                     f"{GRIPPER!r} from {d.add_model.file}, not a packaged "
                                     "gripper; give the variant's file there instead")
            elif d.add_model.file != GRIPPER_FILES[gripper]:
                d = copy.deepcopy(d)
                d.add_model.file = GRIPPER_FILES[gripper]
        out.append(d)
    return out


@dataclass
class _Directives:
    """A holder to dump the directives as text: the cache key of :func:`check_models`."""

    directives: list[ModelDirective]


def _model_info(directives) -> ModelInfo:
    from pydrake.geometry import Box, SceneGraph
    from pydrake.multibody.parsing import ModelDirectives, ProcessModelDirectives
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.multibody.tree import FrameIndex

    from gbh_drake.modeling.package_map import make_parser

    names = [d.add_model.name for d in directives if d.add_model is not None]
    for required in (ARM, GRIPPER, TABLE):
        if required not in names:
            raise FieldError(("directives",), f"must add a model named {required!r} (the "
                                              "station needs it); the default directives are in "
                                              "gbh_drake/scenario/schema.py")
    plant = MultibodyPlant(0.0)
    scene_graph = SceneGraph()
    plant.RegisterAsSourceForSceneGraph(scene_graph)
    parser = make_parser(plant)
    known_packages = [p for p in parser.package_map().GetPackageNames()
                      if p not in REMOTE_PACKAGES]
    for i, d in enumerate(directives):
        for kind in ("add_model", "add_directives"):
            item = getattr(d, kind)
            if item is not None:
                _check_uri(("directives", i, kind, "file"), item.file, parser.package_map(),
                           known_packages, depth=0)
        if d.add_model is not None and d.add_model.name in (ARM, GRIPPER) \
                and d.add_model.default_joint_positions:
            raise FieldError(("directives", i, "add_model", "default_joint_positions"),
                             "the station sets the robot's joints (robot.q_home, "
                             "robot.gripper_open); remove it")
    try:
        ProcessModelDirectives(ModelDirectives(directives=list(directives)), plant, parser)
        plant.Finalize()
    except Exception as e:  # noqa: BLE001  (Drake's parser raises RuntimeError)
        raise FieldError(("directives",), " ".join(str(e).split())) from None
    arm = plant.GetModelInstanceByName(ARM)
    gripper = plant.GetModelInstanceByName(GRIPPER)
    limits = []
    for i in range(1, 8):
        joint_name = f"panda_joint{i}"
        if not plant.HasJointNamed(joint_name, arm):
            raise FieldError(("directives",), f"model {ARM!r} has no joint {joint_name!r} (the "
                                              "station drives panda_joint1..7)")
        joint = plant.GetJointByName(joint_name, arm)
        limits.append((joint_name, float(joint.position_lower_limits()[0]),
                       float(joint.position_upper_limits()[0])))
    for joint_name in HAND_ACTUATORS:
        if not plant.HasJointActuatorNamed(joint_name, gripper):
            raise FieldError(("directives",), f"model {GRIPPER!r} has no actuated joint "
                                              f"{joint_name!r} (use the hook_gripper model)")
    frames: set[str] = set()
    plain: dict[str, int] = {}
    for i in range(plant.num_frames()):
        frame = plant.get_frame(FrameIndex(i))
        frames.add(frame.scoped_name().get_full())
        plain[frame.name()] = plain.get(frame.name(), 0) + 1
    frames |= {n for n, count in plain.items() if count == 1}
    context = plant.CreateDefaultContext()
    base = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName("panda_link0", arm)) \
        if plant.HasBodyNamed("panda_link0", arm) else None
    table_top = None
    table = plant.GetModelInstanceByName(TABLE)
    if plant.HasBodyNamed("table_top", table):
        body = plant.GetBodyByName("table_top", table)
        inspector = scene_graph.model_inspector()
        X_WB = plant.EvalBodyPoseInWorld(context, body)
        for gid in plant.GetCollisionGeometriesForBody(body):
            shape = inspector.GetShape(gid)
            if isinstance(shape, Box):
                X_WG = X_WB @ inspector.GetPoseInFrame(gid)
                half = np.array([shape.width(), shape.depth(), shape.height()]) / 2
                corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1)
                                    for sz in (-1, 1)]) * half
                p = np.array([X_WG.multiply(c) for c in corners])
                table_top = (p[:, 0].min(), p[:, 0].max(), p[:, 1].min(), p[:, 1].max(),
                             p[:, 2].max())
                break
    return ModelInfo(tuple(plant.GetModelInstanceName(plant.GetModelInstanceByName(n))
                           for n in names), tuple(limits), frozenset(frames),
                     tuple(float(v) for v in table_top) if table_top else None,
                     tuple(base.translation()[:2]) if base is not None else (0.0, 0.0))


def _check_uri(path: Path_, uri: str, package_map, known: list[str], depth: int,
               stack: tuple[Path, ...] = ()) -> None:
    """A model file's URI: package:// of a local package or file:// (Drake's parser refuses
    plain paths when directives come from text, and would download drake_models). Nested
    directive files are followed: their URIs too, no loop (Drake would recurse until it
    crashes), at most 8 deep."""
    match = _URI.match(uri.strip())
    if not match:
        raise FieldError(path, f"{uri!r} is not a package:// or file:// URI (e.g. "
                               "package://gbh_drake/table.sdf or file:///abs/path/model.sdf)")
    scheme, rest = match.groups()
    if scheme in ("http", "https"):
        raise FieldError(path, f"{uri!r}: runs are offline; give a local file")
    if scheme == "package":
        package = rest.split("/", 1)[0]
        if package in REMOTE_PACKAGES:
            raise FieldError(path, f"{uri!r}: package {package!r} is downloaded by Drake on "
                                   "first use and runs are offline; use a local file")
        if package not in known:
            raise FieldError(path, f"{uri!r}: unknown package {package!r} (known: "
                                   f"{', '.join(sorted(known))})")
        local = Path(package_map.GetPath(package)) / rest.split("/", 1)[-1]
    elif scheme == "file":
        local = Path(rest if rest.startswith("/") else "/" + rest)
    else:
        return
    if not local.is_file():
        raise FieldError(path, f"{uri!r}: file not found: {local}")
    if local.suffix not in (".yaml", ".yml", ".dmd"):
        return
    local = local.resolve()
    if local in stack:
        raise FieldError(path, f"directive files include each other in a loop through {local} "
                               "(Drake would recurse until it crashes)")
    if depth >= 8:
        raise FieldError(path, f"directive files nested more than 8 deep (at {local})")
    text = local.read_text(errors="replace")
    for nested in _URI.finditer(text):
        _check_uri(path, nested.group(0), package_map, known, depth + 1, stack + (local,))


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
    return directives if table else without_table(directives)


def without_table(directives: list[ModelDirective]) -> list[ModelDirective]:
    """``directives`` less the ones that add and weld the :data:`TABLE` model."""
    return [d for d in directives
            if not (d.add_model and d.add_model.name == TABLE)
            and not (d.add_weld and d.add_weld.child.startswith(f"{TABLE}::"))]
