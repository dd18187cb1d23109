"""tools/reach_bound.py: the most any hook grasp could carry on an experiment's poses."""

import importlib.util
import json
from pathlib import Path

ROOT = Path(__file__).parents[2]
spec = importlib.util.spec_from_file_location("reach_bound", ROOT / "tools" / "reach_bound.py")
reach_bound = importlib.util.module_from_spec(spec)
spec.loader.exec_module(reach_bound)
FOLDER = ROOT / "docs" / "experiment" / "seen_g10_own"


def committed_row(name: str, trial: int, protocol: str) -> dict:
    for line in (FOLDER / "trials.jsonl").open():
        row = json.loads(line)
        if (row["object"], row["trial"], row["protocol"], row["method"]) == \
                (name, trial, protocol, "gbh-10"):
            return row
    raise LookupError((name, trial, protocol))


def test_a_ring_lying_flat_is_out_of_reach_and_an_upright_mug_is_not():
    experiment = str(FOLDER / "experiment.yaml")
    ring = reach_bound.true_reach((experiment, committed_row("key_ring", 0, "natural"), 0.0))
    assert ring["class"] == "out of reach"  # its bar cannot pass under a ring on the table
    mug = reach_bound.true_reach((experiment, committed_row("mug_classic", 0, "natural"), 0.0))
    assert mug["class"] == "reachable" and mug["ground_mm"] > 0.0


def test_the_bound_counts_only_trials_proved_out_of_reach():
    rows = [{"protocol": "natural", "success": s} for s in (True, False, False, False)] + \
        [{"protocol": "stable", "success": False}]
    searched = [{"protocol": "natural", "class": c}
                for c in ("out of reach", "no structure", "reachable")] + \
        [{"protocol": "stable", "class": "out of reach"}]
    assert reach_bound.bounds(rows, searched) == {"natural": (1, 4, 1), "stable": (0, 1, 1)}


def test_the_object_is_where_it_rested_when_planned_not_where_it_started():
    row = committed_row("mug_square_handle", 3, "stable")
    rest = reach_bound.rest_pose(row)
    assert rest == row["record"]["verdict"]["planned_poses"][0]
    assert 0.001 < row["pose"][2] - rest[2] < 0.003  # dropped from 2 mm above its rest
    assert reach_bound.rest_pose({"pose": [1, 2, 3, 0, 0, 0]}) == [1, 2, 3, 0, 0, 0]
