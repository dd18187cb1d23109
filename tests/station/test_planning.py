"""Collision-checked motion: RRT-Connect around the table and the object, seeded, re-checked."""

import numpy as np
import pytest
from pydrake.math import RigidTransform, RotationMatrix

from gbh_drake.modeling.object_sdf import write_object_model
from gbh_drake.objects import make_object
from gbh_drake.planning.collision import make_planning_model
from gbh_drake.planning.rrt import plan_rrt_connect

Q_OPEN = 0.04


@pytest.fixture(scope="module")
def kettle_model(tmp_path_factory):
    from gbh_drake.scenario import Scenario

    spec = make_object("kettle")
    files = write_object_model(spec.mesh, "kettle", tmp_path_factory.mktemp("kettle"),
                               density=spec.density)
    return Scenario(), make_planning_model(Scenario(), str(files.sdf),
                                           RigidTransform([0.45, 0.0, 0.0]))


def _blocked_goal(model, q0):
    """A collision-free goal whose straight joint-space edge from q0 collides (seeded search)."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        q1 = rng.uniform(model.arm_lower, model.arm_upper)
        if model.free(q1, Q_OPEN) and not model.edge_free(q0, q1, Q_OPEN):
            return q1
    raise AssertionError("no blocked goal found")


def test_rrt_connect_goes_around_obstacles_and_repeats(kettle_model):
    scenario, model = kettle_model
    q0 = np.asarray(scenario.robot.q_home)
    assert model.free(q0, Q_OPEN)
    q1 = _blocked_goal(model, q0)
    path = plan_rrt_connect(model, q0, q1, Q_OPEN, seed=0)
    assert path is not None and len(path) >= 3
    np.testing.assert_array_equal(path[0], q0)
    np.testing.assert_array_equal(path[-1], q1)
    assert all(model.edge_free(a, b, Q_OPEN) for a, b in zip(path[:-1], path[1:], strict=True))
    again = plan_rrt_connect(model, q0, q1, Q_OPEN, seed=0)
    assert len(again) == len(path)
    assert all(np.array_equal(a, b) for a, b in zip(again, path, strict=True))


def test_start_in_collision_has_no_path(kettle_model):
    scenario, model = kettle_model
    q_down = np.asarray(scenario.robot.q_home, dtype=float).copy()
    q_down[1], q_down[3] = 1.5, -0.5  # the arm folded down into the table
    assert not model.free(q_down, Q_OPEN)
    assert plan_rrt_connect(model, q_down, scenario.robot.q_home, Q_OPEN) is None


def test_the_object_is_an_obstacle(kettle_model):
    """A gripper pose inside the kettle's hull collides with it, but not without the object."""
    from pydrake.systems.framework import DiagramBuilder

    from gbh_drake.planning.ik import solve_gripper_ik
    from gbh_drake.station import ObjectAsset, add_station

    scenario, model = kettle_model
    empty = make_planning_model(scenario, None, None)
    box = make_object("box")  # any object: the station only serves the IK here
    station = add_station(DiagramBuilder(), scenario,
                          object_asset=ObjectAsset("box", box.mesh, 500.0, (1, 1, 1, 1), "t"))
    plant = station.plant
    context = plant.CreateDefaultContext()
    G = plant.GetFrameByName("G", station.gripper)
    # Top-down, palm 12 cm above the table over the kettle's centre: fingers inside its body.
    X_WG = RigidTransform(RotationMatrix(np.diag([1.0, -1.0, -1.0])), [0.45, 0.0, 0.12])
    q = solve_gripper_ik(plant, context, station.arm, G, X_WG, station.q_home)
    assert q is not None
    assert not model.free(q, Q_OPEN)
    assert empty.free(q, Q_OPEN)
