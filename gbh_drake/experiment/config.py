"""The experiment file: objects x trials x methods over one base scenario.

An experiment YAML (schema :class:`Experiment`, loaded with Drake's ``yaml_load_typed``: unknown
or mistyped keys fail loudly)::

    name: table1                     # optional; default: the file's stem
    base: default.yaml               # the base scenario file (relative to this file)
    base_overrides: {max_time: 60}   # YAML applied over the base for every method (optional)
    objects: [mug_classic, kettle, ball]  # built-in names, or names of the object set's
    object_set: my_set.yaml          # an object set's manifest (optional; relative to this
                                     # file): objects empty = all of its objects
    trials: 5                        # trials per object and method
    seed: 0                          # with (object, trial), seeds every trial
    pose: {x: [0.45, 0.62], y: [-0.18, 0.18], yaw_deg: [-180, 180], stable: true}
    protocols: [stable, natural]     # how objects are set down; default [stable]
    methods:                         # default: the four below
    - {name: gbh-10, paper: GbH 10 views,
       overrides: {grasp_method: gbh, scan: {num_views: 10}, gbh: {d2: 0.0}}}
    - ...
    replays: failures                # failures | all | none
    output_dir: ""                   # default: output/<file stem> under the working folder
    engine: local                    # local (worker processes) | ray
    ray_address: local               # with engine: ray: local | auto | host:port | ray://host:port

A method is a name and YAML overrides applied over the base scenario, exactly as ``gbh run
--set`` applies its text (``yaml_load_typed`` with the base as ``defaults``): a user adds a
method by adding an entry. ``overrides`` may be written as a mapping (as above, Drake's tags such
as ``!Rpy`` included) or as YAML text.

Each trial's scenario is the method's, with ``object.name``, ``object.random_pose`` (the
experiment's ``pose``, its ``rest`` the trial's protocol) and ``seed`` set; the seed is
:func:`trial_seed` of (seed, object, trial, protocol) alone, so every method sees the same start
pose, and a result depends neither on the order of the trials nor on which worker ran it.

Protocols (``protocols``, fixed before any number is seen; :data:`PROTOCOLS`): ``stable``, each
trial's object in one of its stable resting poses drawn by probability (today's experiment, its
seeds and rows unchanged); ``natural``, each object in the rest a person would set it down in,
declared once per object of the set with its reason (``gbh_drake/objects/catalog.py``). Both
draw a random yaw and position. A trial is (object, method, trial, protocol).

Where the trials run (``engine``, ``ray_address``; ``gbh experiment --ray ADDRESS`` overrides
both) is not part of the experiment's definition: it enters no trial's scenario or digest, nor
the ``experiment.yaml`` written into its folder (:data:`WHERE_FIELDS`), so a folder's rows are
resumed whatever engine ran them (docs/ray.md).
"""

import copy
import dataclasses
import hashlib
import os
import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml
from pydrake.common.yaml import yaml_dump_typed

from gbh_drake.core.ranges import (
    FieldError,
    FilePath,
    Int,
    Items,
    OneOf,
    check_fields,
    format_path,
    ranged,
)
from gbh_drake.core.words import counted
from gbh_drake.experiment.report import PAPER_TABLE1
from gbh_drake.experiment.task import TrialTask
from gbh_drake.scenario import (
    RESTS,
    RandomRestingPose,
    Scenario,
    ScenarioError,
    load_scenario,
    validate_scenario,
)
from gbh_drake.scenario.loader import apply_overrides
from gbh_drake.yamlfiles.layers import (
    LayerError,
    Layers,
    file_layer,
    load_layers,
    override_layers,
)
from gbh_drake.yamlfiles.yaml_text import (
    YamlTextError,
    compose,
    compose_own,
    line_of,
    node_at,
    read_text,
    serialize,
)

#: Most trials an experiment may hold (objects x trials x methods x protocols): its task list
#: (each trial's scenario text) is built before the first trial runs, 15-30 ms a trial
#: (measured: 10000 trials take 2.5-5 min), and 10000 trials of 30 s are 3.5 CPU-days.
MAX_TOTAL_TRIALS = 10_000

#: Fields of a trial's scenario that the experiment sets for every trial (from ``objects``,
#: ``pose``, the protocol and ``seed``) or clears: a method's overrides or ``base_overrides``
#: that set them would be silently replaced, so they are refused.
SET_BY_EXPERIMENT = {
    ("object", "name"): "each trial's object is one of the experiment's objects",
    ("object", "mesh"): "each trial's object is one of the experiment's objects (named "
                        "objects of the set)",
    ("object", "set"): "each trial's object is one of the experiment's objects (give the "
                       "experiment's object_set)",
    ("object", "pose"): "each trial's start pose is drawn from the experiment's pose",
    ("object", "random_pose"): "each trial's start pose is drawn from the experiment's pose "
                               "(set it there)",
    ("seed",): "each trial's seed comes from the experiment's seed, object and trial (set "
               "the experiment's seed)",
    ("output_dir",): "the experiment writes into its own folder (its output_dir or --out)",
    ("source_path",): "is set by the loader",
}

#: What ``replays`` may say: keep a Meshcat replay of every failed trial, of every trial, or none.
REPLAY_MODES = ("failures", "all", "none")

#: The protocols an experiment may run: how each trial's object is set down (the values of the
#: scenario's ``object.random_pose.rest``, see :data:`gbh_drake.scenario.schema.RESTS`).
PROTOCOLS = RESTS


#: The longest method name, in bytes (it is part of file names).
MAX_METHOD_NAME = 80

#: Where an experiment's trials may run (``engine``): local worker processes, or Ray tasks.
ENGINES = ("local", "ray")

#: Fields that say where the trials run, not what they are: left out of the folder's
#: ``experiment.yaml`` (:func:`experiment_yaml`); no trial's scenario holds them.
WHERE_FIELDS = ("engine", "ray_address", "trials_per_worker")


class ExperimentError(LayerError):
    """An experiment file or folder is invalid; the message names the file (or ``--set``
    text), the field and its line: ``<origin>: <field> (line N): <problem>`` as a scenario's
    errors read (:class:`~gbh_drake.yamlfiles.layers.LayerError`)."""


@dataclass
class MethodConfig:
    """One method of the experiment: a name and its overrides of the base scenario."""

    name: str = ""
    """The method's name in rows, tables and file names (e.g. ``gbh-10``)."""
    overrides: str = ""
    """YAML applied over the base scenario (``grasp_method``, ``scan.num_views``, ``gbh.d2``...).
    In the file it may be a mapping; it is kept as text."""
    paper: str = ""
    """The row of the paper's Table 1 shown beside this method (a key of ``PAPER_TABLE1``:
    ``GbH 10 views``, ``GbH 1 view``, ``GraspNet 1 view``), or empty."""


def default_methods() -> list[MethodConfig]:
    """The paper's three groups (our antipodal baseline in GraspNet's place) and GbH with the
    antipodal fallback (the bar retracted; the paper's Sec. 4 proposal)."""
    return [
        MethodConfig("gbh-10", "{grasp_method: gbh, scan: {num_views: 10}, gbh: {d2: 0.0}}",
                     "GbH 10 views"),
        MethodConfig("gbh-1", "{grasp_method: gbh, scan: {num_views: 1}, gbh: {d2: 0.005}}",
                     "GbH 1 view"),
        MethodConfig("antipodal", "{grasp_method: antipodal, scan: {num_views: 1}}",
                     "GraspNet 1 view"),
        MethodConfig("gbh+fallback",
                     "{grasp_method: gbh_fallback, scan: {num_views: 10}, gbh: {d2: 0.0}}"),
    ]


@dataclass
class Experiment:
    """Objects x trials x methods over a base scenario. Units as in the scenario (m, deg)."""

    name: str = ""
    """Shown in the reports; empty: the file's stem."""
    base: str = ranged("", FilePath("base scenario file"))
    """The base scenario file (required), relative to the experiment file (given by ``--set``:
    to the current folder)."""
    base_overrides: str = ""
    """YAML applied over the base scenario for every method (a mapping in the file, or text)."""
    objects: list[str] = ranged(list, Items(None, None, what="object names", unique=True))
    """Names of objects: of ``object_set`` (looked up first) or of the built-in set (``gbh
    objects list``), each once; empty with an ``object_set``: every object of the set."""
    object_set: str = ranged("", FilePath("object set manifest"))
    """An object set's manifest (:mod:`gbh_drake.objects.sets`), relative to the experiment
    file: its objects (meshes with their masses, rests and ground truth, or built-in ones)."""
    trials: int = ranged(5, Int(1, 1000, "per object, method and protocol; the paper ran 5"))
    """Trials per object and method (in each protocol). At most :data:`MAX_TOTAL_TRIALS`
    trials in all (objects x trials x methods x protocols)."""
    seed: int = ranged(0, Int(0, 2**64 - 1, "seeds are unsigned 64-bit integers"))
    """With the object's name and the trial's index, seeds each trial (non-negative)."""
    pose: RandomRestingPose = field(default_factory=RandomRestingPose)
    """Where each trial's object starts: a random stable resting pose, a yaw and a position on
    the reachable part of the table (``object.random_pose`` of the trial's scenario; its
    ``rest`` is set by ``protocols``)."""
    protocols: list[str] = ranged(lambda: ["stable"], Items(None, OneOf(PROTOCOLS),
                                                            what="protocols", unique=True))
    """How the objects are set down, each a full run of objects x trials x methods: ``stable``
    (a random stable resting pose by its probability) and/or ``natural`` (the rest a person
    would set each object down in, declared in the object set); see :data:`PROTOCOLS`."""
    methods: list[MethodConfig] = field(default_factory=default_methods)
    """The methods compared; every one runs every (object, trial)."""
    replays: str = ranged("failures", OneOf(REPLAY_MODES))
    """Meshcat replays kept: ``failures`` (every failed trial), ``all`` or ``none``."""
    output_dir: str = ranged("", FilePath("folder"))
    """The experiment's folder, relative to the experiment file (given by ``--set``: to the
    current folder); empty: ``output/<file stem>`` under the working folder."""
    engine: str = ranged("local", OneOf(ENGINES, note="local worker processes, or Ray tasks at "
                                                      "ray_address"))
    """Where the trials run: ``local`` (worker processes on this machine, ``--workers``) or
    ``ray`` (Ray tasks at ``ray_address``). ``gbh experiment --ray ADDRESS`` overrides it; it
    changes no row (see :data:`WHERE_FIELDS`)."""
    ray_address: str = "local"
    """With ``engine: ray``: ``local`` (a Ray started for this experiment, loopback only),
    ``auto`` (the cluster this machine is a node of) or a cluster's address (``host:port``,
    ``ray://host:port``)."""
    trials_per_worker: int = ranged(
        20, Int(1, 100_000, "trials a worker process runs before a fresh one replaces it"))
    """Trials a worker process (local, or a Ray worker) runs before a fresh process replaces it.
    pydrake never frees a trial's Python LeafSystems (their callbacks hold them), so a worker
    grows by about 25 MB per trial (``bench/bench_worker_memory.py``); a fresh process costs
    its imports and first build (about 6.5 s, docs/speed.md). It changes no row (see
    :data:`WHERE_FIELDS`)."""
    source_path: str = ""
    """Set by the loader: the experiment file itself (do not write it in YAML)."""

    @property
    def directory(self) -> Path:
        return Path(self.source_path).resolve().parent if self.source_path else Path.cwd()

    @property
    def object_set_path(self) -> Path | None:
        """The object set's manifest (its path made plain: messages name it), or None."""
        if not self.object_set:
            return None
        p = Path(self.object_set).expanduser()
        return Path(os.path.normpath(p if p.is_absolute() else self.directory / p))

    @property
    def base_path(self) -> Path:
        p = Path(self.base).expanduser()
        return p if p.is_absolute() else self.directory / p

    def output_path(self) -> Path:
        if self.output_dir:
            p = Path(self.output_dir).expanduser()
            return p if p.is_absolute() else self.directory / p
        stem = Path(self.source_path).stem if self.source_path else "experiment"
        return Path.cwd() / "output" / stem

    def method(self, name: str) -> MethodConfig:
        return next(m for m in self.methods if m.name == name)

    def ray_engine_address(self) -> str:
        """The Ray address the trials run at (``engine: ray``), or empty (local workers)."""
        return self.ray_address if self.engine == "ray" else ""


@dataclass(frozen=True)
class TrialObject:
    """An object of an experiment, resolved: its ``name`` (in rows), whether it is a
    ``control``, its ``tags`` (the report groups by them), whether it has a natural rest,
    ``set_path``: the manifest a trial's scenario names (``object.set``) for an object set's
    mesh, None for a built-in object, and ``digest``: which version of the mesh entry it is
    (:func:`~gbh_drake.objects.sets.object_digest`; "" for a built-in object)."""

    name: str
    control: bool
    tags: tuple[str, ...]
    has_natural_rest: bool
    set_path: Path | None = None
    digest: str = ""


def experiment_objects(experiment: Experiment) -> list[TrialObject]:
    """The experiment's objects, resolved (:class:`TrialObject`), in order. A built-in object's
    tags are the built-in set's (``scenarios/object_sets/own.yaml``) unless the experiment's
    object set lists it with its own."""
    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.objects import make_object
    from gbh_drake.objects.catalog import natural_rest
    from gbh_drake.objects.sets import load_object_set, object_digest

    own = load_object_set(SCENARIOS_DIR / "object_sets" / "own.yaml")
    chosen = load_object_set(experiment.object_set_path) if experiment.object_set else None
    found = []
    for name in experiment.objects:
        object_set = chosen if chosen is not None and name in chosen.names else own
        entry = object_set.entry(name) if name in object_set.names else None
        builtin = entry.builtin if entry is not None else name
        tags = tuple(entry.tags) if entry is not None else ()
        if builtin:
            found.append(TrialObject(name, bool(make_object(builtin).is_control), tags,
                                     natural_rest(builtin) is not None))
        else:
            found.append(TrialObject(name, bool(entry.control), tags, entry.rest is not None,
                                     object_set.path, object_digest(object_set.object(name))))
    return found


def trial_seed(seed: int, object_name: str, trial: int, protocol: str = "stable") -> int:
    """The scenario seed of trial ``trial`` of ``object_name`` in ``protocol``: numpy's
    ``SeedSequence`` over (seed, a sha256 of the name, trial), and for any protocol but
    ``stable`` a sha256 of the protocol's name after them (so the ``stable`` seeds are those
    of the experiments before protocols existed), so it does not depend on Python's
    per-process string hash, on the method, nor on any other trial."""
    entropy = [int(seed), _name_key(object_name), int(trial)]
    if protocol != "stable":
        entropy.append(_name_key(protocol))
    state = np.random.SeedSequence(entropy).generate_state(1, dtype=np.uint32)
    return int(state[0])


def _name_key(name: str) -> int:
    return int.from_bytes(hashlib.sha256(name.encode()).digest()[:8], "big")


def load_experiment(filename: str | Path, *, overrides: str | list[str] = "") -> Experiment:
    """Loads and validates an experiment file; ``overrides`` is YAML applied over it (e.g.
    ``trials: 1``), or a list of such texts applied in order. The file and each override are
    layers of one loader, the scenario's (:func:`gbh_drake.yamlfiles.layers.load_layers`): a
    problem raises :class:`ExperimentError` naming the file (or ``--set`` text), the field and
    its line. An empty or comment-only file, or one that is only ``---``, is the defaults (which
    list no objects: refused at ``objects``)."""
    path = Path(filename)
    origin, text = file_layer(path, "experiment", ExperimentError)
    layers = [(origin, text)] + [(f"{path} (--set {t!r})", t)
                                 for _, t in override_layers(origin, overrides, ExperimentError)]
    experiment, trees = load_layers(Experiment, layers, Experiment(), what="experiment",
                                    error=ExperimentError, prepare=_overrides_as_text)
    experiment.source_path = str(path.resolve())
    if not experiment.name:
        experiment.name = path.stem
    experiment._layers = trees  # where each field is written (lines in errors; not a field)
    validate_experiment(experiment, origin)
    return experiment


def _overrides_as_text(root: yaml.Node) -> yaml.Node:
    """``root`` with every ``overrides`` mapping (``base_overrides``, ``methods[i].overrides``)
    turned into a string holding that mapping's YAML, tags kept (a new tree; ``root`` itself
    when there is none)."""
    if not isinstance(root, yaml.MappingNode):
        return root
    changed = False

    def as_text(node):
        nonlocal changed
        if isinstance(node, yaml.MappingNode | yaml.SequenceNode):
            changed = True
            body = yaml.serialize(node, width=1 << 16).strip()
            return yaml.ScalarNode("tag:yaml.org,2002:str", body, node.start_mark, node.end_mark)
        return node

    def method(node):
        if not isinstance(node, yaml.MappingNode):
            return node
        return yaml.MappingNode(node.tag, [(k, as_text(v) if k.value == "overrides" else v)
                                           for k, v in node.value],
                                node.start_mark, node.end_mark, node.flow_style)

    items = []
    for key, value in root.value:
        if key.value == "base_overrides":
            value = as_text(value)
        elif key.value == "methods" and isinstance(value, yaml.SequenceNode):
            value = yaml.SequenceNode(value.tag, [method(m) for m in value.value],
                                      value.start_mark, value.end_mark, value.flow_style)
        items.append((key, value))
    if not changed:
        return root
    return yaml.MappingNode(root.tag, items, root.start_mark, root.end_mark, root.flow_style)


def _layers(experiment: Experiment) -> Layers:
    """Where the fields of a loaded experiment were written (none for one built in code)."""
    return getattr(experiment, "_layers", None) or Layers()


def _line(experiment: Experiment, path: tuple) -> int | None:
    """The line where ``path`` (or the list holding it) was written last."""
    return _layers(experiment).wrote(path)[1]


def field_error(experiment: Experiment, field_path: str | tuple, message: str,
                origin: str = "") -> ExperimentError:
    """``message`` about the field at ``field_path`` (``methods[2].name``), naming the file (or
    ``--set`` text) and line where it is written (else ``origin``, else the experiment file)."""
    path = field_path if isinstance(field_path, tuple) else _parse_path(field_path)
    written, line = _layers(experiment).wrote(path)
    return ExperimentError(written or origin or experiment.source_path or "<experiment>",
                           format_path(path), line, message)


def _object_where(experiment: Experiment, object_set, j: int) -> str:
    """Where the experiment's object ``j`` was chosen: its entry of ``objects`` (``objects[1]
    'block' (line 7)``, naming the layer when another than the protocols' wrote it), or, with
    ``objects`` left out (every object of ``object_set``), the set's entry (``object_set
    set.yaml: objects[1] (block) (line 3)``)."""
    name, layers = experiment.objects[j], _layers(experiment)
    if layers.node(("objects", j)) is not None or object_set is None:
        written, line = layers.wrote(("objects", j))
        where = f"line {line}" if line else ""
        if written and written != layers.wrote(("protocols",))[0]:
            where = f"{written}, {where}"  # (another layer than the error's: --set)
        return f"objects[{j}] {name!r}" + (f" ({where})" if where else "")
    from gbh_drake.objects.sets import written_line

    index = object_set.names.index(name)
    line = written_line(object_set.root, ("objects", index))
    return f"object_set {object_set.given or object_set.path}: objects[{index}] ({name})" + (
        f" (line {line})" if line else "")


def validate_experiment(experiment: Experiment, origin: str) -> None:
    """Checks that the schema cannot express (the scenarios themselves are checked by
    :func:`method_scenarios`). Raises :class:`ExperimentError` naming the field and, for an
    experiment read by :func:`load_experiment`, the file (or ``--set`` text) and line where it
    is written."""
    from gbh_drake.experiment.engines import address_problem
    from gbh_drake.objects import list_objects

    def fail(field_path: str | tuple, message: str):
        raise field_error(experiment, field_path, message, origin)

    try:
        check_fields(experiment)
        check_fields(experiment.pose, ("pose",))
    except FieldError as e:
        fail(e.path, e.problem)
    object_set = None
    if experiment.object_set:
        from gbh_drake.objects.sets import ObjectSetError, load_object_set

        path = experiment.object_set_path
        if not path.is_file():
            fail("object_set", f"{'is a folder' if path.is_dir() else 'file not found'}: {path}")
        try:
            object_set = load_object_set(path)
        except ObjectSetError as e:
            fail("object_set", str(e))
        if not experiment.objects:  # every object of the set
            experiment.objects = list(object_set.names)
    if not experiment.objects:
        fail("objects", "list at least one object of the set (gbh objects list), or give an "
                        "object_set; the defaults (an empty file) have none")
    known = [*(object_set.names if object_set else []), *list_objects()]
    for i, name in enumerate(experiment.objects):
        if name not in known:
            fail(f"objects[{i}]", f"unknown object {name!r} (known: "
                                  f"{', '.join(dict.fromkeys(known))})")
    if object_set is not None:
        from gbh_drake.objects.mesh_io import quiet_mesh_warnings
        from gbh_drake.objects.sets import ObjectSetError

        for i, name in enumerate(experiment.objects):
            if name in object_set.names and not object_set.entry(name).builtin:
                try:  # found (fetched), a mesh, of a size and a mass that can be simulated
                    with quiet_mesh_warnings():  # (gbh objects list says them)
                        mesh = object_set.rest_mesh(name)
                        object_set.check_payload(name, object_set.mass(name, mesh))
                except ObjectSetError as e:  # on the field that chose it
                    written = _layers(experiment).node(("objects", i)) is not None
                    fail(f"objects[{i}]" if written else "object_set", str(e))
    if not experiment.methods:
        fail("methods", "give at least one method")
    names = [m.name for m in experiment.methods]
    for i, m in enumerate(experiment.methods):
        if not m.name or any(c in m.name for c in "/\\ \t"):
            fail(f"methods[{i}].name", f"a non-empty name without spaces or slashes, got "
                                       f"{m.name!r}")
        if names.index(m.name) != i:
            fail(f"methods[{i}].name", f"{m.name!r} is used twice")
        if len(m.name.encode()) > MAX_METHOD_NAME:  # file names are at most 255 bytes
            fail(f"methods[{i}].name", f"at most {MAX_METHOD_NAME} bytes (it names files: "
                                       f"scenarios/<name>.yaml, replays/...), got "
                                       f"{len(m.name.encode())}")
        if m.paper and m.paper not in PAPER_TABLE1:
            fail(f"methods[{i}].paper", f"one of {', '.join(PAPER_TABLE1)}, got {m.paper!r}")
    pose = experiment.pose
    for name in ("x", "y", "yaw_deg"):
        values = getattr(pose, name)
        if len(values) != 2 or values[0] > values[1]:
            fail(f"pose.{name}", f"needs [min, max], got {values}")
    if pose.rest != "stable":
        fail("pose.rest", f"is set by each protocol (protocols: [{pose.rest}]); remove it")
    if not experiment.protocols:
        fail("protocols", f"give at least one of {', '.join(PROTOCOLS)}")
    if "natural" in experiment.protocols:
        i = experiment.protocols.index("natural")
        if not pose.stable:
            fail("pose.stable", "false (as modelled) contradicts the natural protocol "
                                f"(protocols[{i}]), which sets each object in its declared "
                                "natural rest: remove pose.stable")
        objects = experiment_objects(experiment)
        missing = [(j, o.name) for j, o in enumerate(objects) if not o.has_natural_rest]
        if missing:
            j, name = missing[0]
            fail(f"protocols[{i}]", f"natural: {_object_where(experiment, object_set, j)} has "
                                    f"no natural rest declared in the object set "
                                    f"({counted(len(missing), 'object')} without: "
                                    + ", ".join(o for _, o in missing) + "); declare one (rest: "
                                    "in its object set's entry, or rest=... where a built-in "
                                    "object is registered) or drop the protocol")
    problem = address_problem(experiment.ray_address)
    if problem:
        fail("ray_address", problem)
    total = len(experiment.objects) * experiment.trials * len(experiment.methods) * \
        len(experiment.protocols)
    if total > MAX_TOTAL_TRIALS:
        fail("trials", f"{len(experiment.objects)} objects x {experiment.trials} trials x "
                       f"{len(experiment.methods)} methods x {len(experiment.protocols)} "
                       f"protocols are {total} trials; at most {MAX_TOTAL_TRIALS} in one "
                       "experiment (split it, or run fewer trials)")
    if not experiment.base:
        fail("base", "give the base scenario file (e.g. default.yaml)")
    if not experiment.base_path.is_file():
        from gbh_drake import SCENARIOS_DIR

        packaged = SCENARIOS_DIR / Path(experiment.base).name
        hint = f" (the packaged {packaged.name} is {packaged}: give that path, or copy it " \
               "beside the experiment file)" if packaged.is_file() else ""
        fail("base", f"scenario file not found: {experiment.base_path}{hint}")


def _parse_path(text: str) -> tuple:
    """``robot.q_home[3]`` -> ``("robot", "q_home", 3)`` (the inverse of ``format_path``)."""
    path: list = []
    for part in text.split(".") if text else []:
        name, *indices = part.replace("]", "").split("[")
        path += ([name] if name else []) + [int(i) for i in indices]
    return tuple(path)


def method_scenarios(experiment: Experiment) -> dict[str, Scenario]:
    """Each method's scenario: the base file, ``base_overrides``, the method's overrides (each
    loaded and checked as a ``gbh run --set`` text is), the experiment's pose distribution,
    validated with the first object. Fields the experiment sets for every trial
    (:data:`SET_BY_EXPERIMENT`) are refused in the overrides, and ``object.mesh`` in the base.
    Raises :class:`ExperimentError` naming the method, the field and its line."""
    origin = experiment.source_path or "<experiment>"
    _overrides_root(experiment, ("base_overrides",), experiment.base_overrides, origin)
    try:
        base = load_scenario(experiment.base_path, overrides=experiment.base_overrides)
    except ScenarioError as e:
        raise ExperimentError(origin, "base", None, str(e)) from e
    if base.object.mesh:
        line = line_of(_scenario_root(experiment.base_path), ("object", "mesh"))
        raise ExperimentError(origin, "base", _line(experiment, ("base",)),
                               f"{experiment.base_path}: object.mesh"
                               f"{f' (line {line})' if line else ''}: an experiment runs the "
                               "named objects of its objects list, not a mesh file; remove "
                               "object.mesh from the base scenario")
    scenarios = {}
    for i, method in enumerate(experiment.methods):
        at = ("methods", i, "overrides")
        layer, root, in_file = _overrides_root(experiment, at, method.overrides, origin)
        scenario = copy.deepcopy(base)
        if method.overrides.strip():
            try:
                scenario = apply_overrides(base, method.overrides, origin=layer)
            except ScenarioError as e:
                path = _parse_path(e.field)
                line = line_of(root, path) if in_file else None
                if line is None and node_at(root, path) is None:  # judged, not written here
                    field = f"methods[{i}] ({method.name}): {e.field}" if e.field else \
                        f"methods[{i}] ({method.name}).overrides"
                else:
                    field = format_path(at + path)
                    line = line or _line(experiment, at)
                raise ExperimentError(layer, field, line, e.problem) from None
        scenario.source_path = base.source_path
        scenario.output_dir = ""
        where = f"{origin}: methods[{i}] ({method.name})"
        first = experiment_objects(dataclasses.replace(experiment,
                                                       objects=experiment.objects[:1]))[0]
        for protocol in reversed(experiment.protocols):  # (the first one is kept)
            _set_trial(scenario, experiment, first, 0, protocol)
            try:
                validate_scenario(scenario, where)
            except ScenarioError as e:
                raise ExperimentError(e.origin, e.field, e.line, e.problem) from e
        if scenario.task != "pick":
            raise ExperimentError(layer, format_path(at + ("task",)),
                                   _line(experiment, at + ("task",)) or _line(experiment, at),
                                   f"an experiment picks (task: pick), got {scenario.task!r}")
        scenarios[method.name] = scenario
    return scenarios


def _overrides_root(experiment: Experiment, at: tuple, text: str, origin: str
                    ) -> tuple[str, yaml.Node | None, bool]:
    """(origin, node tree, written as a mapping in the file) of the overrides at ``at``;
    refuses (:class:`ExperimentError`) fields the experiment sets itself
    (:data:`SET_BY_EXPERIMENT`)."""
    layer = _layers(experiment).wrote(at)[0] or origin
    node = _layers(experiment).node(at)
    in_file = isinstance(node, yaml.MappingNode)
    root = node
    if not in_file:
        try:
            root = compose(text) if text.strip() else None
        except YamlTextError as e:  # the scenario loader says it again with its line
            raise ExperimentError(layer, format_path(at), _line(experiment, at),
                                   e.problem) from None
    for path, why in SET_BY_EXPERIMENT.items():
        value = node_at(root, path) if root is not None else None
        if value is None or value.tag == "tag:yaml.org,2002:null":
            continue
        if path == ("object", "mesh") and isinstance(value, yaml.ScalarNode) and \
                not value.value:
            continue  # mesh: '' clears a mesh
        line = line_of(root, path) if in_file else None
        raise ExperimentError(layer, format_path(at + path), line or _line(experiment, at),
                               f"{why}: the experiment sets it for every trial, so this "
                               "value would be replaced; remove it")
    return layer, root, in_file


def _scenario_root(path: Path) -> yaml.Node | None:
    """The node tree of a scenario file that has loaded (for a field's line), or None."""
    try:
        return compose(read_text(path))
    except YamlTextError:
        return None


def _set_trial(scenario: Scenario, experiment: Experiment, obj: TrialObject, trial: int,
               protocol: str = "stable") -> int:
    """Makes ``scenario`` the one of (object, trial, protocol): name (and its object set,
    relative to the base scenario's folder: the trial's text does not depend on where the
    experiment lives), random pose (its rest the protocol) and seed."""
    object_name = obj.name
    scenario.object.name = object_name
    scenario.object.set = _set_text(scenario, obj)
    scenario.object.mesh = ""
    scenario.object.random_pose = copy.deepcopy(experiment.pose)
    scenario.object.random_pose.rest = protocol
    scenario.seed = trial_seed(experiment.seed, object_name, trial, protocol)
    return scenario.seed


def _set_text(scenario: Scenario, obj: TrialObject) -> str:
    """The ``object.set`` of ``obj``'s trials of ``scenario``: its manifest relative to the
    scenario's folder, "" for a built-in object."""
    return "" if obj.set_path is None else os.path.relpath(obj.set_path, scenario.directory)


def trial_scenario_yaml(scenario: Scenario) -> str:
    """The YAML of a trial's scenario, as a user would write it: without the fields that say
    where files are (so the same trial has the same digest wherever the experiment lives),
    without ``object.pose`` when ``object.random_pose`` replaces it, without ``random_pose.rest``
    when it is ``stable`` and without an empty ``object.set`` (the defaults: the trials of
    built-in objects keep the text and digest they had before protocols and object sets
    existed)."""
    scenario = copy.copy(scenario)
    scenario.source_path = ""
    scenario.output_dir = ""
    text = yaml_dump_typed(scenario)
    if scenario.object.random_pose is None and scenario.object.set:
        return text
    root = compose_own(text)
    for key, value in root.value:
        if key.value == "object":
            random = scenario.object.random_pose is not None
            value.value = [(k, v) for k, v in value.value
                           if not (k.value == "pose" and random)
                           and not (k.value == "set" and v.value == "")]
            for k, v in value.value:
                if k.value == "random_pose" and isinstance(v, yaml.MappingNode):
                    v.value = [(a, b) for a, b in v.value
                               if not (a.value == "rest" and b.value == "stable")]
    return serialize(root, width=1 << 16)


def _with_seed(seed: int, text: str, new_seed: int) -> str | None:
    """``text``, a trial scenario's YAML whose top-level ``seed`` is ``seed``, with ``new_seed``
    instead; None unless the text has exactly one top-level ``seed`` line, with that value."""
    found = list(re.finditer(r"^seed: (\S*)$", text, flags=re.MULTILINE))
    if len(found) != 1 or found[0].group(1) != str(seed):
        return None
    return text[:found[0].start(1)] + str(new_seed) + text[found[0].end(1):]


def _with_object(text: str, name: str, set_text: str) -> str | None:
    """``text``, a trial scenario's YAML (:func:`trial_scenario_yaml`), with the object
    ``name`` of the set ``set_text`` (the scenario's ``object.set``, "" for a built-in object)
    instead of its own; None unless its object names a set exactly when ``set_text`` does."""
    root = compose_own(text)
    found = [v for k, v in root.value if k.value == "object"] \
        if isinstance(root, yaml.MappingNode) else []
    if len(found) != 1 or not isinstance(found[0], yaml.MappingNode):
        return None
    fields = {k.value: v for k, v in found[0].value}
    if not isinstance(fields.get("name"), yaml.ScalarNode) or \
            ("set" in fields) != bool(set_text):
        return None
    for key, value in (("name", name), ("set", set_text)):
        if key in fields:  # a plain node: the emitter quotes the new value where it must
            node = fields[key]
            node.value, node.style, node.tag = value, None, "tag:yaml.org,2002:str"
    return serialize(root, width=1 << 16)


def make_tasks(experiment: Experiment, *, commit: str = "",
               scenarios: dict[str, Scenario] | None = None) -> list[TrialTask]:
    """Every trial of ``experiment``, trial-major (all objects' first trials, in every protocol
    and by every method, come first, so an interrupted experiment has a little of everything).
    ``scenarios``: the methods' (default: :func:`method_scenarios`)."""
    scenarios = scenarios or method_scenarios(experiment)
    objects = {o.name: o for o in experiment_objects(experiment)}
    # The trials of one (method, protocol) differ only in their object and seed: the YAML is
    # dumped once (its first trial's), the object's name and set are set in its node tree for
    # the other objects and the seed line for the other trials (bench/bench_import.py).
    first: dict[tuple[str, str, str], tuple[int, str]] = {}
    dumped: dict[tuple[str, str], tuple[int, str]] = {}
    tasks = []
    for trial in range(experiment.trials):
        for protocol in experiment.protocols:
            for name in experiment.objects:
                for method in experiment.methods:
                    key = (method.name, name, protocol)
                    seed = trial_seed(experiment.seed, name, trial, protocol)
                    text = _with_seed(*first[key], seed) if key in first else None
                    if text is None and (method.name, protocol) in dumped:
                        dumped_seed, dumped_text = dumped[(method.name, protocol)]
                        text = _with_object(dumped_text, name,
                                            _set_text(scenarios[method.name], objects[name]))
                        text = None if text is None else _with_seed(dumped_seed, text, seed)
                    if text is None:
                        scenario = copy.deepcopy(scenarios[method.name])
                        _set_trial(scenario, experiment, objects[name], trial, protocol)
                        text = trial_scenario_yaml(scenario)
                        dumped.setdefault((method.name, protocol), (seed, text))
                    first.setdefault(key, (seed, text))
                    tasks.append(TrialTask(
                        experiment=experiment.name, object=name,
                        is_control=objects[name].control, object_tags=objects[name].tags,
                        method=method.name, trial=trial, seed=seed, scenario_yaml=text,
                        source_path=scenarios[method.name].source_path,
                        digest=hashlib.sha256(text.encode()).hexdigest(), commit=commit,
                        replays=experiment.replays, protocol=protocol,
                        object_digest=objects[name].digest))
    return tasks


def trial_scenario(experiment: Experiment | str | Path, object_name: str, method: str,
                   trial: int, protocol: str = "stable") -> Scenario:
    """The scenario of one trial of ``experiment`` (or of the experiment file at that path):
    ``method``'s scenario with the object, pose distribution and seed of (object, trial,
    protocol): the trial :func:`make_tasks` runs, to run again alone or to change (another
    ``grasp_method`` on the same pose). Raises :class:`ExperimentError` for an unknown method."""
    if not isinstance(experiment, Experiment):
        experiment = load_experiment(experiment)
    experiment = copy.copy(experiment)
    experiment.objects = [object_name]
    by_name = {m.name: m for m in experiment.methods}
    if method not in by_name:
        raise ExperimentError(experiment.source_path or "<experiment>", "methods", None,
                              f"no method "
                              f"{method!r} (known: {', '.join(by_name)})")
    experiment.methods = [by_name[method]]
    scenario = copy.deepcopy(method_scenarios(experiment)[method])
    _set_trial(scenario, experiment, experiment_objects(experiment)[0], trial, protocol)
    return scenario


def experiment_yaml(experiment: Experiment, folder: Path | None = None) -> str:
    """The resolved experiment as YAML (written into its folder; ``gbh report`` reads it),
    without where its trials ran (:data:`WHERE_FIELDS`: the same text whatever the engine).

    ``folder``: the folder the text is written into. Its ``base`` and ``object_set`` are then
    written relative to that folder and its ``output_dir`` is the folder itself (``.``), so
    ``gbh experiment FOLDER/experiment.yaml`` runs the same trials into the same folder (it
    resumes); the trials' scenarios, and so their digests, do not depend on it."""
    experiment = copy.copy(experiment)
    if folder is not None:
        experiment.base = _path_from(experiment.base_path, folder)
        if experiment.object_set:
            experiment.object_set = _path_from(experiment.object_set_path, folder)
        experiment.output_dir = "."
    experiment.source_path = ""
    root = compose_own(yaml_dump_typed(experiment))
    root.value = [(k, v) for k, v in root.value if k.value not in WHERE_FIELDS]
    return serialize(root)


def _path_from(path: Path, folder: Path) -> str:
    """``path`` relative to ``folder`` (posix separators), or absolute where it cannot be (on
    another drive)."""
    try:
        return Path(os.path.relpath(Path(path).resolve(), Path(folder).resolve())).as_posix()
    except ValueError:
        return Path(path).resolve().as_posix()


def git_commit(repo: Path | None = None) -> str:
    """``HEAD``'s hash, ``-dirty`` when tracked files differ from it; empty outside git (and for
    an installed wheel: its site-packages may sit in someone else's repository)."""
    from gbh_drake import IN_CHECKOUT, REPO_ROOT

    if repo is None and not IN_CHECKOUT:
        return ""
    repo = repo or REPO_ROOT
    try:
        head = subprocess.run(["git", "-C", str(repo), "rev-parse", "HEAD"], check=True,
                              capture_output=True, text=True, timeout=10).stdout.strip()
        status = subprocess.run(["git", "-C", str(repo), "status", "--porcelain",
                                 "--untracked-files=no"], check=True, capture_output=True,
                                text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""
    return head + ("-dirty" if status else "")
