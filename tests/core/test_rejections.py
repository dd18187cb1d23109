"""The count of what each collision rule removed (core/rejections.py), on the pipeline's own
candidates and as a property of the rules."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.core.rejections import ALL_RULES, RULES, closest_rejected, count_rejections
from gbh_drake.core.results import GraspCandidate, GraspKind, HangingStructure
from gbh_drake.core.scoring import collision_free

_S = HangingStructure(np.zeros(3), np.array([0, 0, 1.0]), np.zeros((3, 3)), 1.0, np.zeros(3))


def _candidate(n_c, n_s, height, rods=-1, loop=-1, kind="parallel"):
    g = GraspCandidate(np.eye(4), GraspKind(kind), 0, _S, np.zeros(3))
    g.n_collisions, g.n_sweep_collisions, g.ground_distance = n_c, n_s, height
    g.rod_contacts, g.loop_material = rods, loop
    return g


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(-1, 6), st.integers(-1, 6),
                          st.floats(-0.02, 0.02) | st.just(float("nan")), st.integers(-1, 3),
                          st.integers(-1, 2)),
                max_size=30),
       st.integers(1, 4), st.integers(1, 4), st.sampled_from([-1.0, 0.0, 0.003]),
       st.sampled_from([-1.0, 0.0025]), st.booleans())
def test_the_counts_add_up_to_the_candidates_that_fail(rows, p_c, p_sweep, clearance, rod,
                                                       loop):
    """Every candidate is either passed or removed by exactly one rule, and the passed ones are
    exactly those collision_free accepts; the last rule is the last with a nonzero count."""
    params = GbhParams(p_c=p_c, p_sweep=p_sweep, ground_clearance=clearance, rod_clearance=rod,
                       loop_must_enclose=loop)
    candidates = [_candidate(*r) for r in rows]
    r = count_rejections(candidates, params)
    expected = [*RULES, *(["rod clearance"] if rod >= 0 else []), *(["empty loop"] if loop else [])]
    assert list(r.removed) == expected and set(expected) <= set(ALL_RULES)
    assert r.passed == sum(collision_free(g, params) for g in candidates)
    assert r.passed + sum(r.removed.values()) == len(candidates)
    nonzero = [rule for rule, n in r.removed.items() if n]
    assert r.last_rule == (nonzero[-1] if nonzero else "")
    assert bool(r.closest) == bool(nonzero)


def test_a_mug_standing_on_a_table_below_the_gripper_is_removed_by_the_table(mug):
    """The pipeline's own candidates on a mug whose table is above its top: every candidate
    that passes N_c and the sweep is removed by the table, the closest one named."""
    top = float(mug.bounds[1, 2])
    params = GbhParams(ground_height=top + 0.05)
    result = plan_grasps(mug, params, seed=0)
    r = count_rejections(result.candidates, params)
    assert not result.ranked and r.passed == 0
    assert r.last_rule == "table clearance" and r.removed["table clearance"] > 0
    assert r.closest.startswith("closest: a ") and "short of the 3.0 mm clearance" in r.closest
    free = count_rejections(result.candidates, GbhParams(ground_clearance=-1.0))
    assert free.removed["table clearance"] == 0 and free.passed > 0


def test_the_closest_refused_candidates_passed_the_most_rules():
    params = GbhParams(p_c=1, p_sweep=1, ground_clearance=0.003)
    n_c, sweep, low, lower, ok = (_candidate(4, 0, 0.1), _candidate(0, 3, 0.1),
                                  _candidate(0, 0, 0.002), _candidate(0, 0, -0.01),
                                  _candidate(0, 0, 0.01))
    assert closest_rejected([n_c, sweep, lower, ok, low], params, k=3) == [low, lower, sweep]
    assert closest_rejected([ok], params) == []


def _posed(n_c, n_s, height, p, yaw_deg=0.0):
    g = _candidate(n_c, n_s, height)
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    g.X_WG = np.eye(4)
    g.X_WG[:2, :2] = [[c, -s], [s, c]]
    g.X_WG[:3, 3] = p
    return g


def test_the_nearest_refused_candidates_are_the_nearest_in_pose_with_their_rule():
    """Refused candidates are ordered by distance plus ANGLE_WEIGHT x angle from the grasp;
    passed ones are never listed; each comes with its rule and the words that say why."""
    from gbh_drake.core.rejections import ANGLE_WEIGHT, nearest_refused

    params = GbhParams(p_c=1, p_sweep=1, ground_clearance=0.003)
    near = _posed(3, 0, 0.1, [0.01, 0, 0])                 # N_c, 1 cm away
    turned = _posed(0, 2, 0.1, [0.005, 0, 0], yaw_deg=20)  # the sweep, 5 mm but turned 20 deg
    far = _posed(0, 0, 0.001, [0.05, 0, 0])                # the table, 5 cm away
    ok = _posed(0, 0, 0.01, [0.0, 0, 0])                    # passed: not listed
    found = nearest_refused([far, turned, ok, near], params, np.eye(4), k=3)
    assert [r.candidate for r in found] == [near, turned, far]
    assert 0.01 < 0.005 + ANGLE_WEIGHT * np.radians(20) < 0.05  # (the turned one: second)
    assert [r.rule for r in found] == ["collision N_c", "closing sweep", "table clearance"]
    assert found[0].words == "a parallel grasp with 3 points inside the open gripper, p_c = 1"
    assert "1.0 mm above the table, 2.0 mm short of the 3.0 mm clearance" in found[2].words
    assert nearest_refused([ok], params, np.eye(4)) == []
    assert len(nearest_refused([far, turned, near], params, np.eye(4), k=1)) == 1
