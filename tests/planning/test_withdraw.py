"""Setting an object down: when its weight is off the hand (the near-zero band of the hand's
vertical load) and how an open hook withdraws when its bar lifted the object again."""

import numpy as np
import pytest

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.planning.model import HandPose, PlanningModel
from gbh_drake.planning.pick import withdraw_path, withdrawn_along
from gbh_drake.scenario import Scenario
from gbh_drake.systems.pick_and_carry import MIN_BAND, load_side, unloaded_band


def test_the_band_is_a_fraction_of_the_carried_load_or_its_noise_or_a_floor():
    assert unloaded_band(3.0, 0.05, 0.15) == pytest.approx(0.45)  # a mug: 15 % of 3 N
    assert unloaded_band(3.0, 0.4, 0.15) == pytest.approx(0.8)  # a noisy load: twice its noise
    assert unloaded_band(0.5, 0.0, 0.15) == MIN_BAND  # a light object: the floor
    # A mug swinging while held (its load's deviation 1.76 N): no wider than 40 % of its load.
    assert unloaded_band(3.0, 1.76, 0.15, 0.4) == pytest.approx(1.2)
    assert unloaded_band(0.1, 0.0, 0.15, 0.4) == MIN_BAND


def test_only_a_load_near_zero_counts_as_down_and_one_pressing_down_does_not():
    band = 0.8
    assert load_side(5.4, band) == 1  # carried
    assert load_side(1.3, band) == 1  # the teapot's: fallen below 40 %, the bar still bears it
    assert load_side(0.3, band) == 0  # set down
    assert load_side(-0.8, band) == 0  # on the band's edge
    assert load_side(-1.5, band) == -1  # the hand presses the object down


def test_withdrawn_along_measures_the_move_along_minus_y_g():
    from pydrake.math import RigidTransform, RotationMatrix

    R = RotationMatrix.MakeZRotation(np.pi / 2)  # y_G = -x_W
    X0 = RigidTransform(R, [0.4, 0.3, 0.1])
    assert withdrawn_along(X0, RigidTransform(R, [0.42, 0.3, 0.05])) == pytest.approx(0.02)
    assert withdrawn_along(X0, RigidTransform(R, [0.4, 0.35, 0.1])) == pytest.approx(0.0)


@pytest.mark.sim
def test_a_withdrawal_goes_down_then_out_along_the_bar_then_back_along_z_g():
    scenario = Scenario()
    model = PlanningModel(scenario.directives)
    hand = HandPose(HOOK_GRIPPER.q_open)
    q0 = np.asarray(scenario.robot.q_home, dtype=float)
    X0 = model.X_WG(q0, hand)
    q = withdraw_path(model, q0, scenario.pick, drop=0.01, shift=0.02)
    X_low, X_out, X_back = (model.X_WG(q[k], hand) for k in ("lowered", "out", "retreat"))
    tol = 2e-3  # the IK's
    assert np.allclose(X_low.translation() - X0.translation(), [0, 0, -0.01], atol=tol)
    assert withdrawn_along(X_low, X_out) == pytest.approx(0.02, abs=tol)
    d = X_back.translation() - X_out.translation()
    back = -d @ X_out.rotation().col(2)  # along -z_G (each pose within the IK's tolerance)
    assert back == pytest.approx(scenario.pick.retreat_distance, abs=2 * tol)
    # Nothing asked, nothing moved but the retreat.
    q = withdraw_path(model, q0, scenario.pick)
    assert np.allclose(q["lowered"], q0) and np.allclose(q["out"], q0)


@pytest.mark.sim
def test_the_hands_own_inertia_going_up_is_not_counted_as_a_load():
    """Going up from rest the flange pulls harder on the hand (its own mass accelerates): the
    machine takes m a off the measured load, from the arm's commanded trajectory, so that a
    retreat's start is not read as the bar lifting the object; holding, nothing is taken off."""
    from types import SimpleNamespace

    from gbh_drake.planning.trajectories import joint_path
    from gbh_drake.systems.pick_and_carry import PickAndCarry, _State

    scenario = Scenario()
    machine = PickAndCarry(scenario.station_directives(), scenario.pick, scenario.robot.hand,
                           settle_time=0.3)
    model = PlanningModel(scenario.directives)
    hand = HandPose(HOOK_GRIPPER.q_open)
    q0 = np.asarray(scenario.robot.q_home, dtype=float)
    q = withdraw_path(model, q0, scenario.pick)["retreat"]  # 10 cm back along -z_G (up)
    assert model.X_WG(q, hand).translation()[2] > model.X_WG(q0, hand).translation()[2] + 0.05
    s = _State()
    s.status.plan = SimpleNamespace(bar=0.0)
    s.arm = joint_path([q0, q], 0.0, velocity_scale=0.2)
    end = s.arm.end_time()
    assert machine._accel_z(s, 0.05 * end) > 0.05  # speeding up, upward
    assert machine._accel_z(s, 0.95 * end) < -0.05  # slowing down
    assert machine._accel_z(s, end + 0.1) == 0.0
    s.arm = None
    assert machine._accel_z(s, 0.3) == 0.0
