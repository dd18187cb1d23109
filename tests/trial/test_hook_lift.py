"""The hook gripper cages a horizontal rod and lifts it by contact alone (no weld, no attach).

A grasp of one's own goes through the same machine, physics and judge as GbH's; the control
closes the same loop just above the rod and must lift nothing."""

from dataclasses import dataclass

import numpy as np
import pytest
from pydrake.math import RigidTransform, RotationMatrix

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.trial import build_trial, simulate_trial

pytestmark = pytest.mark.sim

ROD_HEIGHT = 0.06


@dataclass
class Grasp:
    X_WG: np.ndarray
    kind: str = "parallel"


def _pick(scenario, staple_mesh, rod_depth: float):
    """Top-down (z_G = -z_W), the loop's plane normal to the rod (x_W), the rod ``rod_depth``
    short of the bar's centre line along z_G (negative: beyond the bar)."""
    scenario.object.mesh = "staple.obj"
    staple_mesh.export(scenario.directory / "staple.obj")
    scenario.settle_time = 0.2
    R_WG = RotationMatrix(np.diag([1.0, -1.0, -1.0]))
    p_WRod = np.asarray(scenario.object.pose.translation) + [0.0, 0.0, ROD_HEIGHT]
    p_GRod = np.array([0.0, 0.0, HOOK_GRIPPER.finger_length - rod_depth])
    X_WG = RigidTransform(R_WG, p_WRod - R_WG.matrix() @ p_GRod)
    trial = build_trial(scenario, grasps=[Grasp(X_WG.GetAsMatrix4())])
    assert trial.station.plant.GetBodyByName(trial.station.object_name).is_floating_base_body()
    _, record = simulate_trial(trial)
    return record


@pytest.mark.trial
@pytest.mark.parametrize(("rod_depth", "caged"), [(0.025, True), (-0.012, False)],
                         ids=["rod_in_the_loop", "loop_above_the_rod"])
def test_hook_lifts_the_rod_only_when_it_is_in_the_loop(scenario, staple_mesh, rod_depth, caged):
    record = _pick(scenario, staple_mesh, rod_depth)
    assert record.grasp_rank == 0, record.reason
    if caged:
        assert record.success and record.held_by == "cage", record.reason
        assert record.verdict.max_clearance > 0.04
    else:
        assert not record.success and record.outcome == "not_lifted", record.reason
        assert record.verdict.max_clearance < 0.01
