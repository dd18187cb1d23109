"""Loading scenario files: one YAML file describes one run (robot, table, object, cameras,
simulation).

The schema is the :class:`~gbh_drake.scenario.schema.Scenario` dataclass.
:func:`load_scenario` loads a file, then each ``--set`` override on top of it, with Drake's
``yaml_load_typed`` (typos fail loudly) and checks every field
(:mod:`gbh_drake.scenario.checks`) before anything is built. Any problem raises one
:class:`ScenarioError` that names the file (``<file> (overrides)`` for an override), the field,
its line when it is written there, and what was expected; docs/errors.md lists the checks and
limits. An empty, whitespace-only or comment-only file is the default scenario.

Drake's own config structs are reused where they exist (``MultibodyPlantConfig``,
``SimulatorConfig``, ``VisualizationConfig``, ``CameraConfig``, ``schema.Transform`` for poses,
which also takes distributions such as ``!UniformVector``, sampled from the scenario's ``seed``).
:func:`dump_resolved` writes the loaded scenario back as YAML that reloads to the same run.
"""


import copy
from pathlib import Path

from pydrake.common.yaml import yaml_dump_typed, yaml_load_typed

from gbh_drake.core.params import PRESETS
from gbh_drake.core.ranges import FieldError, format_path
from gbh_drake.scenario.checks import check_scenario
from gbh_drake.scenario.schema import ObjectConfig, Scenario
from gbh_drake.yamlfiles.layers import LayerError, Layers, file_layer, load_layers, override_layers, written


class ScenarioError(LayerError):
    """A scenario file is invalid. The message is ``<origin>: <field> (line N): <problem>``
    (``<origin>: <problem>`` for the file as a whole; the line only where the field is written).

    ``origin``: the file, or ``<file> (overrides)``; ``field``: the field's path (``""`` for the
    file as a whole); ``line``: 1-based or None; ``problem``: what is wrong and what was
    expected."""


def load_scenario(filename: str | Path, *, overrides: str | list[str] | tuple[str, ...] = ""
                  ) -> Scenario:
    """Loads and checks a scenario file; ``overrides`` (YAML text, or several applied in order)
    go on top of it. Raises :class:`ScenarioError` (see the module docstring)."""
    path = Path(filename)
    origin, text = file_layer(path, "scenario", ScenarioError)
    return _load_layers([(origin, text), *override_layers(origin, overrides)], Scenario(),
                        origin, str(path.resolve()))


def apply_overrides(scenario: Scenario, overrides: str | list[str] | tuple[str, ...],
                    origin: str = "<in memory>") -> Scenario:
    """A copy of ``scenario`` with ``overrides`` (YAML text, or several applied in order) on
    top, checked as a loaded file is; raises :class:`ScenarioError` naming ``origin``."""
    return _load_layers(override_layers(origin, overrides), scenario, origin,
                        scenario.source_path)


def _load_layers(layers: list[tuple[str, str]], start: Scenario, origin: str,
                 source_path: str) -> Scenario:
    """``start`` updated by each (origin, YAML text) layer in turn, then checked."""
    scenario, trees = load_layers(Scenario, layers, start, what="scenario",
                                  error=ScenarioError, reload=_with_preset)
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
    try:
        check_scenario(scenario)
    except FieldError as e:
        raise ScenarioError(origin, format_path(e.path), None, e.problem) from None


def dump_resolved(scenario: Scenario) -> str:
    """``scenario`` as YAML that ``gbh run`` reloads to the same run from anywhere: every field
    written, the mesh path made absolute, fields the run does not use cleared (``object.name``
    beside a mesh, ``object.pose`` beside a random pose, ``source_path``), ``output_dir``
    emptied (a rerun writes to ``output/<file stem>``, not over the folder the file was saved
    in)."""
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
