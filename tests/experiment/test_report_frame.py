"""The report's one frame (typed columns, read once), the object facts it takes from
``object_tags``, the borderline successes and the plots' colours."""

from __future__ import annotations

from math import pi
from pathlib import Path

import pandas as pd
import pytest
from test_rows_report import flat, make_row

from gbh_drake.experiment.report import (
    COLUMNS,
    ReportInput,
    beyond,
    borderline,
    frame_of,
    object_tags,
    per_object_detail,
    read_input,
    trials_frame,
)
from gbh_drake.experiment.report.plots import CAUSE_COLOURS
from gbh_drake.experiment.taxonomy import CAUSES

REFERENCE = Path(__file__).parents[2] / "docs" / "experiment"


def _input(rows, methods=("gbh+",), objects=None) -> ReportInput:
    objects = objects or list(dict.fromkeys(r["object"] for r in rows))
    return ReportInput(name="x", objects=objects, methods=list(methods), trials=5, paper={},
                       rows=rows)


def test_every_column_is_documented_and_typed():
    names = [c.name for c in COLUMNS]
    assert len(names) == len(set(names))
    assert all(c.meaning and c.dtype in ("string", "Int64", "Float64", "boolean", "object")
               for c in COLUMNS)
    frame = frame_of([make_row("kettle", "gbh-10", 0), {"object": "box", "method": "m",
                                                        "trial": 1, "seed": 2, "outcome": "x",
                                                        "success": False, "reason": "",
                                                        "viewpoints": 1}])
    assert list(frame.columns) == names
    assert {c.name: c.dtype for c in COLUMNS} == {k: str(v) for k, v in frame.dtypes.items()}
    older = frame.iloc[1]  # a row without most fields: typed missing values, no error
    assert pd.isna(older.grasp_score) and pd.isna(older.sank_at) and older.protocol == "stable"


def test_object_facts_come_from_the_rows_tags_else_the_built_in_lists():
    cup = make_row("my_cup", "gbh+", 0)
    cup["object_tags"] = ["cup"]
    widget = make_row("my_widget", "gbh+", 0, "no_hangable_structure")
    widget["record"].update(true_parts=0)
    mug, box = make_row("mug_classic", "gbh+", 0), make_row("box", "gbh+", 0, control=True)
    mug["record"]["true_parts"] = 1
    tags = object_tags([cup, widget, mug, box])
    assert tags == {"my_cup": {"cup"}, "my_widget": {"unknown"}, "mug_classic": {"cup"},
                    "box": {"control"}}
    # the ground-truth columns of an object without facts read "unknown", never an error
    detail = flat(per_object_detail(_input([widget])))
    assert "| my_widget | gbh+ | 1 | unknown | unknown |" in detail


def test_a_set_object_without_hangable_parts_reads_unknown_in_the_ground_truth_columns():
    # A set's rows always carry object_tags (an entry without tags: []); an entry without
    # hangable_parts (true_parts 0) that is no control has no ground truth: "unknown", as the
    # docs say (it read "-", as if nothing were to be found), tagged or not; a control reads "-".
    ring = make_row("ring", "gbh-10", 0, "no_grasp_found")
    ring.update(object_tags=[], is_control=False)
    cup = make_row("my_cup", "gbh-10", 0, "no_grasp_found")
    cup.update(object_tags=["cup"], is_control=False)
    block = make_row("block", "gbh-10", 0, "no_hangable_structure", control=True)
    block["object_tags"] = []
    mug = make_row("my_mug", "gbh-10", 0, "no_grasp_found")
    mug["object_tags"] = ["cup"]
    for row, parts in ((ring, 0), (cup, 0), (block, 0), (mug, 1)):
        row["record"].update(true_parts=parts, true_part_found=None, grasped_true_part=None)
    mug["record"]["true_part_found"] = True
    detail = flat(per_object_detail(_input([ring, cup, block, mug], methods=("gbh-10",))))
    assert "| ring | gbh-10 | 1 | unknown | unknown |" in detail
    assert "| my_cup | gbh-10 | 1 | unknown | unknown |" in detail
    assert "| block | gbh-10 | 1 | - | - |" in detail
    assert "| my_mug | gbh-10 | 1 | 1/1 | - |" in detail


def test_a_cup_of_a_users_set_lying_on_its_side_is_beyond_the_loops_reach():
    rows = [make_row("my_cup", "gbh+", t) for t in range(2)]
    for r in rows:
        r.update(object_tags=["cup"], grasp_method="gbh_plus")
    rows[0]["pose"] = [0.5, 0.0, 0.05, pi / 2, 0.0, 0.0]  # on its side; rows[1] upright
    text = flat(beyond(_input(rows)))
    assert "| gbh+ | 1 | 1 (100.0 %) | 1 |" in text and "cups (my_cup)" in text


def _borderline_rows():
    rows = [make_row("kettle", "gbh+", t) for t in range(4)]
    verdicts = [{"sank_phase": "carry", "sank_at": 12.5, "table_touch_while_carried": True,
                 "min_clearance_after_lift": 0.004, "min_clearance_phase": "carry"},
                {"sank_phase": "lift", "sank_at": 6.0, "table_touch_while_carried": False},
                {"sank_phase": "cage_test", "sank_at": 20.0},  # after success was decided
                {"sank_phase": "", "table_touch_while_carried": False}]
    for r, verdict in zip(rows, verdicts, strict=True):
        r["record"]["verdict"] = verdict
    return rows


def test_borderline_successes_are_listed_with_how_low_they_came():
    data = _input(_borderline_rows())
    text = flat(borderline(data))
    assert "| gbh+ | 4 | 2 | 1 | 0.4 cm |" in text
    assert "| kettle | gbh+ | 0 | cage | carry | 12.50 | yes | 0.4 cm (carry) |" in text
    assert "| kettle | gbh+ | 1 | cage | lift | 6.00 | no | unknown |" in text
    assert "2 of 4 successes" in text and "1 successes came down during the cage test" in text
    csv = trials_frame(data)
    assert csv.borderline_success.tolist() == [True, True, False, False]
    assert csv.min_clearance_after_lift.tolist()[0] == pytest.approx(0.004)


def test_the_reference_experiment_has_4_borderline_successes_and_none_touched_the_table():
    """4 successes in which the object came back below 1 cm while still held, none touching the
    table: since the judge's ``touched_down`` such a trial is no success (6 trials of
    docs/experiment's rows)."""
    frame = read_input(REFERENCE).frame
    down = frame[frame.borderline_success]
    assert len(down) == 4 and down.success.all()
    assert set(down.sank_phase) <= {"lift", "carry"}
    assert int(frame.table_touch_while_carried[frame.success].sum()) == 0
    assert int((frame.outcome == "touched_down").sum()) == 6


def test_each_cause_has_a_colour_of_its_own():
    assert set(CAUSES) <= set(CAUSE_COLOURS)
    assert len(set(CAUSE_COLOURS.values())) == len(CAUSE_COLOURS)
