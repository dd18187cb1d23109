"""``gbh_drake.run_trial``: the one-call API returns the record ``gbh run`` writes."""

import pytest

import gbh_drake
from gbh_drake import SCENARIOS_DIR
from gbh_drake.run import run
from gbh_drake.scenario import Scenario, ScenarioError, load_scenario

pytestmark = [pytest.mark.sim, pytest.mark.trial]


def _comparable(record):
    d = record.to_dict()
    d.pop("timings")
    return d


def test_run_trial_returns_the_same_record_as_gbh_run_for_the_default_scenario(tmp_path):
    """The packaged default, run through the API (no argument: its own max_time, no outputs)
    and through ``gbh run``'s ``run`` (which records a replay): the same record, timings
    aside."""
    record = gbh_drake.run_trial()
    scenario = load_scenario(SCENARIOS_DIR / "default.yaml",
                             overrides=f"output_dir: {tmp_path / 'out'}")
    summary = run(scenario)
    assert record.success and record.held_by == "cage"
    assert _comparable(record) == _comparable(summary.record)
    assert not (tmp_path / "output").exists()


def test_run_trial_takes_a_scenario_built_in_code_with_overrides():
    scenario = Scenario(max_time=1.5)
    record = gbh_drake.run_trial(scenario, overrides=["seed: 4", "{task: settle, settle_time: 0.3}"])
    assert record.seed == 4 and record.sim_time == pytest.approx(0.3, abs=0.02)
    assert scenario.seed == 0  # the caller's scenario is not modified


def test_run_trial_refuses_a_bad_override_naming_the_field():
    with pytest.raises(ScenarioError, match="seed"):
        gbh_drake.run_trial(Scenario(), overrides="seed: -3")
