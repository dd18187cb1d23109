"""The frame contract: where G is on the flange, read from the station's own model, is the
number the geometry module gives (one home for the palm offset and the hand's mount), and the
station's base frame B is the world."""

import numpy as np

from gbh_drake.core.gripper import HOOK_GRIPPER, X_B_link8, X_link8_G, p_G_hook
from gbh_drake.modeling.robot_frames import robot_frames_of
from gbh_drake.scenario.schema import default_directives


def test_the_station_mounts_the_gripper_where_the_geometry_module_says():
    frames = robot_frames_of(default_directives())
    np.testing.assert_allclose(frames.X_link8_G, X_link8_G(), atol=1e-12)
    # The numbers of the contract: G is 5.84 cm along the flange's z, turned -45 deg about it.
    np.testing.assert_allclose(X_link8_G()[:3, 3], [0.0, 0.0, 0.0584], atol=1e-12)
    x_G_in_link8 = X_link8_G()[:3, 0]
    np.testing.assert_allclose(x_G_in_link8, [np.sqrt(0.5), -np.sqrt(0.5), 0.0], atol=1e-12)


def test_the_station_base_frame_is_the_world():
    np.testing.assert_allclose(robot_frames_of(default_directives()).X_WB, np.eye(4), atol=0)


def test_a_grasp_puts_the_flange_back_along_the_approach():
    """A top-down grasp (z_G = -z_B) with G at 10 cm height puts the flange 5.84 cm above G, its
    z down as G's; the hook point T is 8 cm below G."""
    X_BG = np.eye(4)
    X_BG[:3, :3] = np.diag([1.0, -1.0, -1.0])
    X_BG[:3, 3] = [0.5, 0.0, 0.10]
    X_flange = X_B_link8(X_BG)
    np.testing.assert_allclose(X_flange[:3, 3], [0.5, 0.0, 0.10 + HOOK_GRIPPER.palm_offset_in_hand])
    np.testing.assert_allclose(X_flange[:3, 2], [0.0, 0.0, -1.0], atol=1e-12)
    np.testing.assert_allclose(X_BG[:3, :3] @ p_G_hook() + X_BG[:3, 3], [0.5, 0.0, 0.02])
