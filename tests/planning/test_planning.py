"""Collision-checked motion and IK on the planning model (no free bodies): RRT-Connect around
the table and a scanned object's hull, seeded, re-checked."""

import numpy as np
import pytest
from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.objects import make_object
from gbh_drake.planning.model import HandPose, PlanningModel
from gbh_drake.planning.rrt import plan_rrt_connect
from gbh_drake.scenario import Scenario

OPEN = HandPose(HOOK_GRIPPER.q_open)


@pytest.fixture(scope="module")
def kettle_model():
    mesh = make_object("kettle").mesh.copy()
    mesh.apply_translation([0.45, 0.0, 0.0])
    scenario = Scenario()
    return scenario, PlanningModel(scenario.directives, obstacles=[mesh])


def _blocked_goal(model, q0):
    """A collision-free goal whose straight joint-space edge from q0 collides (seeded search)."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        q1 = rng.uniform(model.arm_lower, model.arm_upper)
        if model.free(q1, OPEN) and not model.edge_free(q0, q1, OPEN):
            return q1
    raise AssertionError("no blocked goal found")


def test_rrt_connect_goes_around_obstacles_and_repeats(kettle_model):
    scenario, model = kettle_model
    q0 = np.asarray(scenario.robot.q_home)
    assert model.free(q0, OPEN)
    q1 = _blocked_goal(model, q0)
    path = plan_rrt_connect(model, q0, q1, OPEN, seed=0)
    assert path is not None and len(path) >= 3
    np.testing.assert_array_equal(path[0], q0)
    np.testing.assert_array_equal(path[-1], q1)
    assert all(model.edge_free(a, b, OPEN) for a, b in zip(path[:-1], path[1:], strict=True))
    again = plan_rrt_connect(model, q0, q1, OPEN, seed=0)
    assert len(again) == len(path)
    assert all(np.array_equal(a, b) for a, b in zip(again, path, strict=True))


def test_start_in_collision_has_no_path(kettle_model):
    scenario, model = kettle_model
    q_down = np.asarray(scenario.robot.q_home, dtype=float).copy()
    q_down[1], q_down[3] = 1.5, -0.5  # the arm folded down into the table
    assert not model.free(q_down, OPEN)
    assert plan_rrt_connect(model, q_down, scenario.robot.q_home, OPEN) is None


def test_the_object_is_an_obstacle_and_ik_reaches_into_it(kettle_model):
    """A gripper pose inside the kettle's hull collides with it, but not without the object;
    IK itself (on the model without free bodies) reaches the pose exactly."""
    scenario, model = kettle_model
    empty = PlanningModel(scenario.directives)
    # Top-down, palm 12 cm above the table over the kettle's centre: fingers inside its body.
    X_WG = RigidTransform(RotationMatrix(np.diag([1.0, -1.0, -1.0])), [0.45, 0.0, 0.12])
    q = empty.ik(X_WG, scenario.robot.q_home, OPEN)
    assert q is not None
    np.testing.assert_allclose(empty.X_WG(q, OPEN).translation(), X_WG.translation(), atol=1e-3)
    assert not model.free(q, OPEN)
    assert empty.free(q, OPEN)


def test_ik_restarts_find_what_one_seed_misses():
    """A reachable pose SNOPT misses from the home configuration (about one random pose in
    eleven over the workspace did): restarts from other guesses find it, deterministically."""
    model = PlanningModel(Scenario().directives)
    X_WG = RigidTransform(RollPitchYaw([2.452, -1.714, 0.774]), [0.538, -0.13, 0.187])
    q_home = np.asarray(Scenario().robot.q_home)
    assert model.ik(X_WG, q_home, OPEN, restarts=0) is None
    found = model.ik(X_WG, q_home, OPEN, restarts=3)
    assert found is not None
    X = model.X_WG(found, OPEN)
    np.testing.assert_allclose(X.translation(), X_WG.translation(), atol=1.01e-3)
    assert X.rotation().InvertAndCompose(X_WG.rotation()).ToAngleAxis().angle() <= 0.0101
    np.testing.assert_array_equal(found, model.ik(X_WG, q_home, OPEN, restarts=3))


def test_an_ik_solution_in_which_the_arm_meets_itself_is_no_solution():
    """A pose (found by a seeded search over the workspace) for which SNOPT, from the home
    configuration, folds the arm into the hand: that configuration is refused (without
    restarts, no solution), and the restarts find one in which the robot does not meet
    itself, deterministically."""
    model = PlanningModel(Scenario().directives, padding=0.002)
    X_WG = RigidTransform(RollPitchYaw([-0.249, 0.047, 1.82]), [0.603, -0.146, 0.228])
    q_home = np.asarray(Scenario().robot.q_home)
    folded = model._ik_from(X_WG, q_home, OPEN, 1e-3, 1e-2)
    assert folded is not None and model.self_colliding(folded, OPEN)
    assert model.ik(X_WG, q_home, OPEN, restarts=0) is None
    found = model.ik(X_WG, q_home, OPEN, restarts=3)
    assert found is not None and not model.self_colliding(found, OPEN)
    np.testing.assert_allclose(model.X_WG(found, OPEN).translation(), X_WG.translation(),
                               atol=1.01e-3)
    np.testing.assert_array_equal(found, model.ik(X_WG, q_home, OPEN, restarts=3))


def test_an_edge_can_move_the_hand_with_the_arm():
    """``edge_free(q_a, q_b, hand, hand_b)`` interpolates the fingers with the arm: a block where
    the open straight rod is blocks the open hand and a closing one (it starts open), not the
    closed hand."""
    import trimesh

    scenario = Scenario()
    q = np.asarray(scenario.robot.q_home)
    g = HOOK_GRIPPER
    open_hand, closed = HandPose(g.q_open), HandPose(g.q_closed)
    X = PlanningModel(scenario.directives).X_WG(q, open_hand)
    p = X.multiply([0.0, g.q_open, 0.5 * g.finger_length])  # the open straight rod's middle
    block = trimesh.creation.box((0.006, 0.006, 0.006),
                                 trimesh.transformations.translation_matrix(p))
    model = PlanningModel(scenario.directives, obstacles=[block], padding=0.0)
    assert not model.edge_free(q, q, open_hand)
    assert model.edge_free(q, q, closed)
    assert not model.edge_free(q, q, open_hand, closed)
    assert not model.edge_free(q, q, closed, open_hand)
