"""The lift allows for hooked material sliding through the loop (planning/pick.py with
``pick.slide_lift``): the plan on a wire hanger hooked in the middle of its straight bar."""

import dataclasses

import numpy as np

from gbh_drake.core.results import PARALLEL
from gbh_drake.planning.model import PlanningModel
from gbh_drake.planning.pick import PickPlan, PickSetup, plan_pick
from gbh_drake.scenario import Scenario
from tests.core.test_hanging_pose import _standing_hanger


def test_the_plan_lifts_for_the_corner_the_wire_slides_to_and_says_so():
    scenario = Scenario()
    mesh, points, X = _standing_hanger()
    model = PlanningModel(scenario.directives, padding=0.002)
    q0 = np.asarray(scenario.robot.q_home)
    plans = {}
    for slide in (False, True):
        config = dataclasses.replace(scenario.pick, slide_lift=slide, max_lift=0.6)
        setup = PickSetup(model, None, points, mesh.center_mass, config)
        plans[slide] = plan_pick(setup, X, PARALLEL, 0, q0)
        assert isinstance(plans[slide], PickPlan), plans[slide]
    assert plans[False].slide == 0.0 and plans[True].slide > 0.14
    assert plans[True].lift_needed > plans[False].lift_needed + 0.12
    assert any("may slide" in note for note in plans[True].notes)
