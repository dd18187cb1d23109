"""A pinched object pivots about the pinch axis (core/pinch.py): where it swings to, how low
it goes, and which pinches turn it least; checked on a tall bottle-like cylinder whose answers
follow from its dimensions."""

import numpy as np
import pytest
import trimesh

from gbh_drake.core.pinch import (
    DROP_STEP,
    lowest_any_turn,
    pinch_swing,
    swing_angles,
    swing_drops,
)

HEIGHT, RADIUS = 0.25, 0.035


@pytest.fixture
def bottle():
    """A cylinder standing on z = 0 (points: its vertices), its CoM in its middle."""
    mesh = trimesh.creation.cylinder(radius=RADIUS, height=HEIGHT, sections=32)
    mesh.apply_translation([0.0, 0.0, 0.5 * HEIGHT])
    return np.asarray(mesh.vertices), np.array([0.0, 0.0, 0.5 * HEIGHT])


def test_pinched_above_its_centre_of_mass_it_hangs_as_it_stood(bottle):
    points, com = bottle
    s = pinch_swing(points, com, [0.0, 0.0, 0.20], [1.0, 0.0, 0.0])
    assert s.swing == pytest.approx(0.0, abs=1e-9)
    assert s.lowest == pytest.approx(0.0, abs=1e-9)  # as rigid: the bottom stays put
    assert s.com_W == pytest.approx(com)
    # Any turn: the bottom's rim, 20 cm below and 3.5 cm aside of the axis, straight below it.
    assert s.lowest_any_turn == pytest.approx(0.20 - np.hypot(0.20, RADIUS), abs=1e-6)


def test_pinched_below_it_the_bottle_turns_over(bottle):
    """Issue 42: a tall bottle pinched near its base swings upside down about the pinch axis:
    its top hangs 22 cm below the axis, 19 cm lower than a rigid hold predicts (which kept the
    bottom 3 cm below it)."""
    points, com = bottle
    s = pinch_swing(points, com, [0.0, 0.0, 0.03], [1.0, 0.0, 0.0])
    assert abs(s.swing) == pytest.approx(np.pi)
    assert s.lowest == pytest.approx(0.03 - (HEIGHT - 0.03), abs=1e-6)
    assert s.com_W[2] == pytest.approx(0.03 - (0.5 * HEIGHT - 0.03))
    assert s.lowest_any_turn <= s.lowest + 1e-9


def test_a_sideways_lever_swings_it_a_quarter_turn():
    points = np.array([[0.0, 0.0, 0.0], [0.10, 0.0, 0.0]])
    s = pinch_swing(points, [0.10, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    assert s.swing == pytest.approx(0.5 * np.pi)  # about +y: +x turns to -z
    assert s.com_W == pytest.approx([0.0, 0.0, -0.10])
    assert s.lowest == pytest.approx(-0.10)


def test_a_vertical_axis_turns_nothing_down():
    points = np.array([[0.05, 0.0, 0.0], [0.0, 0.0, 0.2]])
    s = pinch_swing(points, [0.05, 0.0, 0.1], [0.0, 0.0, 0.1], [0.0, 0.0, 1.0])
    assert s.swing == 0.0 and s.lowest == 0.0 and s.lowest_any_turn == pytest.approx(0.0)
    assert lowest_any_turn(np.zeros((0, 3)), [0, 0, 0], [1, 0, 0]) == np.inf


def test_swing_angles_rank_pinches_above_the_centre_of_mass_first(bottle):
    _, com = bottle
    heights = np.array([0.03, 0.10, 0.125, 0.20, 0.24])
    points = np.stack([np.zeros(5), np.full(5, 0.01), heights], axis=1)
    angles = np.abs(swing_angles(points, np.tile([1.0, 0.0, 0.0], (5, 1)), com))
    # 1 cm aside of the CoM's vertical: above it a few degrees, below it nearly a half turn.
    assert np.degrees(angles) == pytest.approx(
        np.degrees([np.pi - np.arctan(0.01 / 0.095), np.pi - np.arctan(0.01 / 0.025),
                    0.5 * np.pi, np.arctan(0.01 / 0.075), np.arctan(0.01 / 0.115)]))
    assert list(np.argsort(angles)) == [4, 3, 2, 1, 0]
    one = pinch_swing(np.zeros((1, 3)), com, points[1], [1.0, 0.0, 0.0]).swing
    assert np.abs(one) == pytest.approx(angles[1])


def test_swing_drops_weigh_the_swing_by_the_lever(bottle):
    _, com = bottle
    points = np.array([[0.0, 0.0, 0.20], [0.0, 0.0, 0.124], [0.0, 0.0, 0.03],
                       [0.0, 0.05, 0.125]])
    drops = swing_drops(points, np.tile([1.0, 0.0, 0.0], (4, 1)), com)
    # Above: none; 1 mm below: twice the lever, 2 mm; near the base: 19 cm; level, 5 cm aside:
    # a quarter turn, the lever.
    assert drops == pytest.approx([0.0, 0.002, 0.19, 0.05], abs=1e-9)
    assert swing_drops(points[:1], [[0.0, 0.0, 1.0]], com)[0] == 0.0  # a vertical axis


def test_the_sampler_ranks_the_pinches_that_hang_first_when_asked():
    """A tall rod (4 cm across, 25 cm) pinched along its side: the baseline's cost takes the
    pinches nearest the height of its centre of mass, above it and below it alike (a pinch half
    a centimetre below lets the CoM fall a centimetre as the rod turns over); with
    ``prefer_hanging`` the fall of the CoM (in steps) never increases down the same list."""
    from gbh_drake.core.antipodal import sample_antipodal_grasps
    from gbh_drake.core.params import AntipodalParams

    rod = trimesh.creation.cylinder(radius=0.02, height=0.25, sections=32)
    rod.apply_translation([0.5, 0.0, 0.125])
    com = np.array([0.5, 0.0, 0.125])

    def drops(**kwargs):
        grasps = sample_antipodal_grasps(rod, AntipodalParams(top_k=40, **kwargs), rng=1)
        mids = np.array([0.5 * (g.p_WA + g.p_WB) for g in grasps])
        axes = np.array([g.X_WG[:3, 1] for g in grasps])
        return np.round(swing_drops(mids, axes, com) / DROP_STEP)

    plain, hanging = drops(), drops(prefer_hanging=True)
    assert list(plain) != sorted(plain) and plain.max() >= 1
    assert list(hanging) == sorted(hanging) and hanging[0] == 0
