"""tools/keep_rows.py: the rows a late tier cannot change are kept, with the current task's
digest, and the experiment then runs only the others."""

import importlib.util
import json
from pathlib import Path

import pytest

TOOL = Path(__file__).parents[2] / "tools" / "keep_rows.py"
spec = importlib.util.spec_from_file_location("keep_rows", TOOL)
keep_rows = importlib.util.module_from_spec(spec)
spec.loader.exec_module(keep_rows)

SOURCES = {"grasps", "scoop_grasps"}


def row(success: bool, source: str = "", control: bool = False, structures: int = 1) -> dict:
    return {"success": success, "is_control": control,
            "record": {"grasp_source": source, "n_structures": structures}}


def test_only_what_an_earlier_tier_carried_and_bare_controls_are_kept():
    assert keep_rows.unchanged(row(True, "grasps"), SOURCES)
    assert keep_rows.unchanged(row(True, "scoop_grasps"), SOURCES)
    assert not keep_rows.unchanged(row(True, "fallback_grasps"), SOURCES)  # the late tier first
    assert not keep_rows.unchanged(row(False), SOURCES)
    assert keep_rows.unchanged(row(False, control=True, structures=0), SOURCES)
    assert not keep_rows.unchanged(row(False, control=True, structures=1), SOURCES)
    # A hook after a fallback pinch came away empty: the first plan may now take the late tier.
    retried = row(True, "grasps")
    retried["record"]["attempts"] = [{"source": "fallback_grasps"}]
    assert not keep_rows.unchanged(retried, SOURCES)
    retried["record"]["attempts"] = [{"source": "grasps"}]
    assert keep_rows.unchanged(retried, SOURCES)


def test_kept_rows_get_the_tasks_digest(tmp_path):
    experiment = Path(__file__).parents[2] / "scenarios" / "experiment_small.yaml"
    tasks = keep_rows.make_tasks(keep_rows.load_experiment(experiment))
    rows = [{"object": t.object, "method": t.method, "trial": t.trial, "protocol": t.protocol,
             "scenario_digest": "old", **row(i % 2 == 0, "grasps")} for i, t in enumerate(tasks)]
    before = tmp_path / "before.jsonl"
    before.write_text("".join(json.dumps(r) + "\n" for r in rows))
    assert keep_rows.main([str(experiment), str(before), str(tmp_path / "out")]) == 0
    kept = [json.loads(line) for line in (tmp_path / "out" / "trials.jsonl").open()]
    assert len(kept) == (len(tasks) + 1) // 2
    digests = {t.key: t.digest for t in tasks}
    assert all(r["scenario_digest"] == digests[keep_rows.row_key(r)] for r in kept)
    with pytest.raises(SystemExit):  # never over a folder's rows
        keep_rows.main([str(experiment), str(before), str(tmp_path / "out")])


def test_a_screen_keeps_the_trials_it_found_unchanged_that_took_no_rescan(tmp_path):
    """``--screen``: kept only where tools/screen_rule.py found the same structures, and the
    trial met the detector once (a regrasp or a retry re-scans)."""
    key = ("mug", "gbh+", 0, "stable")
    same = {key: True, ("mug", "gbh+", 1, "stable"): False}
    r = {"object": "mug", "method": "gbh+", "trial": 0, "protocol": "stable", **row(True, "grasps")}
    assert keep_rows.screened_same(r, same)
    assert not keep_rows.screened_same({**r, "trial": 1}, same)  # changed
    assert not keep_rows.screened_same({**r, "trial": 2}, same)  # never screened
    regrasped = json.loads(json.dumps(r))
    regrasped["record"]["regrasps"] = [{"turn_deg": 90.0}]
    assert not keep_rows.screened_same(regrasped, same)
    retried = json.loads(json.dumps(r))
    retried["record"]["attempts"] = [{"source": "grasps"}]
    assert not keep_rows.screened_same(retried, same)
    failed = {**r, "success": False}  # a failure stands as well as a success when unchanged
    assert keep_rows.screened_same(failed, same)

    experiment = Path(__file__).parents[2] / "scenarios" / "experiment_small.yaml"
    tasks = keep_rows.make_tasks(keep_rows.load_experiment(experiment))
    rows = [{"object": t.object, "method": t.method, "trial": t.trial, "protocol": t.protocol,
             "scenario_digest": "old", **row(False)} for t in tasks]
    screen = tmp_path / "screen.jsonl"
    screen.write_text("".join(json.dumps({"object": t.object, "method": t.method,
                                          "trial": t.trial, "protocol": t.protocol,
                                          "same": i == 0}) + "\n"
                              for i, t in enumerate(tasks)))
    before = tmp_path / "before.jsonl"
    before.write_text("".join(json.dumps(r) + "\n" for r in rows))
    assert keep_rows.main([str(experiment), str(before), str(tmp_path / "out"),
                           "--screen", str(screen)]) == 0
    kept = [json.loads(line) for line in (tmp_path / "out" / "trials.jsonl").open()]
    assert [keep_rows.row_key(k) for k in kept] == [tasks[0].key]
