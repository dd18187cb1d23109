"""A pick whose object the arm cannot lower at the place is still planned: the set-down comes
after the verdict (the cage test), so the plan keeps the pick and carry, says that it sets
nothing down, and the trial ends holding the object (as with ``pick.set_down`` false)."""

import dataclasses

import numpy as np
import pytest

from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.objects import make_object
from gbh_drake.planning.model import PlanningModel
from gbh_drake.planning.pick import NO_SET_DOWN, PickPlan, PickSetup, plan_pick
from gbh_drake.scenario import Scenario

#: A place beside the robot's base (x, y m): the arm carries the mug there at the lift height
#: but cannot lower it (found by trying places round the base).
BESIDE_THE_BASE = [0.1, 0.2]


@pytest.fixture(scope="module")
def mug_plan_at():
    scenario = Scenario()
    mesh = make_object("mug_classic").mesh.copy()
    mesh.apply_translation([0.55, 0.0, -mesh.bounds[0, 2]])
    model = PlanningModel(scenario.directives, padding=0.002)
    best = plan_grasps(mesh, GbhParams(), seed=0).ranked[0]

    def plan(place):
        cfg = dataclasses.replace(scenario.pick, place_position=list(place))
        setup = PickSetup(model, None, np.asarray(mesh.vertices), mesh.centroid, cfg)
        return plan_pick(setup, best.X_WG, best.kind, 0, np.asarray(scenario.robot.q_home))

    return plan


def test_a_pick_the_arm_cannot_set_down_is_planned_without_the_set_down(mug_plan_at):
    plan = mug_plan_at(BESIDE_THE_BASE)
    assert isinstance(plan, PickPlan), plan  # it was refused: no IK solution at place
    assert not plan.sets_down and NO_SET_DOWN in plan.notes
    assert not {"place", "opened", "down", "slide", "retreat"} & set(plan.q)
    # The hook point's place is where the carry ends, over the place.
    np.testing.assert_allclose(plan.place_W[:2], BESIDE_THE_BASE, atol=0.01)


def test_a_pick_the_arm_can_set_down_keeps_its_set_down(mug_plan_at):
    plan = mug_plan_at(Scenario().pick.place_position)
    assert isinstance(plan, PickPlan) and plan.sets_down and NO_SET_DOWN not in plan.notes
    assert {"place", "opened", "retreat"} <= set(plan.q)
