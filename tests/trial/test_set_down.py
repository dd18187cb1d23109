"""Setting the object down after the cage test: the hand lets go only once the object's weight
is off it, and a bar that lifts the object again while withdrawing stops, goes back down and
withdraws out of the hole before going up (PickAndCarry's LOWER, RELEASE and RETREAT)."""

import pytest

from gbh_drake import SCENARIOS_DIR
from gbh_drake.messages import Mode
from gbh_drake.scenario import load_scenario
from gbh_drake.trial import build_trial, simulate_trial

pytestmark = pytest.mark.sim


@pytest.mark.trial
def test_a_mug_set_down_on_its_side_is_left_free_on_the_table_not_carried_off(tmp_path):
    """random_mug_pose: the mug lands on its side; going up, the bar caught its handle and
    carried it off (it ended hanging 12 cm up). Now the machine sees the hand's load rise,
    goes back down and withdraws the bar along its axis first: the mug ends free on the table.
    The verdict (decided at the cage test) is the same."""
    scenario = load_scenario(SCENARIOS_DIR / "random_mug_pose.yaml")
    scenario.output_dir = str(tmp_path / "out")
    trial = build_trial(scenario)
    simulator, record = simulate_trial(trial)
    assert record.success and record.held_by == "cage", record.reason
    assert record.verdict.released_on_table, record.verdict.released_pose
    status = trial.pick.GetOutputPort("status").Eval(
        trial.pick.GetMyContextFromRoot(simulator.get_context()))
    assert status.mode is Mode.DONE
    notes = "\n".join(status.set_down_notes)
    assert "set down (load" in notes and "the bar lifts the object again" in notes, notes
