"""Why a method had no grasp: the pure rule, and the monitor deciding the outcome from it."""

import numpy as np
import trimesh

from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import GraspCandidate, GraspKind, HangingStructure
from gbh_drake.messages import GraspSearch, Mode, Outcome, PickStatus
from gbh_drake.perception.scan import ScanResult
from gbh_drake.scenario.schema import MonitorConfig
from gbh_drake.systems.cage_monitor import Observation, _Watch, observe
from gbh_drake.systems.grasp_search import explain_no_grasp
from gbh_drake.systems.hangability_detector import Hangability
from gbh_drake.systems.scanner import no_scan

SCAN = ScanResult(trimesh.creation.box([0.05] * 3), np.zeros((1, 3)))
STRUCTURE = HangingStructure(np.zeros(3), np.array([0, 0, 1.0]), np.zeros((3, 3)), 1.0,
                             np.zeros(3))


def test_an_empty_scan_says_so_with_the_scanners_words():
    search = explain_no_grasp(no_scan("no object near scan_target"), Hangability())
    assert search == GraspSearch(Outcome.EMPTY_SCAN, "no object near scan_target")


def test_the_antipodal_sampler_alone_found_no_grasp():
    search = explain_no_grasp(SCAN)
    assert search.outcome == Outcome.NO_GRASP_FOUND and "antipodal sampler" in search.reason


def test_nothing_hangable_is_its_own_outcome_and_names_the_fallback():
    search = explain_no_grasp(SCAN, Hangability(None, [], "no hangable structure found"),
                              fallback=True)
    assert search.outcome == Outcome.NO_HANGABLE_STRUCTURE
    assert search.reason == ("no hangable structure found; the antipodal fallback found no "
                             "grasp either")


def _candidate(n_c: int, n_s: int, height: float, kind: str = "vertical") -> GraspCandidate:
    g = GraspCandidate(np.eye(4), GraspKind(kind), 0, STRUCTURE, np.zeros(3))
    g.n_collisions, g.n_sweep_collisions, g.ground_distance = n_c, n_s, height
    return g


def test_structures_without_a_grasp_count_the_candidates_each_rule_removed():
    """The reason says how many candidates there were, what each rule removed (in the order
    the rules apply) and how near the closest came to the last rule."""
    params = GbhParams(p_c=1, p_sweep=1, ground_clearance=0.003)
    candidates = [_candidate(5, 0, 0.1), _candidate(0, 2, 0.1), _candidate(0, 0, 0.0023),
                  _candidate(0, 0, -0.01, "parallel")]
    search = explain_no_grasp(SCAN, Hangability(None, [STRUCTURE, STRUCTURE], ""), candidates,
                              params=params)
    assert search.outcome == Outcome.NO_GRASP_FOUND
    assert search.reason == (
        "no collision-free grasp among 4 candidates on 2 hanging structures: N_c removed 1, "
        "the closing sweep 1, the table clearance the last 2 (closest: a vertical grasp 2.3 mm "
        "above the table, 0.7 mm short of the 3.0 mm clearance)")
    assert search.rejected_by == {"collision N_c": 1, "closing sweep": 1, "table clearance": 2,
                                  "empty loop": 0}


def test_no_candidates_at_all_is_said_without_rules():
    """One structure is said in the singular (it read '1 hanging structures')."""
    search = explain_no_grasp(SCAN, Hangability(None, [STRUCTURE], ""), [])
    assert search.reason == "no collision-free grasp among 0 candidates on 1 hanging structure"
    assert search.rejected_by == {"collision N_c": 0, "closing sweep": 0, "table clearance": 0,
                                  "empty loop": 0}


def test_the_monitor_decides_the_outcome_from_the_search_once():
    """With no grasp to try the verdict is the search's outcome and reason (no 'no_grasp' left
    for a record to re-judge); the outcome is an enum that compares with its value."""
    status = PickStatus(mode=Mode.NO_GRASP)
    o = Observation(t=1.0, p_WO=[0.5, 0, 0], low=0.0, gripper=set(), table=True,
                    hand=np.zeros(6), squeeze=0.0)
    search = GraspSearch(Outcome.NO_HANGABLE_STRUCTURE, "no hangable structure found")
    v = observe(_Watch(), status, o, MonitorConfig(), search=search).verdict
    assert v.outcome is Outcome.NO_HANGABLE_STRUCTURE and v.outcome == "no_hangable_structure"
    assert v.reason == "no hangable structure found" and not v.success
    unexplained = observe(_Watch(), status, o, MonitorConfig()).verdict
    assert unexplained.outcome is Outcome.NO_GRASP_FOUND
