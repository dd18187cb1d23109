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
import os
from pathlib import Path

from pydrake.common.yaml import yaml_dump_typed, yaml_load_typed

from gbh_drake.core.params import PRESETS
from gbh_drake.core.ranges import FieldError, check_ranges, format_path, shown
from gbh_drake.scenario.checks import check_scenario, ours
from gbh_drake.scenario.schema import ObjectConfig, Scenario
from gbh_drake.yamlfiles.layers import (
    LayerError,
    Layers,
    file_layer,
    load_layers,
    override_layers,
    written,
)


class ScenarioError(LayerError):
    """A scenario file is invalid. The message is ``<origin>: <field> (line N): <problem>``
    (``<origin>: <problem>`` for the file as a whole; the line only where the field is written).

    ``origin``: the file, or ``<file> (overrides)``; ``field``: the field's path (``""`` for the
    file as a whole); ``line``: 1-based or None; ``problem``: what is wrong and what was
    expected."""


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
    origin, text = file_layer(path, "scenario", ScenarioError)
    return _load_layers([(origin, text), *override_layers(origin, overrides, ScenarioError)],
                        Scenario(), origin, str(path.resolve()), overrides_from=1)


def apply_overrides(scenario: Scenario, overrides: Overrides,
                    origin: str = "<in memory>") -> Scenario:
    """A copy of ``scenario`` with ``overrides`` (YAML text, or several applied in order) on
    top, checked as a loaded file is; raises :class:`ScenarioError` naming ``origin``."""
    require_scenario(scenario, "apply_overrides", check_fields=False)
    return _load_layers(override_layers(origin, overrides, ScenarioError), scenario, origin,
                        scenario.source_path, overrides_from=0)


def _load_layers(layers: list[tuple[str, str]], start: Scenario, origin: str,
                 source_path: str, *, overrides_from: int) -> Scenario:
    """``start`` updated by each (origin, YAML text) layer in turn (from ``overrides_from`` on,
    overrides: their relative paths are the current folder's), then checked."""
    scenario, trees = load_layers(Scenario, layers, start, what="scenario",
                                  error=ScenarioError, overrides_from=overrides_from,
                                  reload=_with_preset)
    scenario.source_path = source_path
    try:
        _check_layers(trees, scenario)
        check_scenario(scenario)
    except FieldError as e:
        raise trees.locate(e, origin, ScenarioError) from None
    return scenario


def _with_preset(scenario: Scenario, defaults: Scenario, text: str) -> Scenario:
    """A layer that names a GbH preset goes over the preset's defaults (then its own fields)."""
    if scenario.gbh.preset != defaults.gbh.preset and scenario.gbh.preset in PRESETS:
        defaults = copy.deepcopy(defaults)
        defaults.gbh = defaults.gbh.with_preset(scenario.gbh.preset)
        scenario = yaml_load_typed(schema=Scenario, data=text, defaults=defaults)
    return scenario


def _check_layers(trees: Layers, scenario: Scenario) -> None:
    """Fields one of which would be ignored: a named object and a mesh, a pose and a random
    pose; and ``source_path``, which the loader sets.

    Between layers (the file, then each override) the later of ``object.pose`` and
    ``object.random_pose`` wins: ``--set "{object: {random_pose: {}}}"`` draws a random pose for
    a file that gives a pose (its pose goes back to the default), and a pose given over a file's
    random pose clears it. Both in one layer are refused unless the pose is the default one (as
    in a resolved ``scenario.yaml``, which writes every field)."""
    last = ""
    for _, root in trees.roots:
        wrote = [k for k in ("pose", "random_pose") if written(root, ("object", k))]
        if wrote:  # both in one layer: judged below (a default pose beside it is allowed)
            last = wrote[0] if len(wrote) == 1 else "both"
    if last == "random_pose":
        scenario.object.pose = ObjectConfig().pose
    elif last == "pose":
        scenario.object.random_pose = None
    for _, root in trees.roots:
        if written(root, ("source_path",), nonempty=True):
            raise FieldError(("source_path",), "is set by the loader to the file itself; remove "
                                               "it")
        if written(root, ("object", "name"), nonempty=True) and \
                written(root, ("object", "mesh"), nonempty=True):
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
