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
