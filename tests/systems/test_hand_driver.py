"""The hand closes like a Franka Hand: at its speed, then squeezing with the commanded force."""

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource
from station_helpers import make_station

from gbh_drake.core.gripper import BAR_DEPLOYED, BAR_RETRACTED, HOOK_GRIPPER

pytestmark = pytest.mark.sim


def _close(scenario, q_target: float, force: float, bar: float, t_end: float):
    station = make_station(scenario)
    builder = DiagramBuilder()
    builder.AddSystem(station)
    hold = builder.AddSystem(ConstantVectorSource(np.concatenate([station.q_home, np.zeros(7)])))
    command = builder.AddSystem(ConstantVectorSource([q_target, force, bar]))
    builder.Connect(hold.get_output_port(), station.GetInputPort("panda.desired_state"))
    builder.Connect(command.get_output_port(), station.GetInputPort("hook_gripper.command"))
    simulator = Simulator(builder.Build())
    context = station.GetMyContextFromRoot(simulator.get_mutable_context())
    samples = []
    for t in (0.2, t_end):
        simulator.AdvanceTo(t)
        samples.append((station.GetOutputPort("hook_gripper.state").Eval(context).copy(),
                        station.GetOutputPort("hook_gripper.actuation").Eval(context).copy()))
    return samples


@pytest.mark.parametrize("force", [70.0, 20.0])
def test_fingers_close_at_speed_then_squeeze_with_the_force(scenario, force):
    """Bar folded, nothing between the rods: they close at the hand's speed until they touch,
    then squeeze each other with the commanded force."""
    (x_early, _), (x_end, u_end) = _close(scenario, 0.0, force, BAR_RETRACTED, 1.2)
    speed = scenario.robot.hand.speed
    # 0.2 s in, each finger has moved about 0.2 s x 5 cm/s (Franka's finger speed).
    np.testing.assert_allclose(x_early[:2], HOOK_GRIPPER.q_open - 0.2 * speed, atol=2e-3)
    np.testing.assert_allclose(x_end[:2], 0.5 * HOOK_GRIPPER.rod_width, atol=1.5e-3)
    assert x_end[2] == pytest.approx(BAR_RETRACTED, abs=0.05)
    np.testing.assert_allclose(-u_end[:2], force, rtol=0.1)


def test_the_hook_closes_its_loop_at_the_width_command(scenario):
    """Bar out, width command q_closed: the fingers stop where the bar's tip meets the
    straight rod (the loop is closed), pushing nothing."""
    _, (x_end, u_end) = _close(scenario, HOOK_GRIPPER.q_closed, 70.0, BAR_DEPLOYED, 1.0)
    np.testing.assert_allclose(x_end[:2], HOOK_GRIPPER.q_closed, atol=2e-4)
    assert x_end[2] == pytest.approx(BAR_DEPLOYED, abs=0.02)
    assert np.all(np.abs(u_end[:2]) < 2.0)
