"""Loading scenario files: one YAML file describes one run (robot, table, object, cameras,
simulation).

The schema is the :class:`~gbh_drake.scenario.schema.Scenario` dataclass.
:func:`load_scenario` loads a file, then each ``--set`` override on top of it, with Drake's
``yaml_load_typed`` (typos fail loudly) and checks every field
(:mod:`gbh_drake.scenario.checks`) before anything is built. Any problem raises one
:class:`ScenarioError` that names the file (``<file> (overrides)`` for an override), the field,
its line when it is written there, and what was expected; docs/errors.md lists the checks and
limits. An empty, whitespace-only or comment-only file is the default scenario.

An override is YAML text (a ``str``, or ``bytes`` decoded as a file is: UTF-8, a byte-order
mark dropped, UTF-16 and invalid bytes named), or a list of them. A relative path in an
override (``output_dir``, ``object.mesh``: the fields whose rule is
:class:`~gbh_drake.core.ranges.FilePath`) is relative to the current folder, and made absolute
as it is loaded; a relative path in the file is relative to the file's folder.

Drake's own config structs are reused where they exist (``MultibodyPlantConfig``,
``SimulatorConfig``, ``VisualizationConfig``, ``CameraConfig``, ``schema.Transform`` for poses,
which also takes distributions such as ``!UniformVector``, sampled from the scenario's ``seed``).
:func:`dump_resolved` writes the loaded scenario back as YAML that reloads to the same run.
"""


import copy
import functools
import os
from pathlib import Path

import yaml
from pydrake.common.yaml import yaml_dump_typed, yaml_load_typed

from gbh_drake.core.params import PRESETS
from gbh_drake.core.ranges import FieldError, FilePath, check_ranges, format_path, shown
from gbh_drake.scenario.checks import check_scenario, ours, rule_table
from gbh_drake.scenario.schema import ObjectConfig, Scenario
from gbh_drake.scenario.yaml_text import (
    YamlFieldError,
    YamlTextError,
    check_document,
    compose,
    decode,
    line_of,
    locate_load_error,
    node_at,
    read_text,
)


class ScenarioError(ValueError):
    """A scenario file is invalid. The message is ``<origin>: <field> (line N): <problem>``
    (``<origin>: <problem>`` for the file as a whole; the line only where the field is written).

    ``origin``: the file, or ``<file> (overrides)``; ``field``: the field's path (``""`` for the
    file as a whole); ``line``: 1-based or None; ``problem``: what is wrong and what was
    expected."""

    def __init__(self, origin: str, field: str, line: int | None, problem: str,
                 column: int | None = None):
        if field:
            where = f"{field}{f' (line {line})' if line else ''}: "
        else:
            where = f"line {line}{f', column {column}' if column else ''}: " if line else ""
        super().__init__(f"{origin}: {where}{problem}")
        self.origin = origin
        self.field = field
        self.line = line
        self.column = column
        self.problem = problem

    def __reduce__(self):  # picklable (e.g. from a worker process) with its parts
        return type(self), (self.origin, self.field, self.line, self.problem, self.column)


#: An override: YAML text, or bytes decoded as a file is.
Override = str | bytes
#: ``overrides`` of the loading functions: one override, or several applied in order.
Overrides = Override | list[Override] | tuple[Override, ...]


def load_scenario(filename: str | os.PathLike, *, overrides: Overrides = "") -> Scenario:
    """Loads and checks a scenario file; ``overrides`` (YAML text, or several applied in order)
    go on top of it. Raises :class:`ScenarioError` (see the module docstring)."""
    if not isinstance(filename, str | os.PathLike):
        raise ScenarioError("load_scenario()", "filename", None, "expected a scenario file's path "
                            f"(a str or Path), got {shown(filename)}")
    path = Path(filename)
    origin = str(path)
    try:
        text = read_text(path)
    except YamlTextError as e:
        raise ScenarioError(origin, "", e.line, e.problem, e.column) from None
    return _load_layers([(origin, text, False), *_override_layers(origin, overrides)],
                        Scenario(), origin, str(path.resolve()))


def apply_overrides(scenario: Scenario, overrides: Overrides,
                    origin: str = "<in memory>") -> Scenario:
    """A copy of ``scenario`` with ``overrides`` (YAML text, or several applied in order) on
    top, checked as a loaded file is; raises :class:`ScenarioError` naming ``origin``."""
    require_scenario(scenario, "apply_overrides", check_fields=False)
    return _load_layers(_override_layers(origin, overrides), scenario, origin,
                        scenario.source_path)


def _override_layers(origin: str, overrides: Overrides) -> list[tuple[str, str, bool]]:
    """(origin, text, True) of each non-blank override, labelled for messages; bytes are
    decoded as a file is. Raises :class:`ScenarioError` for what is not YAML text."""
    several = isinstance(overrides, list | tuple)
    items = list(overrides) if several else [overrides]
    for i, item in enumerate(items):
        if not isinstance(item, str | bytes):
            where = f"overrides[{i}]" if several else "overrides"
            raise ScenarioError(f"{origin} ({where})", "", None, "expected YAML text (a str, or "
                                "bytes in UTF-8) or a list of them, got " + shown(item))
    texts = [t for t in items if t.strip()]

    def label(i: int) -> str:
        return f"{origin} ({'overrides' if len(texts) == 1 else f'overrides {i + 1} of {len(texts)}'})"

    layers = []
    for i, text in enumerate(texts):
        if isinstance(text, bytes):
            try:
                text = decode(text)
            except YamlTextError as e:
                raise ScenarioError(label(i), "", e.line, e.problem, e.column) from None
        layers.append((label(i), text, True))
    return layers


def _load_layers(layers: list[tuple[str, str, bool]], start: Scenario, origin: str,
                 source_path: str) -> Scenario:
    """``start`` updated by each (origin, YAML text, is an override) layer in turn, then
    checked. A relative path an override writes is made absolute against the current folder."""
    scenario, roots = copy.deepcopy(start), []
    for layer_origin, layer_text, is_override in layers:
        scenario, root = _load_layer(layer_text, layer_origin, scenario)
        roots.append((layer_origin, root))
        if is_override:
            absolute_paths(scenario, root, path_fields(type(scenario)))
    scenario.source_path = source_path
    try:
        _check_layers(roots, scenario)
        check_scenario(scenario)
    except FieldError as e:
        raise _located(e, roots, origin) from None
    return scenario


def _load_layer(text: str, origin: str, defaults: Scenario) -> tuple[Scenario, yaml.Node | None]:
    """``defaults`` updated by one YAML document, and the document's node tree."""
    try:
        if "\0" in text:
            decode(text.encode("utf-8", "surrogatepass"))  # names the NUL's line and column
        root = compose(text)
    except YamlTextError as e:
        raise ScenarioError(origin, "", e.line, e.problem, e.column) from None
    if root is None:  # empty, whitespace or comments only: nothing changes
        return copy.deepcopy(defaults), None
    try:
        check_document(root, Scenario)
    except YamlFieldError as e:
        raise ScenarioError(origin, format_path(e.path), e.line, e.problem) from None
    try:
        scenario = yaml_load_typed(schema=Scenario, data=text, defaults=defaults)
        if scenario.gbh.preset != defaults.gbh.preset and \
                scenario.gbh.preset in PRESETS:  # the preset's defaults, then this layer's fields
            defaults = copy.deepcopy(defaults)
            defaults.gbh = defaults.gbh.with_preset(scenario.gbh.preset)
            scenario = yaml_load_typed(schema=Scenario, data=text, defaults=defaults)
    except Exception as e:  # noqa: BLE001  (Drake raises RuntimeError, ValueError, TypeError...)
        found = locate_load_error(root, Scenario, e)
        raise ScenarioError(origin, format_path(found.path), found.line, found.problem) from None
    return scenario, root


@functools.cache
def path_fields(schema) -> tuple[tuple, ...]:
    """The paths of ``schema``'s fields whose rule is :class:`FilePath`."""
    return tuple(section + (name,) for section, rules in rule_table(schema).items()
                 for name, rule in rules.items() if isinstance(rule, FilePath))


def absolute_paths(config, root: yaml.Node | None, paths) -> None:
    """Each field of ``paths`` (tuples of names) that the YAML document ``root`` writes, when it
    is a relative path, made absolute against the current folder (a path given in an
    override, e.g. ``--set "output_dir: out"``, is where the user is, not where the file is)."""
    for path in paths:
        if not _written(root, path, nonempty=True):
            continue
        *parents, name = path
        holder = config
        for part in parents:
            holder = getattr(holder, part, None)
        value = getattr(holder, name, None)
        if isinstance(value, str) and "\0" not in value:
            p = Path(value).expanduser()
            if not p.is_absolute():
                setattr(holder, name, str(Path.cwd() / p))


def _check_layers(roots: list[tuple[str, yaml.Node | None]], scenario: Scenario) -> None:
    """Fields one of which would be ignored: a named object and a mesh, a pose and a random
    pose; and ``source_path``, which the loader sets.

    Between layers (the file, then each override) the later of ``object.pose`` and
    ``object.random_pose`` wins: ``--set "{object: {random_pose: {}}}"`` draws a random pose for
    a file that gives a pose (its pose goes back to the default), and a pose given over a file's
    random pose clears it. Both in one layer are refused unless the pose is the default one (as
    in a resolved ``scenario.yaml``, which writes every field)."""
    last = ""
    for _, root in roots:
        wrote = [k for k in ("pose", "random_pose") if _written(root, ("object", k))]
        if wrote:  # both in one layer: judged below (a default pose beside it is allowed)
            last = wrote[0] if len(wrote) == 1 else "both"
    if last == "random_pose":
        scenario.object.pose = ObjectConfig().pose
    elif last == "pose":
        scenario.object.random_pose = None
    for _, root in roots:
        if _written(root, ("source_path",), nonempty=True):
            raise FieldError(("source_path",), "is set by the loader to the file itself; remove "
                                               "it")
        if _written(root, ("object", "name"), nonempty=True) and \
                _written(root, ("object", "mesh"), nonempty=True):
            raise FieldError(("object", "mesh"), _BOTH_OBJECTS)
    obj, default = scenario.object, ObjectConfig()
    if obj.mesh and obj.name not in ("", default.name):
        raise FieldError(("object", "mesh"), _BOTH_OBJECTS)
    if obj.random_pose is not None and _pose_text(obj.pose) != _pose_text(default.pose):
        raise FieldError(("object", "random_pose"), _BOTH_POSES)


_BOTH_POSES = ("give object.pose or object.random_pose, not both (object.pose would be "
               "ignored; a later override of one replaces the other)")
_BOTH_OBJECTS = ("give object.name or object.mesh, not both (object.name would be ignored; "
                 "name: '' clears it)")


def _pose_text(pose) -> str:
    return yaml_dump_typed(ObjectConfig(pose=pose))


def _written(root, path, *, nonempty: bool = False) -> bool:
    node = node_at(root, path)
    if node is None or node.tag == "tag:yaml.org,2002:null":
        return False
    return not (nonempty and isinstance(node, yaml.ScalarNode) and node.value == "")


def _located(error: FieldError, roots, origin: str) -> ScenarioError:
    """``error`` with the origin (file or overrides) and line where its field was written last.
    For a bound between two fields (``error.other``), the one written last is named: a field
    left at its default is not where the user can see the problem."""
    for layer_origin, root in reversed(roots):
        for e in (error, error.other) if error.other is not None else (error,):
            path = tuple(e.path)
            for end in range(len(path), 0, -1):  # the field, else its list (q_home for q_home[3])
                line = line_of(root, path[:end])
                if line is not None and (end == len(path) or isinstance(path[end], int)):
                    return ScenarioError(layer_origin, format_path(path), line, e.problem)
    return ScenarioError(origin, format_path(error.path), None, error.problem)


def validate_scenario(scenario: Scenario, origin: str) -> None:
    """Checks a scenario built in code; raises :class:`ScenarioError` naming ``origin``."""
    require_scenario(scenario, "validate_scenario", check_fields=False)
    try:
        check_scenario(scenario)
    except FieldError as e:
        raise ScenarioError(origin, format_path(e.path), None, e.problem) from None


def require_scenario(scenario, function: str, *, check_fields: bool = True) -> Scenario:
    """``scenario`` when it is a :class:`Scenario` whose fields hold values of their types and
    within their ranges (``check_fields``; the relations between fields, the object, the
    models and the start state are :func:`validate_scenario`'s); else raises
    :class:`ScenarioError` naming ``function``'s argument or the field. For the public
    functions that take a scenario built in code (``build_trial``, ``make_station``...): a
    wrong value is named at the call, not deep inside the build."""
    if not isinstance(scenario, Scenario):
        raise ScenarioError(f"{function}()", "scenario", None, "expected a Scenario (of a file: "
                            f"gbh_drake.scenario.load_scenario(path)), got {shown(scenario)}")
    if check_fields:
        try:
            for at, config in ours(scenario):
                check_ranges(config, at)
        except FieldError as e:
            raise ScenarioError(scenario.source_path or "<in memory>", format_path(e.path), None,
                                e.problem) from None
    return scenario


def dump_resolved(scenario: Scenario) -> str:
    """``scenario`` as YAML that ``gbh run`` reloads to the same run from anywhere: every field
    written, the mesh path made absolute, fields the run does not use cleared (``object.name``
    beside a mesh, ``object.pose`` beside a random pose, ``source_path``), ``output_dir``
    emptied (a rerun writes to ``output/<file stem>``, not over the folder the file was saved
    in)."""
    require_scenario(scenario, "dump_resolved", check_fields=False)
    resolved = copy.deepcopy(scenario)
    if resolved.object.mesh:
        resolved.object.mesh = str(scenario.resolve(scenario.object.mesh))
        resolved.object.name = ""
    if resolved.object.random_pose is not None:
        resolved.object.pose = ObjectConfig().pose  # not used: the random pose is
    resolved.output_dir = ""
    resolved.source_path = ""
    header = [
        "# The resolved scenario of a gbh run (its file plus --set overrides), every field",
        f"# written out. Source: {scenario.source_path or '<in memory>'}; outputs were in",
        f"# {scenario.output_path()}. `gbh run <this file>` repeats the run (output_dir is",
        "# empty here so that a rerun does not overwrite that folder).",
    ]
    return "\n".join(header) + "\n" + yaml_dump_typed(resolved)
