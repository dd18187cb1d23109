"""Rows (append, resume after a cut write, compare timing aside) and the reports made from them
(Table 1 beside the paper's, controls apart, per object, failures, the plot), on made-up rows."""

import json
import random
import re

import pytest
from PIL import Image

from gbh_drake.cli import main
from gbh_drake.experiment.config import Experiment, MethodConfig, experiment_yaml
from gbh_drake.experiment.report import read_input, summary_markdown, write_report
from gbh_drake.experiment.rows import RowStore, comparable, row_key
from gbh_drake.experiment.task import TrialTask
from gbh_drake.experiment.worker import run_trial_task

METHODS = [MethodConfig("gbh-10", "{grasp_method: gbh}", "GbH 10 views"),
           MethodConfig("antipodal", "{grasp_method: antipodal}", "GraspNet 1 view")]


def flat(text) -> str:
    """Markdown with runs of spaces made one (the tables pad their columns to their width)."""
    return re.sub(r" +", " ", "\n".join(text) if isinstance(text, list) else text)


def make_row(obj, method, trial, outcome="success", *, control=False, held_by="cage",
             refusals=None, total=10.0):
    success = outcome == "success"
    return {
        "experiment": "made_up", "object": obj, "is_control": control, "method": method,
        "trial": trial, "seed": 1000 + trial, "grasp_method": method.split("-")[0],
        "viewpoints": 10 if method == "gbh-10" else 1, "pose": [0.5, 0.0, 0.01, 0, 0, 1.0],
        "outcome": outcome, "success": success, "reason": f"{outcome} | because",
        "held_by": held_by if success else "", "grasp_kind": "vertical", "grasp_score": 0.5,
        "grasp_rank": 0, "fallback": False, "refusals": refusals or {},
        "replay": "" if success else f"replays/{obj}__{method}__{trial}.html",
        "commit": "abc123", "scenario_digest": "d", "worker": "host:1",
        "stage_times": {"build": 1.0, "scan": 2.0, "plan": 1.0, "simulate": 6.0,
                        "total": total},
        "record": {"object": obj, "timings": {"scan": 2.0}, "sim_time": 20.0},
    }


@pytest.fixture
def made_up(tmp_path):
    """An experiment folder: 2 objects with handles and a control, 2 trials, 2 methods."""
    experiment = Experiment(name="made_up", objects=["mug_classic", "kettle", "box"], trials=2,
                            methods=METHODS)
    (tmp_path / "experiment.yaml").write_text(experiment_yaml(experiment))
    rows = [
        make_row("mug_classic", "gbh-10", 0), make_row("mug_classic", "gbh-10", 1,
                                                         held_by="pinch"),
        make_row("kettle", "gbh-10", 0),
        make_row("kettle", "gbh-10", 1, "dropped_during_carry", refusals={"ik:lift": 2}),
        make_row("mug_classic", "antipodal", 0, "not_lifted"),
        make_row("mug_classic", "antipodal", 1, "no_reachable_grasp",
                 refusals={"ik:lift": 1, "planner:transfer": 3}),
        make_row("kettle", "antipodal", 0), make_row("kettle", "antipodal", 1, "not_lifted"),
        make_row("box", "gbh-10", 0, "no_hangable_structure", control=True),
        make_row("box", "gbh-10", 1, "no_hangable_structure", control=True),
        make_row("box", "antipodal", 0, control=True), make_row("box", "antipodal", 1,
                                                              "not_lifted", control=True),
    ]
    store = RowStore(tmp_path)
    for r in random.Random(3).sample(rows, len(rows)):  # in the order trials finished
        store.append(r)
    return tmp_path, rows


def test_rows_append_and_survive_a_cut_write(tmp_path):
    store = RowStore(tmp_path)
    rows = [make_row("box", "gbh-10", t) for t in range(3)]
    for r in rows:
        store.append(r)
    assert store.load() == rows
    with open(store.path, "a") as f:  # interrupted in the middle of a row
        f.write(json.dumps(make_row("box", "gbh-10", 3))[:50])
    assert store.load() == rows
    store.load(repair=True)
    store.append(rows[0])
    assert store.load() == [*rows, rows[0]]
    store.path.write_text(store.path.read_text().replace('"trial": 1', '"trial": 1,,'))
    with pytest.raises(ValueError, match="line 2"):
        store.load()


def test_comparable_leaves_out_timing_only():
    a, b = make_row("box", "gbh-10", 0, total=10.0), make_row("box", "gbh-10", 0, total=99.0)
    b["worker"], b["record"]["timings"] = "elsewhere:7", {"scan": 5.0}
    assert a != b and comparable(a) == comparable(b)
    b["pose"][0] = 0.6
    assert comparable(a) != comparable(b)


def test_summary(made_up):
    folder, _ = made_up
    summary_path, plot_path = write_report(folder)
    text = flat(summary_path.read_text())
    table = text.split("## Table 1")[1].split("##")[0]
    # hangable objects only: gbh-10 3 of 4 (2 cage, 1 pinch); antipodal 1 of 4 (cage); Wilson
    # 95 %: 3/4 -> [30.06, 95.44] %, 1/4 -> [4.56, 69.94] %
    assert "| gbh-10 | 10 | 4 | 3 | 1 | 75.0 % | [30.1, 95.4] % | 2 | 1 | GbH 10 views: 68/75 " \
        "= 90.7 % |" in table
    assert "| antipodal | 1 | 4 | 1 | 3 | 25.0 % | [4.6, 69.9] % | 1 | 0 | GraspNet 1 view: " \
        "23/75 = 30.7 % |" in table
    controls = text.split("## Controls")[1].split("##")[0]
    assert "| gbh-10 | 2 | 0 | no_hangable_structure x2 |" in controls
    assert "| antipodal | 2 | 1 | not_lifted x1, success x1 |" in controls
    per_object = text.split("## Per object")[1].split("##")[0]
    assert "| mug_classic | 2/2 [34, 100] % | 0/2 [0, 66] % |" in per_object
    assert "| box (control) | 0/2 [0, 66] % | 1/2 [9, 91] % |" in per_object
    outcomes = text.split("## Failures by outcome")[1].split("##")[0]
    assert "| not_lifted | 0 | 2 |" in outcomes and "| dropped_during_carry | 1 | 0 |" in outcomes
    refused = text.split("## Grasps refused")[1].split("##")[0]
    assert "| planner:transfer | 0 | 3 |" in refused and "| ik:lift | 2 | 1 |" in refused
    failed = text.split("## Failed trials")[1].split("##")[0]
    assert failed.count("[replay](replays/") == 4  # the controls' failures are not listed
    assert "not_lifted / because" in failed  # a pipe in a reason does not break the table
    assert "4 of 12" not in text and "12 of 12 trials done" in text
    image = Image.open(plot_path)
    assert image.format == "PNG" and image.size[0] >= 600


def test_report_does_not_depend_on_the_order_rows_finished(made_up):
    folder, rows = made_up
    first = summary_markdown(read_input(folder))
    RowStore(folder).rewrite(list(reversed(rows)))
    assert summary_markdown(read_input(folder)) == first
    assert [row_key(r) for r in read_input(folder).rows][:3] == [
        ("mug_classic", "gbh-10", 0, "stable"), ("mug_classic", "gbh-10", 1, "stable"),
        ("mug_classic", "antipodal", 0, "stable")]  # (rows without a protocol are stable)


def test_incomplete_experiment_says_so(made_up):
    folder, rows = made_up
    RowStore(folder).rewrite(rows[:5])
    text = summary_markdown(read_input(folder))
    assert "5 of 12 trials done" in text and "**Incomplete**" in text


def test_gbh_report_command(made_up, capsys):
    folder, _ = made_up
    (folder / "experiment.yaml").unlink()  # the rows alone are enough
    assert main(["report", str(folder)]) == 0
    out = flat(capsys.readouterr().out)
    assert "| Method | Viewpoints | Total | Success | Fail | Rate | 95 % CI |" in out
    assert "| A vs B | Pairs |" in out  # the paired comparison beside Table 1
    assert (folder / "summary.md").is_file() and (folder / "success.png").is_file()
    assert main(["report", str(folder / "nowhere")]) == 2


def test_a_broken_trial_is_a_row_not_a_crash():
    task = TrialTask(experiment="e", object="box", is_control=True, method="m", trial=0,
                     seed=1, scenario_yaml="not_a_field: 1\n", source_path="", digest="d",
                     commit="c", replays="none")
    row = run_trial_task(task).row
    assert row["outcome"] == "error" and not row["success"]
    assert "not_a_field" in row["reason"] and "Traceback" in row["traceback"]
    assert row_key(row) == ("box", "m", 0, "stable") and row["scenario_digest"] == "d"


def test_a_trial_run_in_a_fresh_process_leaves_its_ctrl_c_alone():
    """Only an engine's worker leaves SIGINT to its parent: a process that runs a trial itself
    (a script, a test) keeps its Ctrl-C, pydrake imported before or not (a test process that
    ran a trial first and then ignored SIGINT hung a later test that waited for it)."""
    import subprocess
    import sys

    code = (
        "import signal\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"  # as in a terminal
        "from gbh_drake.experiment.task import TrialTask\n"
        "from gbh_drake.experiment.worker import run_trial_task\n"
        "task = TrialTask(experiment='e', object='box', is_control=True, method='m', trial=0,"
        " seed=1, scenario_yaml='not_a_field: 1\\n', source_path='', digest='d', commit='c',"
        " replays='none')\n"
        "assert 'pydrake' not in __import__('sys').modules\n"
        "run_trial_task(task)\n"
        "print(signal.getsignal(signal.SIGINT) is signal.default_int_handler)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "True"


def test_resting_pose_classes_and_their_table(made_up):
    from math import pi

    from gbh_drake.experiment.report import by_resting_pose, resting_pose

    assert resting_pose([0, 0, 0, 0.0, 0.0, 2.0]) == "upright"
    assert resting_pose([0, 0, 0, pi / 2, 0.43, -2.3]) == "on its side"  # a mug on its side
    assert resting_pose([0, 0, 0, 0.0, pi / 2 - 0.01, 0.0]) == "on its side"
    assert resting_pose([0, 0, 0, -pi, 0.0, 1.0]) == "upside down"
    folder, rows = made_up
    for r in rows:
        if r["object"] == "kettle":
            r["pose"] = [0.5, 0.0, 0.05, pi / 2, 0.0, 0.0]
    RowStore(folder).rewrite(rows)
    table = flat(by_resting_pose(read_input(folder)))
    # gbh-10: the mug upright 2/2; the kettle on its side 1/2; antipodal: 0/2 and 1/2.
    assert "| gbh-10 | 2/2 (100.0 %, [34.2, 100.0] %) | 1/2 (50.0 %, [9.5, 90.5] %) | - |" in table
    assert "| antipodal | 0/2 (0.0 %, [0.0, 65.8] %) | 1/2 (50.0 %, [9.5, 90.5] %) | - |" in table
    assert "## By resting pose" in summary_markdown(read_input(folder))


def test_executed_grasps_are_counted_by_rank_and_value(tmp_path):
    """How often the planner went down the ranked list, a fallback was executed, or a grasp far
    below the best: each as successes / executed."""
    from gbh_drake.experiment.report import ReportInput, by_rank

    rows = [make_row("mug_classic", "gbh-10", 0), make_row("mug_classic", "gbh-10", 1),
            make_row("kettle", "gbh-10", 0, "not_lifted"), make_row("kettle", "gbh-10", 1)]
    rows[1].update(grasp_rank=4, grasp_score=0.002)
    rows[1]["record"]["best_score"] = 0.9
    rows[2].update(grasp_rank=1)
    rows[3].update(fallback=True, grasp_rank=0)
    data = ReportInput(name="x", objects=["mug_classic", "kettle"], methods=["gbh-10"],
                       trials=2, paper={}, rows=rows)
    table = flat(by_rank(data))
    assert "| gbh-10 | 1/1 | 0/1 | 1/1 | 1/1 | 1/1 |" in table


def test_the_rate_among_trials_a_loop_can_reach_leaves_out_only_those_out_of_reach():
    """Four no-grasp trials, one of each reach, and a success: the out-of-reach one leaves the
    denominator, the others stay (a miss of the candidate set or of the scan is a defect)."""
    from gbh_drake.experiment.report import ReportInput, by_reach, reach_class

    rows = [make_row("mug_classic", "gbh-10", t, "no_grasp_found") for t in range(4)]
    rows.append(make_row("mug_classic", "gbh-10", 4))
    for r, (true, scan) in zip(rows[:4], [("out of reach", "out of reach"),
                                      ("reachable", "reachable"), ("reachable", "out of reach"),
                                      ("undecided", "undecided")], strict=True):
        r["reach"] = {"true": true, "scan": scan}
    assert [reach_class(r) for r in rows[:4]] == ["out of reach", "candidate set missed",
                                                  "lost in the scan", "undecided"]
    assert reach_class(make_row("kettle", "gbh-10", 0, "no_grasp_found")) == "not analysed"
    data = ReportInput(name="x", objects=["mug_classic"], methods=["gbh-10"], trials=5,
                       paper={}, rows=rows)
    assert "| gbh-10 | 5 | 4 | 1 | 1 | 1 | 1 | 0 | 1/4 | 25.0 % |" in flat(by_reach(data))


def test_outputs_a_researcher_loads(made_up):
    """trials.csv (one row per trial), table1.csv, the paired comparison and the causes, on the
    made-up rows; both plots as PNG and SVG."""
    import pandas as pd

    folder, rows = made_up
    summary, _ = write_report(folder)
    trials = pd.read_csv(folder / "trials.csv", keep_default_na=False)
    assert len(trials) == len(rows) == 12
    assert not trials.duplicated(["object", "method", "trial"]).any()
    for column in ("object", "method", "trial", "seed", "outcome", "success", "held_by", "cause",
                   "grasp_kind", "grasp_rank", "grasp_score", "resting_pose", "n_structures",
                   "true_part_found", "grasped_true_part", "lift", "time_total", "pose_yaw"):
        assert column in trials.columns, column
    kettle = trials[(trials.object == "kettle") & (trials.method == "gbh-10") & (trials.trial == 1)]
    assert kettle.cause.item() == "slipped during carry" and kettle.refusals.item() == "ik:lift x2"
    assert set(trials[trials.success].cause) == {""}
    table1 = pd.read_csv(folder / "table1.csv")
    gbh = table1.set_index("method").loc["gbh-10"]
    assert (gbh.trials, gbh.successes, gbh.cage, gbh.pinch) == (4, 3, 2, 1)
    assert (gbh.rate, gbh.wilson_lo, gbh.wilson_hi) == pytest.approx((0.75, 0.3006, 0.9544),
                                                                     abs=1e-4)
    text = flat(summary.read_text())
    # gbh-10 vs antipodal on the 4 hangable poses: both 1 (kettle 0), gbh-10 only 2 (the mug's),
    # neither 1 (kettle 1): p = 2 x 0.5^2 = 0.5, +50 points
    assert "| gbh-10 vs antipodal | 4 | 1 | 2 | 0 | 1 | +50.0 |" in text
    assert "| 0.500 | 0.500 |" in text
    causes = text.split("## Failures by cause")[1].split("##")[0]
    assert "| slipped during carry | 1 | 0 | 1 |" in causes
    assert "| lift too low | 0 | 2 | 2 |" in causes and "| planner | 0 | 1 | 1 |" in causes
    assert "| out of reach | 0 | 0 | 0 |" in causes  # reserved classes are listed
    svgs = {}
    for name in ("success", "causes"):
        assert Image.open(folder / f"{name}.png").format == "PNG"
        svgs[name] = (folder / f"{name}.svg").read_text()
        assert svgs[name].lstrip().startswith("<?xml")
    write_report(folder)  # the same rows, the same files
    assert all((folder / f"{name}.svg").read_text() == svg for name, svg in svgs.items())


def test_a_rate_of_no_trials_is_a_dash(made_up):
    import pandas as pd

    folder, rows = made_up
    RowStore(folder).rewrite(rows[:4])  # gbh-10 only
    write_report(folder)
    text = flat((folder / "summary.md").read_text())
    assert "| antipodal | - | 0 | 0 | 0 | - | - | 0 | 0 |" in text
    assert "No two methods ran on the same poses." in text
    assert "| box | - | - |" in text  # no rows: not known to be a control
    table1 = pd.read_csv(folder / "table1.csv").set_index("method")
    assert table1.loc["antipodal"].trials == 0 and pd.isna(table1.loc["antipodal"].wilson_lo)
    RowStore(folder).rewrite([])
    write_report(folder)  # no rows at all: the reports still come out
    empty = pd.read_csv(folder / "trials.csv")
    assert empty.empty and "cause" in empty.columns


def test_reference_experiment_as_csv(tmp_path):
    """The 1150-trial experiment in docs/experiment (5 methods, 2 protocols): one CSV row per
    trial, a cause for every failure, Table 1's numbers (no plots: fast)."""
    from pathlib import Path

    import pandas as pd

    from gbh_drake.experiment.report import cause_counts, table1_frame, trials_frame

    data = read_input(Path(__file__).parents[2] / "docs" / "experiment")
    (tmp_path / "trials.csv").write_text(trials_frame(data).to_csv(index=False))
    trials = pd.read_csv(tmp_path / "trials.csv", keep_default_na=False)
    assert len(trials) == len(data.rows) == 1150
    assert not trials.duplicated(["object", "method", "trial", "protocol"]).any()
    assert ((trials.cause == "") == trials.success).all()
    hangable_failures = sum(not r["success"] and not r["is_control"] for r in data.rows)
    assert cause_counts(data).to_numpy().sum() == hangable_failures == 314
    table = table1_frame(data).set_index(["protocol", "method"])
    gbh10 = table.loc[("stable", "gbh-10")]
    assert (gbh10.trials, gbh10.successes) == (95, 57)
    assert (gbh10.wilson_lo, gbh10.wilson_hi) == pytest.approx((0.4995, 0.6928), abs=1e-4)
    plus = table.loc[("stable", "gbh+")]
    assert (plus.trials, plus.successes, plus.cage) == (95, 89, 71)


# ---- protocols ---------------------------------------------------------------------------------
def test_a_stable_only_report_is_the_one_of_rows_without_a_protocol(made_up):
    """Rows written before protocols existed are ``stable``: the same report, byte for byte,
    whether the rows say ``protocol: stable`` or nothing."""
    folder, rows = made_up
    before = summary_markdown(read_input(folder))
    assert "protocol" not in before.lower()
    RowStore(folder).rewrite([dict(r, protocol="stable") for r in rows])
    assert summary_markdown(read_input(folder)) == before


def test_two_protocols_give_table_1_once_per_protocol(made_up):
    import pandas as pd

    from gbh_drake.experiment.report import table1_frame, trials_frame

    folder, rows = made_up
    experiment = Experiment(name="made_up", objects=["mug_classic", "kettle", "box"], trials=2,
                            methods=METHODS, protocols=["stable", "natural"])
    (folder / "experiment.yaml").write_text(experiment_yaml(experiment))
    natural = [dict(r, protocol="natural", seed=r["seed"] + 7) for r in rows]
    for r in natural:  # in the natural rest every mug trial succeeds
        if r["object"] == "mug_classic":
            r.update(outcome="success", success=True, held_by="cage", reason="success")
    RowStore(folder).rewrite(rows + natural[:-1])  # the last natural trial not run yet
    data = read_input(folder)
    assert data.protocols == ["stable", "natural"] and len(data.rows) == 23
    text = flat(summary_markdown(data))
    assert "3 objects x 2 trials x 2 methods x 2 protocols (stable, natural): 23 of 24" in text
    stable = text.index("## Table 1, protocol `stable`")
    natural_at = text.index("## Table 1, protocol `natural`")
    assert stable < natural_at < text.index("## By resting pose")
    assert "| antipodal | 1 | 4 | 1 | 3 | 25.0 % |" in text[stable:natural_at]
    assert "| antipodal | 1 | 4 | 3 | 1 | 75.0 % |" in text[natural_at:]
    assert "## Per object, protocol `natural`" in text and "| gbh-10 (natural) |" in text
    assert "| Object | Method | Trial | Protocol | Seed |" in text  # the failed trials
    write_report(folder)
    table = pd.read_csv(folder / "table1.csv")
    assert list(table.protocol) == ["stable", "stable", "natural", "natural"]
    assert table.set_index(["protocol", "method"]).loc[("natural", "antipodal")].successes == 3
    trials = pd.read_csv(folder / "trials.csv")
    assert len(trials) == 23 and not trials.duplicated(["object", "method", "trial",
                                                        "protocol"]).any()
    assert (trials.protocol == "natural").sum() == 11
    assert list(table1_frame(data).columns[:2]) == ["protocol", "method"]
    assert "protocol" in trials_frame(data).columns


def test_old_rows_read_as_stable_and_resume_against_todays_tasks(tmp_path):
    from gbh_drake.experiment.runner import _finished, _set_protocol, replay_name

    task = TrialTask(experiment="e", object="box", is_control=True, method="m", trial=0,
                     seed=1, scenario_yaml="", source_path="", digest="d1", commit="c",
                     replays="none")
    natural = TrialTask(experiment="e", object="box", is_control=True, method="m", trial=0,
                        seed=2, scenario_yaml="", source_path="", digest="d2", commit="c",
                        replays="none", protocol="natural")
    old = make_row("box", "m", 0, control=True)
    old.update(scenario_digest="d1")
    store = RowStore(tmp_path)
    store.append(old)  # a row of before protocols: no protocol field
    done = _finished(store, [task, natural])
    assert list(done) == [("box", "m", 0, "stable")]
    row = make_row("box", "m", 0, "not_lifted", control=True)
    row.update(scenario_digest="d2")
    _set_protocol(row, {("box", "m", 0, "d1"): task, ("box", "m", 0, "d2"): natural})
    assert row["protocol"] == "natural" and row_key(row) == ("box", "m", 0, "natural")
    assert replay_name(row) == "box__m__0__natural.html"
    assert replay_name(old) == "box__m__0.html"


def test_the_report_counts_the_retries_and_what_came_of_them():
    """Rows whose record has ``attempts`` (a lift came away empty, a retry followed) are counted
    per method: how many were then carried, by a cage or a pinch; no retries, no section."""
    from gbh_drake.experiment.report import ReportInput, retries

    attempt = {"kind": "parallel", "rank": 0, "score": 1e-6, "source": "grasps", "load": 0.03}
    rows = [make_row("kettle", "gbh+", 0), make_row("kettle", "gbh+", 1, held_by="pinch"),
            make_row("kettle", "gbh+", 2, "not_lifted"), make_row("kettle", "gbh+", 3),
            make_row("kettle", "gbh-10", 0, "not_lifted")]
    for r in rows[1:3]:
        r["record"]["attempts"] = [attempt]
    data = ReportInput(name="x", objects=["kettle"], methods=["gbh-10", "gbh+"], trials=4,
                       paper={}, rows=rows)
    text = flat(retries(data))
    assert "| gbh+ | 2 | 1 | 0 | 1 |" in text and "| gbh-10 |" not in text
    for r in rows:
        r["record"].pop("attempts", None)
    data = ReportInput(name="x", objects=["kettle"], methods=["gbh-10", "gbh+"], trials=4,
                       paper={}, rows=rows)  # (the rows are read once: a new input)
    assert retries(data) == []


def test_the_report_counts_the_lifts_the_unseen_space_raised():
    """A row whose plan notes that the unseen space raised its lift counts, with whether it was
    carried; a dragged row counts as dragged; a pinch is not a hook."""
    from gbh_drake.experiment.report import UNSEEN_LIFT_NOTE, ReportInput, by_lift

    rows = [make_row("kettle", "gbh-1", t) for t in range(3)] + [
        make_row("kettle", "gbh-1", 3, "not_lifted")]
    rows[0]["record"]["plan_notes"] = [f"{UNSEEN_LIFT_NOTE}: 0.202 m keeps it clear, 0.132 m "
                                       "the scan"]
    rows[3]["record"]["plan_notes"] = list(rows[0]["record"]["plan_notes"])
    rows[3]["reason"] = "held by the gripper (bar) but still touching the table: dragged"
    rows[2]["grasp_kind"] = "antipodal"
    data = ReportInput(name="x", objects=["kettle"], methods=["gbh-1"], trials=4, paper={},
                       rows=rows)
    assert "| gbh-1 | 3 | 2 | 1 | 1 |" in flat(by_lift(data))


def test_every_success_beyond_the_loops_reach_is_counted_once_by_how_it_was_taken():
    """A pinch by the fallback after a regrasp is a column of its own: the ways add up to the
    successes (a success taken in a way with no column would vanish from the table)."""
    from gbh_drake.experiment.report import HELD_HOW, ReportInput, held_how

    ways = [("grasps", False, "parallel"), ("scoop_grasps", False, "scoop"),
            ("grasps", True, "parallel"), ("fallback_grasps", True, "antipodal"),
            ("fallback_grasps", False, "antipodal"), ("tall_scoop_grasps", False, "scoop"),
            ("tall_scoop_grasps", True, "scoop")]
    rows = []
    for trial, (source, regrasp, kind) in enumerate(ways):
        r = make_row("key_ring", "gbh+", trial)
        r["grasp_method"], r["grasp_kind"] = "gbh_plus", kind
        r["record"].update(grasp_source=source, regrasps=[{"turn_deg": 90.0}] if regrasp else [])
        rows.append(r)
    assert all(held_how(r) in HELD_HOW for r in rows)
    assert held_how(rows[3]) == "regrasp, fallback pinch"
    assert held_how(rows[6]) == "regrasp, tall scoop"
    data = ReportInput(name="x", objects=["key_ring"], methods=["gbh+"], trials=len(rows),
                       paper={}, rows=rows)
    from gbh_drake.experiment.report import beyond

    line = next(s for s in flat(beyond(data)).splitlines() if s.startswith("| gbh+ "))
    cells = [c.strip() for c in line.strip("|").split("|")]
    assert cells[2].startswith(f"{len(rows)} ") and sum(int(c) for c in cells[4:]) == len(rows)


def test_rows_that_ended_after_the_cage_test_are_not_counted_as_kept_on_the_bar(made_up):
    """``pick.set_down: false`` rows (no ``lower`` phase) are left out of the released count
    and said to be so; rows without phases (older) count as before."""
    folder, rows = made_up
    rows = [dict(r, record=dict(r["record"], phases={"hold": 1.0})) if r["method"] == "gbh-10"
            else r for r in rows]
    RowStore(folder).rewrite(rows)
    text = flat(summary_markdown(read_input(folder)))
    assert "gbh-10 0/0 (3 not set down: pick.set_down false)" in text


def test_gbh_report_prints_table_1_per_protocol_as_the_summary_has_it(tmp_path, capsys):
    # An experiment of two protocols: its printout pooled both into one table without a
    # heading (4 trials of gbh-10, a table found in neither summary.md nor table1.csv); it is
    # the summary's tables, each under its protocol's heading.
    experiment = Experiment(name="two", objects=["mug_classic", "kettle"], trials=1,
                            methods=METHODS, protocols=["stable", "natural"])
    (tmp_path / "experiment.yaml").write_text(experiment_yaml(experiment))
    store = RowStore(tmp_path)
    for protocol, outcome in (("stable", "not_lifted"), ("natural", "success")):
        for obj in ("mug_classic", "kettle"):
            for method in ("gbh-10", "antipodal"):
                row = make_row(obj, method, 0, outcome)
                row["protocol"] = protocol
                store.append(row)
    assert main(["report", str(tmp_path)]) == 0
    out = flat(capsys.readouterr().out)
    assert out.index("## Table 1, protocol `stable`") < out.index("## Table 1, protocol `natural`")
    stable, natural = out.split("## Table 1, protocol `natural`")
    assert "| gbh-10 | 10 | 2 | 0 | 2 | 0.0 % |" in stable
    assert "| gbh-10 | 10 | 2 | 2 | 0 | 100.0 % |" in natural
    assert "| gbh-10 | 10 | 4 |" not in out  # no table pooling the protocols


def test_per_object_says_the_widths_of_its_own_intervals(made_up):
    """It said 'with 5 trials an interval spans some 50 points' whatever the trials: here 2
    trials per cell, intervals of 0/2 and 2/2 (66 points) and 1/2 (81 points)."""
    folder, rows = made_up
    per_object = flat(summary_markdown(read_input(folder))).split("## Per object")[1]
    assert "(with 2 trials each, these intervals span 66 to 81 points: tell objects apart " \
           "with care)." in per_object and "5 trials" not in per_object
    RowStore(folder).rewrite([r for r in rows if r["trial"] == 0])  # 1 trial each so far
    per_object = flat(summary_markdown(read_input(folder))).split("## Per object")[1]
    assert "(with 1 trial each, these intervals span 79 points:" in per_object


def test_the_head_names_the_command_that_wrote_it(made_up):
    """It said 'by `gbh report`' when `gbh experiment` wrote it too."""
    folder, _ = made_up
    head = summary_markdown(read_input(folder), command="gbh experiment").splitlines()[2]
    assert head.endswith("Rebuilt from `trials.jsonl` by `gbh experiment`.")
    assert main(["report", str(folder)]) == 0
    assert "by `gbh report`." in (folder / "summary.md").read_text()


def test_a_protocol_without_trials_has_no_detail_table(made_up):
    """A protocol no trial of which has run gave a table of headers alone."""
    folder, _ = made_up
    experiment = Experiment(name="made_up", objects=["mug_classic", "kettle", "box"], trials=2,
                            methods=METHODS, protocols=["stable", "natural"])
    (folder / "experiment.yaml").write_text(experiment_yaml(experiment))
    text = flat(summary_markdown(read_input(folder)))
    detail = text.split("## Per object, in detail, protocol `natural`")[1].split("##")[0]
    assert detail.strip() == "No trials yet." and "| Object | Method | Trials |" in text
