"""The pick-and-carry machine as a table: every mode that is not final has a handler."""

import pytest

from gbh_drake.messages import FINAL_MODES, Mode
from gbh_drake.method_spec import Tier
from gbh_drake.scenario import Scenario
from gbh_drake.systems.pick_and_carry import PickAndCarry


def test_every_mode_but_the_final_ones_has_a_handler():
    assert set(PickAndCarry.AFTER) == set(Mode) - set(FINAL_MODES)
    assert set(PickAndCarry.DURING) <= set(PickAndCarry.AFTER)


@pytest.mark.sim
def test_the_machine_declares_one_input_per_port_of_its_tiers():
    s = Scenario()
    machine = PickAndCarry(s.station_directives(), s.pick, s.robot.hand, settle_time=0.3,
                           tiers=(Tier.GRASPS, Tier.REGRASP, Tier.FALLBACK))
    inputs = [machine.get_input_port(i).get_name() for i in range(machine.num_input_ports())]
    assert inputs[:4] == ["grasps", "regrasp_poses", "regrasp_grasps", "fallback_grasps"]
    with pytest.raises(ValueError, match="tiers must start with grasps"):
        PickAndCarry(s.station_directives(), s.pick, s.robot.hand, settle_time=0.3,
                     tiers=(Tier.FALLBACK,))


@pytest.mark.sim
@pytest.mark.parametrize("tiers, retries, regrasps, attempts", [
    ((Tier.GRASPS,), 0, 1, 1),  # the paper's one attempt
    ((Tier.GRASPS, Tier.FALLBACK), 0, 1, 2),  # a pinch after the hooks' empty lift
    ((Tier.GRASPS, Tier.REGRASP, Tier.FALLBACK), 1, 1, 4),  # 3 lifts and a regrasp
    ((Tier.GRASPS, Tier.REGRASP, Tier.FALLBACK), 1, 0, 3),
])
def test_the_machine_counts_the_picks_it_may_start(tiers, retries, regrasps, attempts):
    """Each lift (one per lifting tier, plus the retries) and each regrasp starts a pick: a
    trial may last max_time per attempt (trial_duration)."""
    from gbh_drake.core.params import RegraspParams

    s = Scenario()
    machine = PickAndCarry(s.station_directives(), s.pick, s.robot.hand, settle_time=0.3,
                           tiers=tiers, max_retries=retries,
                           regrasp=RegraspParams(max_regrasps=regrasps))
    assert machine.max_attempts == attempts


@pytest.mark.parametrize("argument, value, error", [
    ("settle_time", float("nan"), "settle_time must be a finite number"),
    ("period", 0.0, "period must be positive"),
    ("ground_clearance", -0.01, "ground_clearance must be at least 0"),
    ("max_retries", 1.5, "max_retries must be an integer"),
    ("scan_height", "0.06", "scan_height must be a finite number"),
])
def test_a_machine_built_by_hand_names_its_bad_argument(argument, value, error):
    """Before any model is parsed: a diagram of one's own builds the machine without a
    scenario's checks."""
    s = Scenario()
    kwargs = {"settle_time": 0.3, argument: value}
    with pytest.raises((TypeError, ValueError), match=error):
        PickAndCarry(s.station_directives(), s.pick, s.robot.hand, **kwargs)


def test_a_machine_without_a_pick_config_says_so():
    s = Scenario()
    with pytest.raises(TypeError, match="config must be a PickConfig, got dict"):
        PickAndCarry(s.station_directives(), {}, s.robot.hand, settle_time=0.3)


@pytest.mark.sim
def test_a_rescan_that_holds_no_object_ends_in_no_grasp_not_in_nothing_plannable():
    """After an empty lift the object may have left the scene (a ball squeezed out of a pinch):
    the re-scan is empty, and the machine ends in NO_GRASP, so that the grasp search's reason
    (an empty scan) is the verdict's, not "no grasp left to try"."""
    import copy

    import numpy as np

    from gbh_drake.perception.scan import ScanResult

    s = Scenario()
    machine = PickAndCarry(s.station_directives(), s.pick, s.robot.hand, settle_time=0.3,
                           max_retries=1)
    context = machine.CreateDefaultContext()
    machine.GetInputPort("scan").FixValue(context, ScanResult.empty_result("nothing there"))
    machine.GetInputPort("grasps").FixValue(context, [])
    machine.GetInputPort("panda.state").FixValue(context, np.zeros(14))
    machine.GetInputPort("hook_gripper.state").FixValue(context, np.zeros(6))
    machine.GetInputPort("hook_gripper.load").FixValue(context, np.zeros(3))
    state = context.get_mutable_abstract_state(0)
    st = copy.copy(state.get_value())
    st.status = copy.copy(st.status)
    st.status.mode, st.status.n_grasps = Mode.PLAN, 5  # grasps were offered before the re-scan
    state.set_value(st)
    machine.AFTER[Mode.PLAN](machine, context, st, 1.0)
    assert st.status.mode == Mode.NO_GRASP
