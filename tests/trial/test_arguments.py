"""The public functions that run a trial refuse arguments of the wrong type at the call, naming
the function and the argument (or the scenario's field), before anything is built: a
``ScenarioError`` for the scenario and its overrides, a ``TypeError`` for the others."""

import numpy as np
import pytest

import gbh_drake
import gbh_drake.trial as trial_module
from gbh_drake.scenario import Scenario, ScenarioError
from gbh_drake.station import make_station
from gbh_drake.trial import build_trial, record_trial, simulate_trial


@pytest.fixture(autouse=True)
def nothing_is_simulated(monkeypatch):
    """A refusal comes before the simulation (a trial would take seconds: the test fails)."""
    def forbidden(*args, **kwargs):
        raise AssertionError("a trial was simulated")
    monkeypatch.setattr(trial_module, "simulate_trial", forbidden)


def _scalar_target() -> Scenario:
    scenario = Scenario()
    scenario.scan_target = 0.5
    return scenario


SCALAR = "scan_target: expected a list of 3 coordinates (x, y, z in m), got 0.5 (a float)"


@pytest.mark.parametrize("call", [
    lambda: gbh_drake.run_trial(_scalar_target()),
    lambda: build_trial(_scalar_target()),
    lambda: record_trial(_scalar_target()),
    lambda: make_station(_scalar_target()),
])
def test_a_scalar_scan_target_is_a_scenario_error_naming_the_field(call):
    with pytest.raises(ScenarioError) as info:
        call()
    assert str(info.value) == f"<in memory>: {SCALAR}"
    assert info.value.field == "scan_target"


@pytest.mark.parametrize(("call", "message"), [
    (lambda: gbh_drake.run_trial(3), "run_trial(): scenario_or_path: expected a Scenario, a "
                                     "scenario file's path or None, got 3 (an int)"),
    (lambda: build_trial("scenarios/default.yaml"), "build_trial(): scenario: expected a "
     "Scenario (of a file: gbh_drake.scenario.load_scenario(path)), got 'scenarios/default.yaml' "
     "(a str)"),
    (lambda: make_station(None), "make_station(): scenario: expected a Scenario (of a file: "
                                 "gbh_drake.scenario.load_scenario(path)), got None (a NoneType)"),
])
def test_a_scenario_of_the_wrong_type_is_named(call, message):
    with pytest.raises(ScenarioError) as info:
        call()
    assert str(info.value) == message


def test_overrides_of_the_wrong_type_or_encoding_are_named():
    default = gbh_drake.SCENARIOS_DIR / "default.yaml"
    with pytest.raises(ScenarioError) as info:
        gbh_drake.run_trial(overrides=3)
    assert str(info.value) == (f"{default} (overrides): expected YAML text (a str, or bytes in "
                               "UTF-8) or a list of them, got 3 (an int)")
    with pytest.raises(ScenarioError) as info:
        gbh_drake.run_trial(Scenario(), overrides=b"seed: -3")  # bytes: read as a file is
    assert str(info.value) == ("<in memory> (overrides): seed (line 1): must be an integer in "
                               "[0, 18446744073709551615], got -3 (seeds are unsigned 64-bit "
                               "integers)")
    with pytest.raises(ScenarioError, match=r"\(overrides\): is UTF-16 text"):
        gbh_drake.run_trial(Scenario(), overrides="seed: 3".encode("utf-16"))


@pytest.mark.parametrize(("call", "message"), [
    (lambda: gbh_drake.run_trial(Scenario(), meshcat="yes"),
     "run_trial(): meshcat: expected a pydrake.geometry.Meshcat or None, got 'yes' (a str)"),
    (lambda: build_trial(Scenario(), method="gbh"), "build_trial(): method: expected a "
     "GraspMethod (e.g. gbh_drake.methods.method_named('gbh')) or None, got 'gbh' (a str)"),
    (lambda: build_trial(Scenario(), grasps=5), "build_trial(): grasps: expected a list of "
     "grasps (each with X_WG and kind) or None, got 5 (an int)"),
    (lambda: build_trial(Scenario(), grasps=[np.eye(4)]), "build_trial(): grasps[0]: expected a "
     "grasp with X_WG (the open gripper's pose in W, 4 x 4) and kind, got array([[1., 0., 0., "),
    (lambda: build_trial(Scenario(), asset="mug_classic"), "build_trial(): asset: expected an "
     "ObjectAsset (gbh_drake.modeling.object_asset.load_object_asset) or None, got "
     "'mug_classic' (a str)"),
    (lambda: record_trial(Scenario(), keep_replay="no"), "record_trial(): keep_replay: expected "
     "True, False or a function of the record, got 'no' (a str)"),
    (lambda: simulate_trial(Scenario()), "simulate_trial(): trial: expected a Trial "
     "(build_trial(scenario)), got Scenario(seed=0, object=ObjectConfig(name='mug_classic', ... "
     "(a Scenario)"),
])
def test_other_arguments_of_the_wrong_type_are_named(call, message):
    with pytest.raises(TypeError) as info:
        call()
    assert str(info.value).startswith(message), info.value
