"""Where a hooked object hangs: rotations, lowest points, the lift that clears the table."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from gbh_drake.core.hanging_pose import (
    hanging_lowest_height,
    hanging_rotation,
    lift_for_clearance,
)

UP = np.array([0.0, 0.0, 1.0])
vectors = st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).map(np.array)


@given(vectors, vectors)
def test_hanging_rotation_brings_the_com_straight_below_the_hook(com, hook):
    d = com - hook
    R = hanging_rotation(com, hook, UP)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-9)
    assert np.linalg.det(R) == pytest.approx(1.0)
    if np.linalg.norm(d) > 1e-6:
        np.testing.assert_allclose(R @ d, -np.linalg.norm(d) * UP, atol=1e-9)


def test_a_stick_hooked_at_one_end_hangs_straight_down():
    """A 30 cm horizontal stick at 5 cm height, hooked at one end: it swings to hang below."""
    x = np.linspace(0.0, 0.3, 31)
    points = np.column_stack([x, np.zeros_like(x), np.full_like(x, 0.05)])
    hook = points[0]
    com = points.mean(axis=0)
    assert hanging_lowest_height(points, com, hook) == pytest.approx(0.05 - 0.3)
    assert hanging_lowest_height(points, com, hook, swings=False) == pytest.approx(0.05)
    # Clear the table by 5 cm: the hook rises 30 cm.
    assert lift_for_clearance(points, com, hook, 0.05) == pytest.approx(0.30)
    assert lift_for_clearance(points, com, hook, 0.05, swings=False) == pytest.approx(0.0)


def test_the_lift_bounds_any_way_the_object_turns():
    """A wrong centre of mass (a scan's centroid) cannot make the lift too short: the farthest
    point from the hook bounds the hanging object's lowest point."""
    rng = np.random.default_rng(0)
    points = rng.uniform([-0.1, -0.1, 0.0], [0.1, 0.1, 0.2], (500, 3))
    hook = np.array([0.0, 0.0, 0.2])
    lift = lift_for_clearance(points, points.mean(axis=0), hook, 0.05)
    for com in rng.uniform([-0.1, -0.1, 0.0], [0.1, 0.1, 0.2], (50, 3)):
        assert hanging_lowest_height(points, com, hook) + lift >= 0.05 - 1e-9
