"""Planning a regrasp (planning/regrasp.py): a pinch turns a mug lying on its handle upright."""

import numpy as np
import pytest
from pydrake.math import RigidTransform

from gbh_drake.core.antipodal import sample_antipodal_grasps
from gbh_drake.core.params import AntipodalParams, GbhParams
from gbh_drake.core.regrasp import choose_regrasp_pose
from gbh_drake.objects import lift_to_table, make_object, stable_poses
from gbh_drake.planning.model import PlanningModel
from gbh_drake.planning.pick import PickSetup, Refusal
from gbh_drake.planning.regrasp import RegraspPlan, plan_regrasp
from gbh_drake.scenario import Scenario

pytestmark = pytest.mark.sim


@pytest.fixture(scope="module")
def lying_mug():
    """mug_square_handle on its side (its most probable pose offers no hook grasp), in W."""
    mesh = make_object("mug_square_handle").mesh
    X = np.eye(4)
    X[:3, :3] = stable_poses(mesh).poses[0].R
    X = lift_to_table(mesh, X)
    X[:2, 3] += [0.55, 0.05]
    return mesh.copy().apply_transform(X)


def test_a_pinch_sets_the_mug_upright_and_the_hand_moves_with_it(lying_mug):
    scenario = Scenario()
    poses = choose_regrasp_pose(lying_mug, [(p.R, p.probability) for p in
                                            stable_poses(lying_mug).poses],
                                GbhParams(), [0.55, 0.05])
    assert poses and poses[0].turn_deg == pytest.approx(90.0, abs=10.0)
    # The trial's sampler keeps GbH's table clearance (3 mm; the planner pads 2 mm).
    pinches = sample_antipodal_grasps(lying_mug, AntipodalParams(ground_clearance=0.003), rng=0)
    assert pinches
    near = PlanningModel(scenario.directives, padding=0.002)
    points = np.asarray(lying_mug.vertices)
    setup = PickSetup(near, None, points, points.mean(axis=0), scenario.pick, 0)
    q_home = np.asarray(scenario.robot.q_home)
    # (Pinches whose rods end exactly at the clearance may land within the planner's padding
    # by the IK's tolerance and be refused: the planner tries them in turn.)
    plans = [plan_regrasp(setup, g.X_WG, poses[0], i, q_home, q_home)
             for i, g in enumerate(pinches)]
    plan = next((p for p in plans if isinstance(p, RegraspPlan)), None)
    assert plan is not None, [p.text() for p in plans if isinstance(p, Refusal)]
    assert {"approach", "grasp", "lift", "above", "place", "opened", "retreat", "home"} <= \
        set(plan.q)
    # The gripper where it sets the mug down is the pinch moved by the resting pose's motion
    # (turned by the plan's yaw about the vertical through the place).
    X_pinch = pinches[plan.rank].X_WG
    yaw = np.radians(plan.yaw_deg)
    Rz = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]])
    np.testing.assert_allclose(plan.X_WG_place[:3, :3],
                               Rz @ poses[0].X_WnewWnow[:3, :3] @ X_pinch[:3, :3], atol=1e-9)
    # The arm reaches it (forward kinematics within the IK's tolerance, less the place depth).
    from gbh_drake.core.gripper import BAR_RETRACTED, HOOK_GRIPPER
    from gbh_drake.planning.model import HandPose

    held = HandPose(0.5 * HOOK_GRIPPER.rod_width, BAR_RETRACTED)
    X_reached = near.X_WG(plan.q["place"], held)
    X_place = RigidTransform(plan.X_WG_place)
    assert np.linalg.norm(X_reached.translation() - X_place.translation()) < \
        scenario.pick.place_depth + 2e-3
    # It lifts the mug clear of the table whichever way it turns in the hand.
    assert plan.lift >= scenario.pick.min_lift
    np.testing.assert_allclose(plan.q["home"], q_home)
    np.testing.assert_allclose(plan.place_W[:2], [0.55, 0.05], atol=0.03)


def test_the_regrasp_lifts_the_unseen_space_clear_too(lying_mug):
    """Unseen cells beyond the scan (as if the mug went on 6 cm where no camera looked) raise the
    lift that lets the held mug turn any way clear of the table."""
    scenario = Scenario()
    poses = choose_regrasp_pose(lying_mug, [(p.R, p.probability) for p in
                                            stable_poses(lying_mug).poses],
                                GbhParams(), [0.55, 0.05])
    pinches = sample_antipodal_grasps(lying_mug, AntipodalParams(ground_clearance=0.003), rng=0)
    near = PlanningModel(scenario.directives, padding=0.002)
    points = np.asarray(lying_mug.vertices)
    q_home = np.asarray(scenario.robot.q_home)
    lifts = []
    for unseen in (np.zeros((0, 3)), points + [0.0, 0.06, 0.0]):
        setup = PickSetup(near, None, points, points.mean(axis=0), scenario.pick, 0,
                          unseen_W=unseen)
        plan = next(p for p in (plan_regrasp(setup, g.X_WG, poses[0], i, q_home, q_home)
                                for i, g in enumerate(pinches)) if isinstance(p, RegraspPlan))
        lifts.append(plan.lift)
    assert lifts[1] > lifts[0] + 0.02, lifts
