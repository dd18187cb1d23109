"""The plan lifts a hooked bucket from where its handle will rest on the bar, not from the hole's
centre, and carries it at that height (a scan, the grasp search and planning; no pick)."""

import pytest

from gbh_drake.messages import Mode
from gbh_drake.planning.pick import CARRY_TOLERANCE, PickPlan
from gbh_drake.trial import build_trial, simulate_trial

pytestmark = pytest.mark.sim


def test_a_bucket_hooked_under_its_handle_is_lifted_by_the_handles_drop(scenario):
    scenario.object.name = "bucket"
    scenario.settle_time = 0.2
    trial = build_trial(scenario)
    simulator, _ = simulate_trial(trial, max_time=scenario.settle_time + 0.05)
    context = trial.pick.GetMyContextFromRoot(simulator.get_context())
    status = trial.pick.GetOutputPort("status").Eval(context)
    while status.mode in (Mode.SETTLE, Mode.PLAN) and simulator.get_context().get_time() < 4.0:
        # (The scan may wait for the object to be still.)
        simulator.AdvanceTo(simulator.get_context().get_time() + 0.05)
        status = trial.pick.GetOutputPort("status").Eval(context)
    plan = status.plan
    assert isinstance(plan, PickPlan), [r.text() for r in status.refusals]
    # The handle sinks onto the bar once lifted: the lift accounts for it.
    assert plan.support == "bar"
    assert plan.drop > 0.01
    assert plan.lift >= plan.lift_needed - 1e-9 or plan.notes
    # The hook point stays at the lift height along the carry.
    assert plan.carry_low >= plan.hook_W[2] + plan.lift - CARRY_TOLERANCE - 1e-6 or plan.notes
    assert plan.carry and len(plan.carry) >= 2
