"""Grasps whose gripper (open, closing or closed) would come closer to the supporting surface than
``ground_clearance`` are not ranked."""

import numpy as np
import pytest
from gbh_shapes import make_mug, make_ring

from gbh_drake.core.collision import ground_distance
from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.core.results import PARALLEL, VERTICAL
from gbh_drake.core.scoring import collision_free

UP = np.array([0.0, 0.0, 1.0])


def test_ground_distance_of_known_poses():
    """Top-down gripper (z_G = -z_W) with its fingertips' lowest corner at a known height."""
    R = np.diag([1.0, -1.0, -1.0])
    lowest_G = HOOK_GRIPPER.finger_length + HOOK_GRIPPER.rod_width / 2  # rod ends past p2
    X = np.eye(4)
    X[:3, :3] = R
    for tip_height in (0.05, 0.0, -0.004):
        X[2, 3] = tip_height + lowest_G
        for kind in (PARALLEL, VERTICAL):
            height = ground_distance(X[None], kind, UP, 0.0)[0]
            assert height == pytest.approx(tip_height, abs=1e-9)
        assert ground_distance(X[None], PARALLEL, UP, 0.01)[0] == pytest.approx(tip_height - 0.01)


def test_ground_distance_covers_the_closing_sweep():
    """Closing axis +y_G pointing down: a vertical grasp's arm follows the fingers down by the
    finger travel, so its hand ends that much lower than at the grasp pose; a parallel grasp's
    hand stays, and its L finger (the lowest finger, on -y_G = up) rises."""
    X = np.eye(4)
    X[:3, :3] = np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]])  # y_G = -z_W, z_G = +y_W
    X[2, 3] = 0.5
    hand_bottom = 0.5 - HOOK_GRIPPER.hand_half_extents[1]  # hand's y half extent, downward
    travel = HOOK_GRIPPER.q_open - HOOK_GRIPPER.q_closed
    # The straight rod (at +q_open, down) reaches q_open + r below G, less than the hand.
    assert ground_distance(X[None], PARALLEL, UP, 0.0)[0] == pytest.approx(hand_bottom)
    assert ground_distance(X[None], VERTICAL, UP, 0.0)[0] == pytest.approx(hand_bottom - travel)


def _on_table(mesh):
    mesh = mesh.copy()
    mesh.apply_translation([0, 0, -mesh.bounds[0, 2]])
    return mesh


def test_flat_ring_on_the_table_has_no_grasp_through_the_table():
    ring = _on_table(make_ring())
    off = plan_grasps(ring, GbhParams(ground_clearance=-1.0))
    on = plan_grasps(ring, GbhParams())
    clearance = GbhParams().ground_clearance
    # Without the check the best grasps put rods under the ring, i.e. into the table.
    assert any(g.ground_distance < clearance for g in off.ranked)
    assert all(g.ground_distance >= clearance for g in on.ranked)


def test_upright_mug_keeps_its_top_down_grasps():
    on = plan_grasps(_on_table(make_mug()), GbhParams())
    assert on.ranked, "the handle is above the table: its grasps stay"
    assert all(g.ground_distance >= GbhParams().ground_clearance for g in on.ranked)


def test_negative_clearance_turns_the_check_off():
    # (The rods' clearance off: it is checked only for grasps that may be ranked.)
    off = GbhParams(ground_clearance=-1.0, rod_clearance=-1.0)
    result = plan_grasps(_on_table(make_ring()), off)
    below = [g for g in result.candidates if g.ground_distance < -0.01
             and g.n_collisions < 10 and g.n_sweep_collisions < 1]
    assert below
    assert all(collision_free(g, off) for g in below)
    assert not any(collision_free(g, GbhParams(rod_clearance=-1.0)) for g in below)
