"""gbh experiment on a user's object set: a manifest of two meshes and one built-in object runs,
resumes and reports, its rows carrying the set's facts (control, tags, ground truth)."""

import copy
import json

import numpy as np
import pytest
import trimesh
from pydrake.common.yaml import yaml_load_typed

from gbh_drake import SCENARIOS_DIR
from gbh_drake.cli import main
from gbh_drake.experiment.config import (
    ExperimentError,
    _set_trial,
    experiment_objects,
    load_experiment,
    make_tasks,
    method_scenarios,
    trial_scenario_yaml,
)
from gbh_drake.scenario import Scenario

pytestmark = pytest.mark.sim


@pytest.fixture
def user_set(tmp_path):
    """A ring (a torus lying flat, its hole known) and a block (a control), as a user gives
    them: files in centimetres, real masses; and the built-in teapot."""
    ring = trimesh.creation.torus(3.0, 0.6, major_sections=48, minor_sections=16)  # cm, flat
    ring.export(tmp_path / "ring_cm.stl")
    trimesh.creation.box((6.0, 8.0, 10.0)).export(tmp_path / "block_cm.obj")
    (tmp_path / "set.yaml").write_text(
        "name: users\n"
        "objects:\n"
        "  - name: ring\n"
        "    mesh: ring_cm.stl\n"
        "    scale: 0.01\n"
        "    mass: 0.12\n"
        "    rest: {as_given: true, reason: lying flat}\n"
        "    tags: [ring, flat]\n"
        "    hangable_parts: [{center: [0, 0, 0], axis: [0, 0, 1], clear_diameter: 0.048}]\n"
        "  - {name: block, mesh: block_cm.obj, scale: 0.01, mass: 0.3, control: true,\n"
        "     rest: {as_given: true, reason: on its base}}\n"
        "  - {builtin: teapot}\n")
    (tmp_path / "exp.yaml").write_text(
        f"name: users\nbase: {SCENARIOS_DIR / 'default.yaml'}\n"
        "base_overrides: {max_time: 0.6, settle_time: 0.1}\n"
        "object_set: set.yaml\ntrials: 1\nprotocols: [natural]\n"
        "methods: [{name: gbh-1, overrides: {grasp_method: gbh, scan: {num_views: 1}}}]\n"
        "replays: none\n")
    return tmp_path


def test_a_users_set_runs_resumes_and_reports(user_set, capsys):
    experiment = load_experiment(user_set / "exp.yaml")
    assert experiment.objects == ["ring", "block", "teapot"]  # objects: all of the set's
    tasks = make_tasks(experiment)
    assert [(t.object, t.is_control, t.object_tags) for t in tasks] == [
        ("ring", False, ("ring", "flat")), ("block", True, ()), ("teapot", False, ())]
    out = user_set / "out"
    assert main(["experiment", str(user_set / "exp.yaml"), "--out", str(out), "--workers", "1",
                 "--no-progress"]) == 0
    rows = [json.loads(line) for line in (out / "trials.jsonl").read_text().splitlines()]
    by_object = {r["object"]: r for r in rows}
    assert set(by_object) == {"ring", "block", "teapot"}
    for row in rows:
        assert row["outcome"] != "error", row.get("traceback")
    assert by_object["ring"]["record"]["true_parts"] == 1
    assert by_object["ring"]["record"]["source"] == "object set users: ring"
    assert by_object["block"]["is_control"] and by_object["block"]["record"]["true_parts"] == 0
    assert by_object["ring"]["object_tags"] == ["ring", "flat"]
    capsys.readouterr()
    # Resumed: nothing left to run; the report names every object.
    assert main(["experiment", str(user_set / "exp.yaml"), "--out", str(out), "--workers", "1",
                 "--no-progress"]) == 0
    assert "0 to run" in capsys.readouterr().out
    summary = (out / "summary.md").read_text()
    assert all(name in summary for name in ("ring", "block", "teapot"))
    # The folder's own experiment.yaml, run from elsewhere, is the same experiment (its base and
    # manifest found from the folder) writing into the same folder: it resumes, nothing to run.
    saved = load_experiment(out / "experiment.yaml")
    assert saved.base_path.resolve() == (SCENARIOS_DIR / "default.yaml").resolve()
    assert saved.object_set_path.resolve() == (user_set / "set.yaml").resolve()
    assert saved.output_path().resolve() == out.resolve()
    assert [t.digest for t in make_tasks(saved)] == [t.digest for t in tasks]
    assert main(["experiment", str(out / "experiment.yaml"), "--workers", "1",
                 "--no-progress"]) == 0
    assert "0 to run" in capsys.readouterr().out


def test_an_object_neither_in_the_set_nor_built_in_is_refused(user_set):
    (user_set / "bad.yaml").write_text(
        (user_set / "exp.yaml").read_text() + "objects: [ring, nosuch]\n")
    with pytest.raises(ExperimentError, match=r"bad\.yaml: objects\[1\] \(line \d+\): unknown "
                                              r"object 'nosuch' \(known: ring, block, teapot, "):
        load_experiment(user_set / "bad.yaml")


def test_a_set_object_without_a_natural_rest_is_refused_by_the_natural_protocol(user_set):
    text = (user_set / "set.yaml").read_text().replace(
        "    rest: {as_given: true, reason: lying flat}\n", "")
    (user_set / "set.yaml").write_text(text)
    with pytest.raises(ExperimentError, match=r"protocols\[0\].*natural: object_set .*set\.yaml: "
                                              r"objects\[0\] \(ring\) \(line 3\) has no "
                                              r"natural rest"):
        load_experiment(user_set / "exp.yaml")


def test_the_external_set_experiment_lists_every_object_of_the_set():
    experiment = load_experiment(SCENARIOS_DIR / "experiment_external.yaml")
    assert len(experiment.objects) == 22 and len(experiment.methods) == 5
    assert experiment.protocols == ["stable", "natural"]
    assert np.isclose(len(make_tasks(experiment)), 22 * 5 * 5 * 2)


def test_each_task_holds_its_trials_own_dump_whatever_the_objects_names(user_set):
    """The task list dumps one scenario per method and protocol and sets the others' object
    (name, set) in its node tree: the text is each trial's own full dump, for names YAML would
    read as a number, an octal, a boolean or null unless quoted, and for a built-in object of
    the set (no ``object.set``) after set objects."""
    names = ["123", "0_7", "yes", "null"]
    text = (user_set / "set.yaml").read_text()
    for name in names:
        text += (f"  - {{name: '{name}', mesh: block_cm.obj, scale: 0.01, mass: 0.3, "
                 "rest: {as_given: true, reason: on its base}}\n")
    (user_set / "set.yaml").write_text(text)
    (user_set / "exp.yaml").write_text(
        f"name: users\nbase: {SCENARIOS_DIR / 'default.yaml'}\nobject_set: set.yaml\n"
        "trials: 2\nprotocols: [natural, stable]\n"
        "methods: [{name: a, overrides: {scan: {num_views: 1}}}, {name: b, overrides: {}}]\n")
    experiment = load_experiment(user_set / "exp.yaml")
    assert experiment.objects == ["ring", "block", "teapot", *names]
    tasks = make_tasks(experiment)
    assert len(tasks) == 7 * 2 * 2 * 2
    scenarios = method_scenarios(experiment)
    objects = {o.name: o for o in experiment_objects(experiment)}
    for task in tasks:  # each trial's scenario made and dumped alone, as trial_scenario does
        scenario = copy.deepcopy(scenarios[task.method])
        _set_trial(scenario, experiment, objects[task.object], task.trial, task.protocol)
        assert task.scenario_yaml == trial_scenario_yaml(scenario), task.key
        loaded = yaml_load_typed(schema=Scenario, data=task.scenario_yaml)
        assert (loaded.object.name, loaded.seed) == (task.object, task.seed)


def test_the_folders_method_scenarios_find_the_object_set(user_set):
    """summary.md says: rerun a trial with ``gbh run scenarios/<method>.yaml --set '{seed: ..,
    object: {name: ..}}'`` in the folder. Its ``object.set`` was written relative to the
    experiment file's folder ("set.yaml"), so the rerun was refused (file not found:
    <folder>/scenarios/set.yaml); it is relative to ``scenarios/``."""
    from gbh_drake.experiment.runner import _write_definition
    from gbh_drake.scenario import load_scenario

    experiment = load_experiment(user_set / "exp.yaml")
    out = user_set / "results" / "out"
    out.mkdir(parents=True)
    scenarios = method_scenarios(experiment)
    before = [t.digest for t in make_tasks(experiment, scenarios=scenarios)]
    _write_definition(out, experiment, scenarios)
    written = out / "scenarios" / "gbh-1.yaml"
    scenario = load_scenario(written, overrides="{seed: 7, object: {name: teapot}}")
    scenario = load_scenario(written, overrides="{seed: 7, object: {name: ring}}")
    assert scenario.resolve(scenario.object.set).resolve() == (user_set / "set.yaml").resolve()
    # the trials' own texts (and so their digests) are not changed by it
    assert [t.digest for t in make_tasks(experiment, scenarios=scenarios)] == before
