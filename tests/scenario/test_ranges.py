"""One home per range: each field's rule is declared beside it, as field metadata, and the
classes' own checks, the scenario loader and docs/errors.md all read it from there."""

import dataclasses
import math
import typing

import pytest

from gbh_drake.core.params import AntipodalParams, GbhParams
from gbh_drake.core.ranges import FieldError, check_fields, rule_of
from gbh_drake.core.results import GbhInputError
from gbh_drake.perception.config import ScanConfig
from gbh_drake.scenario import RandomRestingPose, Scenario, ScenarioError, load_scenario, validate_scenario
from gbh_drake.scenario.checks import DRAKE_RULES, ours, rule_table


def _full_scenario() -> Scenario:
    """The default scenario with its optional parts given (a random pose)."""
    scenario = Scenario()
    scenario.object.random_pose = RandomRestingPose()
    return scenario


def test_every_numeric_field_of_ours_has_a_rule():
    classes = {type(config) for _, config in ours(_full_scenario())}
    assert {GbhParams, AntipodalParams, ScanConfig, Scenario} <= classes
    missing = []
    for cls in classes:
        for f in dataclasses.fields(cls):
            numeric = f.type in (int, float) or typing.get_origin(f.type) is list and \
                typing.get_args(f.type) == (float,)
            if numeric and rule_of(f) is None:
                missing.append(f"{cls.__name__}.{f.name}")
    assert missing == []


def test_the_rule_table_is_the_fields_metadata_plus_drakes_structs():
    table = rule_table()
    for section, rules in table.items():
        if section in DRAKE_RULES:
            assert rules is DRAKE_RULES[section]
            continue
        obj = _full_scenario()
        for part in section:
            obj = getattr(obj, part)
        declared = {f.name: rule_of(f) for f in dataclasses.fields(obj) if rule_of(f)}
        assert rules == declared, section


@pytest.mark.parametrize(("value", "problem"), [
    (math.nan, "must be a finite number, got nan"),
    (1.0, "must be in [-0.05, 0.05] m, got 1 m"),
])
def test_params_check_and_the_yaml_refuse_alike(tmp_path, value, problem):
    with pytest.raises(GbhInputError) as own:
        GbhParams(d2=value).check()
    assert str(own.value) == f"GbhParams.d2: {problem}"
    path = tmp_path / "bad.yaml"
    path.write_text(f"gbh:\n  d2: {'.nan' if math.isnan(value) else value}\n")
    with pytest.raises(ScenarioError) as loaded:
        load_scenario(path)
    assert (loaded.value.field, loaded.value.line, loaded.value.problem) == ("gbh.d2", 2, problem)


def test_a_relation_is_refused_by_validate_and_the_yaml_with_the_field_named(tmp_path):
    with pytest.raises(ValueError, match=r"^ScanConfig\.sdf_trunc: must be >= 2 x voxel_size "
                                         r"\(0\.008 m\), got 0\.005 m: "):
        ScanConfig(voxel_size=0.004, sdf_trunc=0.005).validate()
    with pytest.raises(ValueError, match=r"^ScanConfig\.distance_max: must be >= distance "):
        ScanConfig(distance_max=0.3).validate()
    path = tmp_path / "bad.yaml"
    path.write_text("scan: {distance_max: 0.3}\n")
    with pytest.raises(ScenarioError) as loaded:
        load_scenario(path)
    assert loaded.value.field == "scan.distance_max"
    assert loaded.value.problem.startswith("must be >= scan.distance (0.5 m), got 0.3 m")


def test_own_checks_raise_field_errors_inside():
    """The public checks are made from the same FieldError the loader reports."""
    with pytest.raises(FieldError) as info:
        check_fields(AntipodalParams(min_contact_depth=0.05), ("antipodal",))
    assert info.value.path == ("antipodal", "min_contact_depth")
    assert info.value.problem == ("must be <= antipodal.contact_depth (0.015 m), got 0.05 m: the "
                                  "hand backs off from contact_depth to it")
    assert info.value.other.path == ("antipodal", "contact_depth")  # the same, said of the other
    assert info.value.other.problem.startswith("must be >= antipodal.min_contact_depth (0.05 m), "
                                               "got 0.015 m")


@pytest.mark.parametrize(
    "bad", [{"n_points": 0}, {"ground_normal": [0.0, 0.0]}, {"ground_normal": [0.0, 0.0, 0.0]},
            {"p_theta": 1.5}, {"n_rays_per_plane": 2}, {"p_sweep": 0},
            {"cage_clearance": -0.001}, {"min_miss_resultant": 1.5},
            {"sweep_margin_spacings": -1.0}]
)
def test_out_of_range_params_name_the_field(bad):
    with pytest.raises(GbhInputError, match=next(iter(bad))):
        GbhParams(**bad).check()


# ---- a scenario or a config built in code: every field of its declared type --------------------


@pytest.mark.parametrize(("set_field", "field", "problem"), [
    (lambda s: setattr(s, "scan_target", 0.5), "scan_target",
     "expected a list of 3 coordinates (x, y, z in m), got 0.5 (a float)"),
    (lambda s: setattr(s, "seed", 3.0), "seed", "expected an integer, got 3.0 (a float)"),
    (lambda s: setattr(s, "seed", "3"), "seed", "expected an integer, got '3' (a str)"),
    (lambda s: setattr(s, "object", "mug_classic"), "object",
     "expected an ObjectConfig, got 'mug_classic' (a str)"),
    (lambda s: setattr(s, "gbh", GbhParams), "gbh",
     "expected a GbhParams, got the class GbhParams (not an instance of it)"),
    (lambda s: setattr(s.object, "name", 5), "object.name", "expected a string, got 5 (an int)"),
    (lambda s: setattr(s, "output_dir", __import__("pathlib").Path("out")), "output_dir",
     "expected a path as text (a str; str(path) of a Path), got PosixPath('out')"),
    (lambda s: setattr(s.robot, "gripper_open", "no"), "robot.gripper_open",
     "expected true or false, got 'no' (a str)"),
    (lambda s: setattr(s.gbh, "approach_rotations_deg", 20.0), "gbh.approach_rotations_deg",
     "expected a list of angles (deg), each in [-90, 90] deg, got 20.0 (a float)"),
    (lambda s: setattr(s.pick, "set_down", "no"), "pick.set_down",
     "expected true or false, got 'no' (a str)"),
    (lambda s: setattr(s, "cameras", None), "cameras", "expected a list, got None"),
    (lambda s: setattr(s, "directives", ["x"]), "directives[0]",
     "expected a ModelDirective, got 'x' (a str)"),
    (lambda s: setattr(s, "plant_config", None), "plant_config",
     "expected a MultibodyPlantConfig, got None"),
    (lambda s: setattr(s.object, "pose", None), "object.pose", "expected a Transform, got None"),
    (lambda s: setattr(s.object, "random_pose", {}), "object.random_pose",
     "expected a RandomRestingPose, got {} (a dict)"),
])
def test_a_scenario_built_in_code_names_a_field_of_the_wrong_type(set_field, field, problem):
    scenario = Scenario()
    set_field(scenario)
    with pytest.raises(ScenarioError) as info:
        validate_scenario(scenario, "<in memory>")
    assert info.value.field == field and info.value.problem.startswith(problem), info.value


def test_numpy_values_and_tuples_are_their_types():
    import numpy as np

    scenario = Scenario(seed=np.int64(3), scan_target=np.array([0.55, 0.0, 0.06]))
    scenario.pick.place_position = (0.4, 0.3)
    scenario.max_time = np.float64(30.0)
    validate_scenario(scenario, "<in memory>")


@pytest.mark.parametrize(("config", "message"), [
    (lambda: GbhParams(parallel_grasps="no").check(),
     "GbhParams.parallel_grasps: expected true or false, got 'no' (a str)"),
    (lambda: GbhParams(ground_normal=1.0).check(),
     "GbhParams.ground_normal: expected a list of 3 components, got 1.0 (a float)"),
    (lambda: GbhParams(n_points="5000").check(), "GbhParams.n_points: expected an integer, got "
                                                  "'5000' (a str)"),
    (lambda: GbhParams().with_preset(["paper"]), "GbhParams.preset: one of '', 'paper', got "
                                                 "['paper']"),
    (lambda: AntipodalParams(check_ground="no").check(),
     "AntipodalParams.check_ground: expected true or false, got 'no' (a str)"),
    (lambda: ScanConfig(robot_base_xy=0).validate(),
     "ScanConfig.robot_base_xy: expected a list of 2 coordinates (x, y in m), got 0 (an int)"),
])
def test_configs_built_in_code_name_a_field_of_the_wrong_type(config, message):
    with pytest.raises(ValueError) as info:
        config()
    assert str(info.value) == message


# ---- bounds between fields -------------------------------------------------------------------


def test_a_bound_names_both_fields_and_holds_only_where_it_applies():
    from gbh_drake.core.ranges import Relation, check_bounds

    scenario = Scenario()
    scenario.scoop.min_lift, scenario.pick.max_lift = 0.3, 0.25
    with pytest.raises(FieldError) as info:
        check_bounds(scenario)
    assert info.value.path == ("scoop", "min_lift") and info.value.other.path == ("pick", "max_lift")
    assert info.value.problem.startswith("must be <= pick.max_lift (0.25 m), got 0.3 m: ")
    assert info.value.other.problem.startswith("must be >= scoop.min_lift (0.3 m), got 0.25 m: ")
    assert info.value.__reduce__()[1][2] is info.value.other  # (picklable, from a worker)
    settle = Scenario(task="settle", settle_time=2.0, max_time=1.0)  # max_time > settle_time:
    check_bounds(settle)                                              # for a pick only
    with pytest.raises(FieldError, match="must exceed settle_time"):
        check_bounds(Scenario(settle_time=2.0, max_time=1.0))
    retries = Scenario()
    retries.pick.max_retries = None  # left out: not compared (a bound on it would be skipped)
    check_bounds(retries)
    with pytest.raises(ValueError, match="Relation.op"):
        Relation("=<", "max_lift")
