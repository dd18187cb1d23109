"""The lift allows for the unseen space (planning/pick.py ``unseen_lift``): clearing the scan's
points and the unseen cells clears their union however the object turns, a rigid hold lifts its
lowest cell, no unseen space asks for nothing (tests/perception/test_unseen_space.py: a real scan)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gbh_drake.core.hanging_pose import rest_on_loop
from gbh_drake.core.results import PARALLEL
from gbh_drake.core.unseen import farthest_distance
from gbh_drake.planning.pick import unseen_lift
from tests.core.test_hanging_pose import _ring, _top_down

CLEARANCE = 0.05


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31 - 1), st.floats(0.1, 0.9))
def test_clearing_the_scan_and_the_unseen_cells_clears_both(seed, share):
    """Whatever part of a hooked ring (and its tail) a view missed: the larger of the scan's
    bound and the unseen cells' lift is the lift the whole object's points need."""
    rng = np.random.default_rng(seed)
    ring = _ring(np.array([0.5, 0.0, 0.15]), 0.02)
    tail = rng.uniform([0.45, -0.03, 0.02], [0.6, 0.03, 0.12], (200, 3))
    points = np.concatenate([ring, tail])
    seen = rng.random(len(points)) < share
    seen[: len(ring)] = True  # the hooked ring is seen (the grasp is on it)
    rest = rest_on_loop(points[seen], points[seen].mean(axis=0), _top_down([0.5, 0.0, 0.17]),
                        PARALLEL)
    need_scan = CLEARANCE - rest.lowest_any_turn
    need = max(need_scan, unseen_lift(points[~seen], rest, CLEARANCE))
    sunk = points - np.array([0.0, 0.0, rest.drop])
    whole = CLEARANCE - (rest.contact_W[2] - farthest_distance(sunk, rest.contact_W))
    assert need == pytest.approx(whole, abs=1e-12)


def test_a_rigid_hold_lifts_the_lowest_unseen_cell_and_no_cells_ask_for_nothing():
    cells = np.array([[0.5, 0.0, 0.03], [0.5, 0.1, 0.01]])
    assert unseen_lift(cells, None, CLEARANCE) == pytest.approx(0.04)
    assert unseen_lift(np.zeros((0, 3)), None, CLEARANCE) == float("-inf")
