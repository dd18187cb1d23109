"""The hook gripper cages a horizontal rod and lifts it by contact alone (no weld, no attach)."""

import numpy as np
import pytest
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.systems.analysis import Simulator

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.planning.pick import PickParams, pick_script
from gbh_drake.run import build_diagram
from gbh_drake.station import ObjectAsset

ROD_HEIGHT = 0.06


def _lift(scenario, staple_mesh, *, close: bool):
    scenario.object.drop_height = 0.001
    asset = ObjectAsset("staple", staple_mesh, 500.0, (0.2, 0.4, 0.8, 1.0), "test staple")

    def script_fn(station):
        plant = station.plant
        context = plant.CreateDefaultContext()
        # Top-down: z_G = -z_W, the loop's plane normal to the rod (x_W), the rod 2.5 cm above
        # the bar and 5 mm off the loop's centre line, inside the open gap.
        R_WG = RotationMatrix(np.diag([1.0, -1.0, -1.0]))
        p_WRod = station.X_WO_initial.translation() + [0, 0, ROD_HEIGHT - 0.001]
        p_GRod = np.array([0.0, 0.005, HOOK_GRIPPER.finger_length - 0.025])
        X_WG = RigidTransform(R_WG, p_WRod - R_WG.matrix() @ p_GRod)
        script = pick_script(station, context, X_WG, PickParams(hold_time=0.5), wait=0.3)
        assert script is not None, "IK failed for the test grasp"
        if not close:  # the control: same motion, fingers never close
            script.finger = [HOOK_GRIPPER.q_open] * len(script.finger)
        return script

    built = build_diagram(scenario, script_fn, object_asset=asset)
    station, script = built.station, built.script
    simulator = Simulator(built.diagram)
    plant = station.plant
    context = plant.GetMyContextFromRoot(simulator.get_mutable_context())
    body = station.object_body()
    z0 = plant.EvalBodyPoseInWorld(context, body).translation()[2]
    simulator.AdvanceTo(script.time_of("lift"))
    z_lift = plant.EvalBodyPoseInWorld(context, body).translation()[2]
    simulator.AdvanceTo(script.end_time)
    z_end = plant.EvalBodyPoseInWorld(context, body).translation()[2]
    return body, z0, z_lift, z_end


@pytest.mark.parametrize("close", [True, False], ids=["closed_hook", "open_control"])
def test_hook_lifts_rod_only_when_closed(scenario, staple_mesh, close):
    body, z0, z_lift, z_end = _lift(scenario, staple_mesh, close=close)
    assert body.is_floating_base_body(), "the object must be a free body (never welded)"
    if close:
        # Lifted by (almost) the full 15 cm, and still there after the hold.
        assert z_lift - z0 > 0.10
        assert z_end - z0 > 0.10
    else:
        assert z_end - z0 < 0.01
