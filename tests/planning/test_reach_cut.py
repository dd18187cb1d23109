"""The cut by reach on a real pot and the real arm: the paper's ten are all out of reach."""

import numpy as np

from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.method_spec import Tier
from gbh_drake.objects import make_object
from gbh_drake.objects.stability import stable_poses
from gbh_drake.planning.choice import Offer, choose
from gbh_drake.planning.model import PlanningModel
from gbh_drake.planning.pick import PickPlan, PickSetup, plan_pick, reach_refusal
from gbh_drake.scenario import Scenario


def test_a_pot_on_its_side_is_hooked_by_a_grasp_below_the_paper_ten():
    """Issue 42: the pot lying on its side, one handle up and away from the robot, at the far
    edge of the experiment's poses (x = 0.62 m). GbH's best twelve grasps hook the far handle,
    out of the arm's reach (no IK at the grasp pose from home): the plain top ten (the paper's
    cut, ``top_k: 10``) are all of them. Offered 40 and cut by reach, the plan choice plans the
    first the arm reaches."""
    scenario = Scenario()
    spec = make_object("pot")
    pose = stable_poses(spec.mesh).poses[3]  # on its side (probability 0.06)
    mesh = spec.mesh.copy()
    T = np.eye(4)
    T[:3, :3] = pose.R
    mesh.apply_transform(T)
    mesh.apply_translation([0.62, 0.0, -mesh.bounds[0, 2]])
    model = PlanningModel(scenario.directives, padding=0.002)
    setup = PickSetup(model, None, np.asarray(mesh.vertices), mesh.centroid, scenario.pick)
    q0 = np.asarray(scenario.robot.q_home)

    def plan(tier, rank, grasp):
        return plan_pick(setup, grasp.X_WG, grasp.kind, rank, q0)

    def reach(tier, rank, grasp):
        return reach_refusal(setup, grasp.X_WG, grasp.kind, rank, q0)

    def is_plan(result):
        return isinstance(result, PickPlan)

    paper = plan_grasps(mesh, GbhParams(), seed=0).ranked  # top_k 10
    ours = plan_grasps(mesh, GbhParams(top_k=40), seed=0).ranked  # preset robust's
    assert len(paper) == 10 and len(ours) == 40
    assert all(reach(Tier.GRASPS, i, g) is not None for i, g in enumerate(paper))
    plain = choose([Offer(Tier.GRASPS, lambda: paper)], plan_grasp=plan, is_plan=is_plan,
                   max_grasps=10)
    assert plain.plan is None
    cut = choose([Offer(Tier.GRASPS, lambda: ours)], plan_grasp=plan, is_plan=is_plan,
                 max_grasps=10, reach=reach)
    assert cut.plan is not None and cut.rank >= 10
