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


def _candidate(n_c, n_s, height, rods=-1, kind="parallel"):
    g = GraspCandidate(np.eye(4), GraspKind(kind), 0, _S, np.zeros(3))
    g.n_collisions, g.n_sweep_collisions, g.ground_distance = n_c, n_s, height
    g.rod_contacts = rods
    return g


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(-1, 6), st.integers(-1, 6),
                          st.floats(-0.02, 0.02) | st.just(float("nan")), st.integers(-1, 3)),
                max_size=30),
       st.integers(1, 4), st.integers(1, 4), st.sampled_from([-1.0, 0.0, 0.003]),
       st.sampled_from([-1.0, 0.0025]))
def test_the_counts_add_up_to_the_candidates_that_fail(rows, p_c, p_sweep, clearance, rod):
    """Every candidate is either passed or removed by exactly one rule, and the passed ones are
    exactly those collision_free accepts; the last rule is the last with a nonzero count."""
    params = GbhParams(p_c=p_c, p_sweep=p_sweep, ground_clearance=clearance, rod_clearance=rod)
    candidates = [_candidate(*r) for r in rows]
    r = count_rejections(candidates, params)
    assert list(r.removed) == list(ALL_RULES if rod >= 0 else RULES)
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
