"""A small experiment run for real (3 objects with a control, 2 trials, the four methods) on a
short horizon: every output file, resume after an interruption, and the same rows from 2 workers,
1 worker and a local Ray, timing fields aside (``first_run``: conftest.py; on a cluster of two
nodes: test_ray_cluster.py).

The trials stop after planning and the first motions (``max_time: 0.6`` per pick, outcome mostly
``incomplete``): rows, resume, reports and engines are what this checks; real outcomes are
checked by the trial's own tests. About 2 minutes on 2 cores.
"""

import ipaddress
import json
import re
import shutil
from collections import Counter
from pathlib import Path

import psutil
import pytest
from PIL import Image

from gbh_drake.cli import main
from gbh_drake.experiment.config import load_experiment, trial_seed
from gbh_drake.experiment.rows import ROWS_FILE, RowStore, comparable, row_key
from gbh_drake.experiment.runner import run_experiment
from gbh_drake.scenario import load_scenario

pytestmark = pytest.mark.sim

SHORT = Path(__file__).parent / "short_experiment.yaml"
OBJECTS, TRIALS = ["mug_classic", "clothes_hanger", "box"], 2
METHODS = ["gbh-10", "gbh-1", "antipodal", "gbh+fallback"]


def test_every_trial_has_one_row(first_run):
    folder, by_key, rows = first_run
    assert len(rows) == len(by_key) == len(OBJECTS) * TRIALS * len(METHODS)
    assert set(by_key) == {(o, m, t, "stable") for o in OBJECTS for m in METHODS
                           for t in range(TRIALS)}  # (the protocol by default: stable)
    assert [row_key(r) for r in rows] == sorted(  # the finished file is in report order
        by_key, key=lambda k: (OBJECTS.index(k[0]), METHODS.index(k[1]), k[2]))
    for (obj, method, trial, _), r in by_key.items():
        assert r["protocol"] == "stable"
        assert r["outcome"] != "error", r.get("traceback")
        assert r["seed"] == r["record"]["seed"] == trial_seed(11, obj, trial)
        assert r["is_control"] == (obj == "box")
        assert r["viewpoints"] == (10 if method in ("gbh-10", "gbh+fallback") else 1)
        assert r["grasp_method"] == {"gbh-10": "gbh", "gbh-1": "gbh", "antipodal": "antipodal",
                                     "gbh+fallback": "gbh_fallback"}[method]
        assert r["outcome"] and r["reason"]
        assert r["commit"] and len(r["scenario_digest"]) == 64
        assert set(r["stage_times"]) >= {"build", "scan", "plan", "simulate", "total"}
        picks = 2 if method == "gbh+fallback" else 1  # max_time holds for each pick it may start
        assert r["record"]["object"] == obj and r["record"]["sim_time"] <= 0.6 * picks + 1e-9
        assert len(r["pose"]) == 6 and r["pose"] == r["record"]["pose"]
    per_worker = Counter(r["worker"] for r in rows)  # trials_per_worker: 5 in the file
    assert len(per_worker) >= 5 and max(per_worker.values()) <= 5, per_worker
    for obj in OBJECTS:  # every method saw the same pose; the trials' poses differ
        poses = [{tuple(by_key[(obj, m, t, "stable")]["pose"]) for m in METHODS}
                 for t in range(TRIALS)]
        assert all(len(p) == 1 for p in poses) and poses[0] != poses[1]


def test_output_files(first_run):
    folder, by_key, _ = first_run
    for name in ("summary.md", "success.png", "experiment.yaml", "runs.jsonl", ROWS_FILE):
        assert (folder / name).is_file(), name
    failed = [r for r in by_key.values() if not r["success"]]
    assert failed  # on this short horizon nothing is carried
    for r in by_key.values():  # a replay for every failed trial, none for the others
        if r["success"]:
            assert r["replay"] == ""
        else:
            html = (folder / r["replay"]).read_text()
            assert html.lstrip().lower().startswith("<!doctype html") and "meshcat" in html
    assert len(list((folder / "replays").iterdir())) == len(failed)
    summary = re.sub(" +", " ", (folder / "summary.md").read_text())  # (tables are padded)
    for section in ("## Table 1", "## Controls", "## Per object", "## Failures by outcome",
                    "## Grasps refused", "## Failed trials", "## Time"):
        assert section in summary
    assert "| Method | Viewpoints | Total | Success | Fail | Rate | 95 % CI | Cage | Pinch |" in summary
    assert "GbH 10 views: 68/75 = 90.7 %" in summary and "24 of 24 trials done" in summary
    assert "| box (control) |" in summary
    assert Image.open(folder / "success.png").format == "PNG"
    for method in METHODS:  # each method's scenario, loadable to rerun a trial with gbh run
        scenario = load_scenario(folder / "scenarios" / f"{method}.yaml")
        assert scenario.object.random_pose is not None
    run = json.loads((folder / "runs.jsonl").read_text().splitlines()[0])
    assert run["trials"] == 24 and run["engine"] == "2 local workers"


def test_report_rebuilds_the_same_summary(first_run, tmp_path, capsys):
    folder, _, _ = first_run
    copy = tmp_path / "copy"
    shutil.copytree(folder, copy, ignore=shutil.ignore_patterns("replays"))
    (copy / "summary.md").unlink()
    (copy / "success.png").unlink()
    assert main(["report", str(copy)]) == 0
    rebuilt, written = (copy / "summary.md").read_text(), (folder / "summary.md").read_text()
    # The same summary, but for the command its head says wrote it.
    assert "by `gbh experiment`" in written and "by `gbh report`" in rebuilt
    assert rebuilt.replace("by `gbh report`", "by `gbh experiment`") == written
    assert (copy / "success.png").is_file()
    assert "| gbh-10 | 10 | 4 |" in re.sub(" +", " ", capsys.readouterr().out)


def test_resume_on_one_worker_redoes_only_the_missing_trials(first_run, tmp_path, capsys):
    """An interrupted experiment (2 rows missing, the last one cut short, and a trial that ended
    in an error) resumes on 1 worker: the other rows are kept as they were, and the 3 trials give
    the same rows as on 2 workers, timing fields aside: same seed, same rows twice, whatever the
    number of workers."""
    folder, by_key, rows = first_run
    copy = tmp_path / "resumed"
    shutil.copytree(folder, copy, ignore=shutil.ignore_patterns("replays"))
    missing = [("mug_classic", "gbh-1", 1, "stable"), ("clothes_hanger", "antipodal", 0, "stable"),
               ("box", "gbh+fallback", 1, "stable")]
    kept = [r if row_key(r) != missing[2] else dict(r, outcome="error", reason="a bug")
            for r in rows if row_key(r) not in missing[:2]]
    RowStore(copy).rewrite(kept)
    with open(copy / ROWS_FILE, "a") as f:
        f.write(json.dumps(by_key[missing[0]])[:200])  # the write the interruption cut
    assert main(["experiment", str(SHORT), "--workers", "1", "--out", str(copy),
                 "--no-progress"]) == 0
    assert "3 trials run, 21 found done" in capsys.readouterr().out
    again = {row_key(r): r for r in RowStore(copy).load()}  # (the error row sorted out)
    assert len(again) == 24 and len(RowStore(copy).load()) == 24
    for key, row in again.items():
        if key in missing:
            assert row["worker"] != by_key[key]["worker"]
            assert comparable(row) == comparable(by_key[key]), key
        else:
            assert row == by_key[key]  # not redone: even its timings are the old ones
    assert (copy / "summary.md").read_text().count("[replay](") == \
        (folder / "summary.md").read_text().count("[replay](")


def _ray_processes() -> tuple[set[str], dict[str, str]]:
    """The addresses on which this process's descendants (Ray's servers) accept connections,
    and the HTTP proxy each of them has (by its command line)."""
    listening, proxies = set(), {}
    for child in psutil.Process().children(recursive=True):
        try:
            for c in child.net_connections(kind="inet"):
                if c.status == psutil.CONN_LISTEN:
                    listening.add(c.laddr.ip)
            proxies[" ".join(child.cmdline())] = child.environ().get("http_proxy", "")
        except psutil.Error:
            continue
    return listening, proxies


def test_local_ray_gives_the_same_rows(first_run, tmp_path):
    """The same trials as Ray tasks on a Ray started here (2 CPUs): the same rows, timing aside.
    Ray listens on the loopback only, and its processes' HTTP goes to a dead loopback proxy
    (its dashboard process would otherwise ask the cloud metadata address which cloud it is
    on)."""
    _, by_key, _ = first_run
    part = load_experiment(SHORT, overrides="objects: [clothes_hanger, box]\ntrials: 1\n"
                                            "replays: none\n")
    listening: set[str] = set()
    proxies: dict[str, str] = {}

    def log(message: str):
        if message.startswith("ray:"):  # Ray is up
            found = _ray_processes()
            listening.update(found[0])
            proxies.update(found[1])

    result = run_experiment(part, out=tmp_path / "ray", workers=2, ray_address="local",
                            progress=False, log=log)
    assert result.ran == 8 and result.complete
    assert listening and all(ipaddress.ip_address(a.removeprefix("::ffff:")).is_loopback
                             for a in listening), listening
    dashboard = [p for cmd, p in proxies.items() if "dashboard" in cmd]
    assert dashboard and all(p == "http://127.0.0.1:9" for p in dashboard), proxies
    rows = RowStore(tmp_path / "ray").load()
    assert len(rows) == 8
    for row in rows:
        original = dict(by_key[row_key(row)], replay="")  # no replays kept in this run
        assert comparable(row) == comparable(original), row_key(row)


def test_rows_of_other_scenarios_are_not_resumed(first_run, tmp_path, capsys):
    folder, _, _ = first_run
    copy = tmp_path / "other"
    copy.mkdir()
    shutil.copy(folder / ROWS_FILE, copy / ROWS_FILE)
    assert main(["experiment", str(SHORT), "--set", "base_overrides: {max_time: 0.7}",
                 "--out", str(copy), "--no-progress"]) == 2
    assert "made with other scenarios" in capsys.readouterr().err
    assert RowStore(copy).load() == RowStore(folder).load()  # untouched


def test_reuse_copies_the_same_trials_of_another_folder(first_run, tmp_path, capsys):
    """Another experiment that shares trials with the first run (the box, one trial, its
    antipodal method as it was and its gbh-1 with another d2): ``--reuse`` copies the shared
    trial's row (and its replay) unchanged, refuses the trial whose scenario differs and runs
    it; an own folder or a folder without rows is refused naming it."""
    folder, by_key, _ = first_run
    methods = ("methods: [{name: antipodal, overrides: {grasp_method: antipodal, scan: "
               "{num_views: 1}}}, {name: gbh-1, overrides: {grasp_method: gbh, scan: "
               "{num_views: 1}, gbh: {d2: 0.004}}}]")
    out = tmp_path / "shared"
    args = ["experiment", str(SHORT), "--set", "objects: [box]", "--set", "trials: 1",
            "--set", methods, "--out", str(out), "--no-progress"]
    assert main([*args, "--reuse", str(folder)]) == 0
    said = capsys.readouterr().out
    commit = by_key[("box", "antipodal", 0, "stable")]["commit"][:12]
    assert f"reused 1 trials from {folder} (1 at {commit}); 1 trials there ran other " \
           "scenarios: not reused" in said
    assert "1 trials run, 1 found done" in said
    rows = {row_key(r): r for r in RowStore(out).load()}
    assert rows[("box", "antipodal", 0, "stable")] == by_key[("box", "antipodal", 0, "stable")]
    replay = rows[("box", "antipodal", 0, "stable")]["replay"]
    assert not replay or (out / replay).read_bytes() == (folder / replay).read_bytes()
    assert rows[("box", "gbh-1", 0, "stable")]["scenario_digest"] != \
        by_key[("box", "gbh-1", 0, "stable")]["scenario_digest"]  # run here
    assert main([*args, "--reuse", str(out)]) == 2
    assert "--reuse names the experiment's own folder" in capsys.readouterr().err
    assert main([*args, "--reuse", str(tmp_path / "nothing")]) == 2
    assert f"{tmp_path / 'nothing'}: no trials.jsonl here" in capsys.readouterr().err
