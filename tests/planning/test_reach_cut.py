"""The cut by reach on a real pot and the real arm: ten grasps out of reach hide no reachable one."""

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


def test_ten_unreachable_grasps_do_not_hide_a_reachable_one():
    """Issue 42: the pot lying on its side, one handle up and away from the robot, at the far
    edge of the experiment's poses (x = 0.62 m), had its best ten (non-distinct) grasps on the far
    handle, out of the arm's reach (no IK at the grasp pose from home), and the near handle's
    ranked lower. Since the ranking is distinct its top ten reach the near handle too, so the
    case is built from its 40 ranked grasps: the unreachable ones first (at least ten), then the
    rest. The plain cut (the first ``max_grasps``: 10) plans nothing; the cut by reach plans the
    first the arm reaches, below the tenth."""
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

    ranked = plan_grasps(mesh, GbhParams(top_k=40), seed=0).ranked  # preset robust's top_k
    assert len(ranked) == 40
    out = [g for i, g in enumerate(ranked) if reach(Tier.GRASPS, i, g) is not None]
    offered = out + [g for g in ranked if not any(g is o for o in out)]
    assert len(out) >= 10
    plain = choose([Offer(Tier.GRASPS, lambda: offered)], plan_grasp=plan, is_plan=is_plan,
                   max_grasps=10)
    assert plain.plan is None
    cut = choose([Offer(Tier.GRASPS, lambda: offered)], plan_grasp=plan, is_plan=is_plan,
                 max_grasps=10, reach=reach)
    assert cut.plan is not None and cut.rank >= len(out) >= 10
