"""Every failed trial gets exactly one cause class, from its row alone (made-up rows)."""

import pytest

from gbh_drake.experiment.taxonomy import CAUSES, EDGE_WARNINGS, RESERVED, cause_of


def row(outcome, *, refusals=None, scan_warnings=(), success=False, reach=None,
        rejected_by=None):
    r = {"object": "mug", "method": "gbh-10", "trial": 0, "outcome": outcome,
         "success": success, "refusals": refusals or {},
         "record": {"scan_warnings": list(scan_warnings), "refusals": refusals or {}}}
    if reach is not None:
        r["reach"] = reach
    if rejected_by is not None:
        r["record"]["rejected_by"] = rejected_by
    return r


def reach(scan, true):
    return {"scan": scan, "true": true, "best_margin_mm": -1.1, "scan_best_margin_mm": -1.1,
            "poses": 20000, "seconds": 2.0}


#: A row's rejected_by, rules in the order they apply.
REJECTED = {"collision N_c": 600, "closing sweep": 100, "table clearance": 20}


EDGE = ("the object reaches the edge of the region framed by the first look (+x, top of "
        "[0.2, 0.0, -0.05]-[0.45, 0.27, 0.15] m (W)): it may be larger than the first look saw")
BORDER = ("the object reaches the image border in 2 of the views ([2, 7]): part of it may be out "
          "of view and missing")


@pytest.mark.parametrize("r, cause", [
    (row("no_hangable_structure"), "no structure"),
    (row("no_grasp_found"), "no grasp found"),
    (row("no_reachable_grasp", refusals={"ik:grasp": 8}), "IK"),
    (row("no_reachable_grasp", refusals={"ik:lift": 1, "planner:transfer": 3}), "planner"),
    (row("no_reachable_grasp", refusals={"approach:grasp": 3, "ik:grasp": 4, "ik:lift": 2,
                                         "ik:place": 1}), "IK"),
    (row("no_reachable_grasp", refusals={"collision:descend": 1}), "planner"),
    (row("no_reachable_grasp", refusals={"ik:grasp": 1, "approach:grasp": 1}), "IK"),  # a tie
    (row("no_reachable_grasp"), "IK"),
    (row("not_lifted"), "lift too low"),
    (row("dropped_during_carry"), "slipped during carry"),
    (row("dropped_during_lift"), "slipped during carry"),
    (row("empty_scan"), "scan cut/partial"),
    (row("no_grasp_found", scan_warnings=[EDGE]), "scan cut/partial"),
    (row("no_reachable_grasp", refusals={"ik:place": 1}, scan_warnings=[BORDER]),
     "scan cut/partial"),
    (row("not_lifted", scan_warnings=[EDGE]), "lift too low"),  # executed: its physical cause
    (row("no_hangable_structure", scan_warnings=["the object's bounding sphere (radius 0.3 m) "
                                                 "needs views from 1.2 m"]), "no structure"),
    # Out of reach on the true mesh, whatever the scan; missed: a pose on both meshes.
    (row("no_grasp_found", reach=reach("out of reach", "out of reach")), "out of reach"),
    (row("no_grasp_found", reach=reach("reachable", "out of reach")), "out of reach"),
    (row("no_grasp_found", reach=reach("reachable", "reachable")), "candidate set missed"),
    # Reachable on the true mesh only: lost in the scan, the rules say which removed it.
    (row("no_grasp_found", reach=reach("out of reach", "reachable"), rejected_by=REJECTED),
     "table clearance"),
    (row("no_grasp_found", reach=reach("no structure", "reachable")), "no grasp found"),
    # Undecided (or no structure on the true mesh): the last rule that removed candidates.
    (row("no_grasp_found", reach=reach("reachable", "undecided"), rejected_by=REJECTED),
     "table clearance"),
    (row("no_grasp_found", reach=reach("reachable", "no structure"),
         rejected_by={"collision N_c": 700, "closing sweep": 20, "table clearance": 0}),
     "closing sweep"),
    (row("no_grasp_found", rejected_by={"collision N_c": 720, "closing sweep": 0,
                                        "table clearance": 0}), "collision N_c"),
    (row("no_grasp_found", reach={"error": "ValueError: x"}, rejected_by={}), "no grasp found"),
    (row("no_grasp_found", scan_warnings=[EDGE], reach=reach("reachable", "reachable")),
     "scan cut/partial"),
    (row("no_grasp_found", scan_warnings=[EDGE], reach=reach("reachable", "out of reach")),
     "out of reach"),
    (row("error"), "error"),
    (row("incomplete"), "error"),
    (row("success", success=True), ""),
])
def test_cause_of(r, cause):
    assert cause_of(r) == cause
    assert cause == "" or cause in CAUSES and cause not in RESERVED


def test_refusals_are_read_from_the_record_when_the_row_has_none():
    r = row("no_reachable_grasp", refusals={"planner:transfer": 2})
    r["refusals"] = {}
    assert cause_of(r) == "planner"


def test_every_failing_outcome_has_a_class_and_an_unknown_one_raises():
    from gbh_drake.messages import Outcome

    for outcome in Outcome:
        if outcome != Outcome.SUCCESS:
            assert cause_of(row(str(outcome))) in CAUSES
    with pytest.raises(ValueError, match="'teleported'.*mug/gbh-10/0"):
        cause_of(row("teleported"))


def test_the_edge_warnings_are_the_scans():
    from gbh_drake.perception.scan import FRAME_EDGE_WARNING

    assert FRAME_EDGE_WARNING in EDGE_WARNINGS
    assert len(set(CAUSES)) == len(CAUSES) == 16 and set(RESERVED) <= set(CAUSES)


def test_nothing_is_reserved_and_the_rules_are_classes():
    from gbh_drake.experiment.taxonomy import REJECTION_RULES

    assert RESERVED == ()
    assert set(REJECTION_RULES) <= set(CAUSES)
