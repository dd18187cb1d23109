"""The pick motion's waypoints: symmetric closing keeps p_M, vertical closing keeps the straight rod."""

import numpy as np
import pytest
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.systems.framework import DiagramBuilder

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.planning.pick import PickParams, pick_script
from gbh_drake.station import ObjectAsset, add_station


@pytest.mark.parametrize("keep_straight_rod", [False, True])
def test_closing_keeps_the_right_point(scenario, staple_mesh, keep_straight_rod):
    asset = ObjectAsset("staple", staple_mesh, 500.0, (0.2, 0.4, 0.8, 1.0), "test")
    station = add_station(DiagramBuilder(), scenario, object_asset=asset)
    plant = station.plant
    context = plant.CreateDefaultContext()
    X_WG = RigidTransform(RotationMatrix.MakeXRotation(np.pi), [0.5, 0.05, 0.2])
    script = pick_script(station, context, X_WG, PickParams(),
                         keep_straight_rod=keep_straight_rod)
    assert script is not None
    G = plant.GetFrameByName("G", station.gripper)

    def point_W(label: str, keypoint: str) -> np.ndarray:
        i = script.labels.index(label)
        plant.SetPositions(context, station.arm, script.arm[i])
        q = script.finger[i]
        return G.CalcPoseInWorld(context).multiply(HOOK_GRIPPER.keypoints_G(q)[keypoint])

    kept = "p2" if keep_straight_rod else "pM"
    moved = "pM" if keep_straight_rod else "p2"
    np.testing.assert_allclose(point_W("close", kept), point_W("descend", kept), atol=2e-3)
    travel = HOOK_GRIPPER.q_open - HOOK_GRIPPER.q_closed
    assert np.linalg.norm(point_W("close", moved) - point_W("descend", moved)) > 0.5 * travel
