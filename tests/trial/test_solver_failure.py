"""A step Drake's contact solver cannot solve ends the trial with a record, not a crash: after the
cage test the verdict stands with a warning; before it the trial has no outcome (``error``)."""

import pytest

from gbh_drake import REPO_ROOT
from gbh_drake.messages import Mode, verdict_final


def test_the_verdict_is_final_once_the_cage_test_is_over():
    final = {m for m in Mode if verdict_final(m)}
    assert final == {Mode.LOWER, Mode.RELEASE, Mode.RETREAT, Mode.DONE, Mode.NO_GRASP,
                     Mode.NO_REACHABLE_GRASP}


@pytest.mark.trial
def test_sap_failing_after_the_cage_test_leaves_the_verdict_with_a_warning(tmp_path):
    """The experiment's tote_bag, gbh-1, natural, trial 3, as GbH without the exit proof chooses
    (``unknown_is_occupied: false``, the default until bed1a7d), the insert was planned
    before 2026-12-04 (``pick.precise_insert: false``) and the bag set down as before the
    set-down read the hand's load (the object down once the load fell under 40 % of the load
    carried, no dwell, no withdrawal): SAP fails to converge at t = 14.43 s, while the hand
    backs off from the released bag (it used to be an ``error`` row)."""
    import dataclasses

    from gbh_drake.experiment.config import trial_scenario
    from gbh_drake.trial import build_trial, simulate_trial

    scenario = trial_scenario(REPO_ROOT / "scenarios" / "experiment.yaml", "tote_bag", "gbh-1", 3,
                              "natural")
    scenario.gbh = dataclasses.replace(scenario.gbh, unknown_is_occupied=False)
    scenario.pick.precise_insert = False
    scenario.pick.unloaded_band, scenario.pick.unloaded_dwell = 0.4, 0.0
    scenario.pick.relift_tries = 0
    scenario.output_dir = str(tmp_path)
    _, record = simulate_trial(build_trial(scenario))
    stopped = [w for w in record.warnings if w.startswith("the simulation stopped")]
    assert stopped, "this trial no longer makes SAP diverge: pick another for this test"
    assert "did not converge after t = 14.4" in stopped[0] and "retreat phase" in stopped[0]
    assert record.outcome == "success" and record.held_by == "pinch", record.reason
