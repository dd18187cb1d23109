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


@pytest.mark.trial
def test_a_trial_whose_set_down_cannot_be_planned_ends_holding_the_object(tmp_path):
    """The default mug carried to a place beside the robot's base, where the arm reaches the
    carry but cannot lower the mug: the grasp is executed (it was refused, 'no IK solution at
    place', and the trial had no grasp), the verdict is decided at the cage test, and the
    trial ends there holding the mug, the plan saying why."""
    scenario = load_scenario(SCENARIOS_DIR / "default.yaml")
    scenario.output_dir = str(tmp_path / "out")
    scenario.pick.place_position = [0.1, 0.2]
    trial = build_trial(scenario)
    simulator, record = simulate_trial(trial)
    assert record.success and record.held_by == "cage", record.reason
    assert any(note.startswith("no set-down") for note in record.plan_notes), record.plan_notes
    assert "lower" not in record.phases and "cage_test" in record.phases
    assert not record.verdict.released_on_table
    status = trial.pick.GetOutputPort("status").Eval(
        trial.pick.GetMyContextFromRoot(simulator.get_context()))
    assert status.mode is Mode.DONE and not status.set_down_notes


@pytest.mark.trial
def test_a_hand_that_cannot_withdraw_leaves_the_object_standing_not_carried_off(tmp_path):
    """The default scenario's teapot hangs on its side and lands on it; each withdrawal along
    the bar lifted it again, and once the tries were used the retreat carried it off (it ended
    hanging 16 cm up, its full weight on the bar). Now the hand goes back down, opens and
    stops there: the teapot rests on the table, the gripper still touching it."""
    scenario = load_scenario(SCENARIOS_DIR / "default.yaml", overrides="{object: {name: teapot}}")
    scenario.output_dir = str(tmp_path / "out")
    trial = build_trial(scenario)
    simulator, record = simulate_trial(trial)
    assert record.success and record.held_by == "cage", record.reason
    status = trial.pick.GetOutputPort("status").Eval(
        trial.pick.GetMyContextFromRoot(simulator.get_context()))
    notes = "\n".join(status.set_down_notes)
    assert status.mode is Mode.DONE and "tries used: down" in notes, notes
    assert record.verdict.released_standing and not record.verdict.released_on_table
    assert "retreat" in record.phases  # the tries withdrew before it stopped
