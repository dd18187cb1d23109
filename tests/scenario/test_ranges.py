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
from gbh_drake.scenario import RandomRestingPose, Scenario, ScenarioError, load_scenario
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
    with pytest.raises(ValueError, match=r"^ScanConfig\.sdf_trunc: must be >= 2 voxel_size"):
        ScanConfig(voxel_size=0.004, sdf_trunc=0.005).validate()
    with pytest.raises(ValueError, match=r"^ScanConfig\.distance_max: must be >= distance "):
        ScanConfig(distance_max=0.3).validate()
    path = tmp_path / "bad.yaml"
    path.write_text("scan: {distance_max: 0.3}\n")
    with pytest.raises(ScenarioError) as loaded:
        load_scenario(path)
    assert loaded.value.field == "scan.distance_max"
    assert loaded.value.problem.startswith("must be >= scan.distance (0.5)")


def test_own_checks_raise_field_errors_inside():
    """The public checks are made from the same FieldError the loader reports."""
    with pytest.raises(FieldError) as info:
        check_fields(AntipodalParams(min_contact_depth=0.05), ("antipodal",))
    assert info.value.path == ("antipodal", "min_contact_depth")
    assert info.value.problem == "must be <= antipodal.contact_depth (0.015 m)"


@pytest.mark.parametrize(
    "bad", [{"n_points": 0}, {"ground_normal": [0.0, 0.0]}, {"ground_normal": [0.0, 0.0, 0.0]},
            {"p_theta": 1.5}, {"n_rays_per_plane": 2}, {"p_sweep": 0},
            {"cage_clearance": -0.001}, {"min_miss_resultant": 1.5},
            {"sweep_margin_spacings": -1.0}]
)
def test_out_of_range_params_name_the_field(bad):
    with pytest.raises(GbhInputError, match=next(iter(bad))):
        GbhParams(**bad).check()
