"""Every field of a loaded :class:`~gbh_drake.scenario.Scenario` checked before anything is built.

:func:`check_scenario` raises :class:`~gbh_drake.core.ranges.FieldError` (the field's path and
what was expected) on the first field that cannot give a meaningful run:

1. every number anywhere (our dataclasses and Drake's config structs, poses and their
   distributions included) is finite;
2. each field is of its declared type (a scenario built in code may hold anything) and in its
   range: the rules our dataclasses declare beside their fields
   (:func:`gbh_drake.core.ranges.ranged`) and, for Drake's own config structs, the small table
   :data:`DRAKE_RULES`; then the bounds between fields (:class:`~gbh_drake.core.ranges.
   Relation`, declared beside the fields) and the other relations (each dataclass's own
   ``check_relations``, and the scenario's, :func:`check_relations`);
3. poses and distributions (:mod:`.poses`), the object (:mod:`.object_checks`), the model
   directives (:mod:`gbh_drake.modeling.directives`), the cameras (:mod:`.cameras`): what Drake
   would refuse deep inside the build (some with an assertion that kills the process) is
   checked here with the field named;
4. fields the run does not use are refused rather than ignored (a pose's ``base_frame``, the
   visualizer's ``lcm_bus``, a nonzero ``simulator_config.start_time``...);
5. the start state must allow a meaningful trial (:mod:`.start_state`).

:func:`rule_table` lists every range rule by section (docs/errors.md's table,
:func:`rules_markdown`, and the generated test cases use it); :func:`relation_table` every bound
between fields (:func:`relations_markdown`).
"""

import dataclasses
from pathlib import Path

import numpy as np
from pydrake.common import schema as drake_schema
from pydrake.systems.analysis import GetIntegrationSchemes

from gbh_drake.core.ranges import (
    FieldError,
    Fixed,
    NonNeg,
    OneOf,
    Path_,
    Pos,
    Range,
    Relation,
    Rule,
    check_bounds,
    check_finite_number,
    check_ranges,
    format_path,
    relations_of,
    rule_of,
)
from gbh_drake.method_spec import method_spec
from gbh_drake.modeling.directives import check_models
from gbh_drake.scenario.cameras import check_cameras
from gbh_drake.scenario.object_checks import check_object, object_model_name
from gbh_drake.scenario.poses import check_poses
from gbh_drake.scenario.schema import Scenario
from gbh_drake.scenario.start_state import check_start_state
from gbh_drake.yamlfiles.yaml_text import optional_of, struct_fields

#: The ranges and allowed values of Drake's own config structs (not ours: their fields carry no
#: rules), by section. Fields not listed are checked for finiteness only.
DRAKE_RULES: dict[tuple, dict[str, Rule]] = {
    ("plant_config",): {
        "time_step": Range(1e-5, 0.01, unit="s", note="gbh_drake needs a discrete plant; "
                                                        "smaller steps make a trial take hours"),
        "penetration_allowance": Pos(1.0, "m"),
        "stiction_tolerance": Pos(1.0, "m/s"),
        "contact_model": OneOf(("hydroelastic_with_fallback", "point"),
                               "'hydroelastic' alone fails: the arm's meshes have no "
                               "hydroelastic representation"),
        "discrete_contact_approximation": OneOf(("", "sap", "similar", "lagged"),
                                                "the fingers' coupler constraint needs a "
                                                "SAP-family solver; 'tamsi' cannot"),
        "sap_near_rigid_threshold": NonNeg(1000.0),
        "contact_surface_representation": OneOf(("polygon", "triangle")),
    },
    ("simulator_config",): {
        "integration_scheme": OneOf(tuple(GetIntegrationSchemes())),
        "max_step_size": Pos(10.0, "s"),
        "accuracy": Pos(1.0),
        "start_time": Fixed(0.0, "the trial's phases count from t = 0"),
        "target_realtime_rate": NonNeg(1000.0, note="0: as fast as possible"),
    },
    ("visualization",): {
        "lcm_bus": Fixed("default", "gbh_drake publishes on an in-memory bus only"),
        "publish_period": Range(1e-3, 10.0, unit="s"),
        "initial_proximity_alpha": NonNeg(1.0),
        "enable_meshcat_creation": Fixed(True, "a run always records its Meshcat replay"),
    },
}

#: The station's gravity is -z_W and its table is horizontal.
_UP = "the station's table is horizontal (gravity along -z): give [0, 0, 1]"


def check_scenario(scenario) -> None:
    """Raises :class:`FieldError` on the first field of ``scenario`` that cannot work (see the
    module docstring). Imports the object set and parses the directives (cached)."""
    check_finite(scenario)
    for at, config in ours(scenario):
        check_ranges(config, at)
    for section, rules in DRAKE_RULES.items():
        struct = getattr(scenario, section[0])
        for name, rule in rules.items():
            rule.check(section + (name,), getattr(struct, name))
    check_relations(scenario)
    check_poses(scenario)
    check_object(scenario)
    info = check_models(scenario.station_directives(), q_home=scenario.robot.q_home,
                        object_model=object_model_name(scenario))
    check_cameras(scenario, info)
    check_start_state(scenario, info)


def _is_ours(kind) -> bool:
    return dataclasses.is_dataclass(kind) and kind.__module__.startswith("gbh_drake.")


def ours(config, at: Path_ = ()):
    """(path, config) of ``config`` and of every dataclass of ours in it (parents first, in
    field order; an absent optional one, e.g. no ``object.random_pose``, is skipped)."""
    yield at, config
    for f in dataclasses.fields(config):
        value = getattr(config, f.name)
        if _is_ours(type(value)):
            yield from ours(value, at + (f.name,))


def rule_table(schema=Scenario, at: Path_ = ()) -> dict[Path_, dict[str, Rule]]:
    """Every range rule of ``schema`` by section: the rules declared on our dataclasses' fields
    and Drake's structs' :data:`DRAKE_RULES`, in field order."""
    table = {at: {f.name: rule_of(f) for f in dataclasses.fields(schema) if rule_of(f)}}
    for name, kind in struct_fields(schema).items():
        kind = optional_of(kind) or kind
        if at + (name,) in DRAKE_RULES:
            table[at + (name,)] = DRAKE_RULES[at + (name,)]
        elif _is_ours(kind):
            table.update(rule_table(kind, at + (name,)))
    return {section: rules for section, rules in table.items() if rules}


def rules_markdown(schema=Scenario) -> str:
    """The table of :func:`rule_table` of ``schema`` (the scenario's, or the experiment's) as
    Markdown (docs/errors.md includes both; a test keeps them equal)."""
    rows = ["| field | must be |", "|---|---|"]
    for section, rules in rule_table(schema).items():
        rows += [f"| `{format_path(section + (name,))}` | {rule.doc()} |"
                 for name, rule in rules.items()]
    return "\n".join(rows) + "\n"


def relation_table(schema=Scenario, at: Path_ = ()) -> list[tuple[Path_, str, Relation]]:
    """Every bound between fields declared in ``schema`` and its sections: (the path of the
    config that declares it, the field it is declared on, the relation), in field order."""
    table = [(at, f.name, r) for f in dataclasses.fields(schema) for r in relations_of(f)]
    for name, kind in struct_fields(schema).items():
        kind = optional_of(kind) or kind
        if _is_ours(kind):
            table += relation_table(kind, at + (name,))
    return table


def relations_markdown(schema=Scenario) -> str:
    """The table of :func:`relation_table` of ``schema`` as Markdown (docs/errors.md includes
    it; a test keeps them equal)."""
    rows = ["| field | must be | why |", "|---|---|---|"]
    rows += [f"| `{format_path(at + relation.lhs(name))}` | {relation.doc(at)} | {relation.why} |"
             for at, name, relation in relation_table(schema)]
    return "\n".join(rows) + "\n"


def iter_numbers(value, path: Path_ = ()):
    """(path, number) for every number in ``value``: dataclasses, Drake structs (with YAML
    paths: a ``schema.Rotation``'s ``value`` is skipped as YAML does), lists, dicts, arrays."""
    if isinstance(value, bool) or value is None or isinstance(value, str | Path):
        return
    if isinstance(value, int | float | np.number):
        yield path, value
    elif isinstance(value, np.ndarray):
        for i, v in enumerate(np.ravel(value)):
            yield path + (i,), v
    elif isinstance(value, list | tuple):
        for i, v in enumerate(value):
            yield from iter_numbers(v, path + (i,))
    elif isinstance(value, dict):
        for k, v in value.items():
            yield from iter_numbers(v, path + (str(k),))
    elif isinstance(value, drake_schema.Rotation):
        yield from iter_numbers(value.value, path)
    else:
        fields = struct_fields(type(value))
        if fields is None:
            return
        for name in fields:
            yield from iter_numbers(getattr(value, name, None), path + (name,))


def check_finite(scenario) -> None:
    for path, v in iter_numbers(scenario):
        check_finite_number(path, v)


def check_relations(scenario) -> None:
    """Fields that depend on each other: the bounds declared beside the fields (the scenario's
    across sections, then each section's), the scenario's other rules across sections, then
    each of our dataclasses' own ``check_relations``."""
    s = scenario
    for at, config in ours(s):
        check_bounds(config, at)
    spec = method_spec(s.grasp_method)
    needs = spec.gripper if spec.needs_gripper else None
    if needs and s.gripper != needs:
        raise FieldError(("robot", "gripper"), f"{s.robot.gripper}: grasp_method "
                         f"{s.grasp_method} needs the {needs} gripper (give {needs} or auto)")
    for section in ("gbh", "antipodal"):
        n = np.asarray(getattr(s, section).ground_normal, float)
        if not (np.linalg.norm(n) > 0 and np.allclose(n / np.linalg.norm(n), [0, 0, 1])):
            raise FieldError((section, "ground_normal"), f"{_UP}; got {list(n)}")
    for at, config in ours(s):
        relations = getattr(config, "check_relations", None)
        if relations is not None:
            relations(at)
    if "\0" in s.source_path:
        raise FieldError(("source_path",), "holds a NUL character")
    if s.output_dir:
        out = s.resolve(s.output_dir)
        try:
            is_file = out.exists() and not out.is_dir()
        except OSError:  # a name too long: gbh_drake.outputs refuses the folder, naming it
            is_file = False
        if is_file:
            raise FieldError(("output_dir",), f"{out} is a file, not a folder")
