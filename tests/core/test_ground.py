"""Grasps that would put the gripper through the supporting surface are not ranked."""

import numpy as np
import pytest
from gbh_shapes import make_mug, make_ring

from gbh_drake.core.collision import ground_penetration
from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps


def test_penetration_of_known_poses():
    """Top-down gripper (z_G = -z_W) with its fingertips' lowest corner at a known height."""
    R = np.diag([1.0, -1.0, -1.0])
    lowest_G = HOOK_GRIPPER.finger_length + HOOK_GRIPPER.rod_width / 2  # rod ends past p2
    X = np.eye(4)
    X[:3, :3] = R
    for tip_height in (0.05, 0.0, -0.004):
        X[2, 3] = tip_height + lowest_G
        depth = ground_penetration(X[None], np.array([0, 0, 1.0]), 0.0)[0]
        assert depth == pytest.approx(-tip_height, abs=1e-9)


def _on_table(mesh):
    mesh = mesh.copy()
    mesh.apply_translation([0, 0, -mesh.bounds[0, 2]])
    return mesh


def test_flat_ring_on_the_table_has_no_grasp_through_the_table():
    ring = _on_table(make_ring())
    off = plan_grasps(ring, GbhParams(ground_margin=-1.0))
    on = plan_grasps(ring, GbhParams())
    # Without the check the best grasps put rods under the ring, i.e. into the table.
    assert any(g.ground_penetration > 0.001 for g in off.ranked)
    assert all(g.ground_penetration <= 0.001 for g in on.ranked)


def test_upright_mug_keeps_its_top_down_grasps():
    on = plan_grasps(_on_table(make_mug()), GbhParams())
    assert on.ranked, "the handle is above the table: its grasps stay"
    assert all(g.ground_penetration <= 0.001 for g in on.ranked)
