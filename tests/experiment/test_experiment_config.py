"""The experiment file: methods as overrides of a base scenario, seeds from (seed, object, trial)
alone, the shipped experiments, and errors that name the field."""

import re
import textwrap
from pathlib import Path

import pytest
import yaml

from gbh_drake import SCENARIOS_DIR
from gbh_drake.experiment.config import (
    ExperimentError,
    load_experiment,
    make_tasks,
    method_scenarios,
    trial_seed,
)
from gbh_drake.objects import make_object
from gbh_drake.scenario import DEFAULT_DIRECTIVES

HERE = Path(__file__).parent
SHORT = HERE / "short_experiment.yaml"
DEFAULT_SCENARIO = SCENARIOS_DIR / "default.yaml"


class _AnyTag(yaml.SafeLoader):
    """Reads Drake's tagged values (``!Rpy``) as plain mappings."""


_AnyTag.add_multi_constructor("!", lambda loader, suffix, node: loader.construct_mapping(node))


def write(tmp_path: Path, text: str, name: str = "exp.yaml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text).replace("BASE", str(DEFAULT_SCENARIO)))
    return path


def test_trial_seed_is_fixed_by_seed_object_and_trial():
    # Golden values: a sha256 of the name (not Python's per-process hash) and numpy's
    # SeedSequence, so the same trial has the same seed in every process and on every machine.
    assert trial_seed(0, "mug_classic", 0) == 374982299
    assert trial_seed(0, "mug_classic", 1) == 1701024929
    assert trial_seed(1, "mug_classic", 0) == 3305700452
    assert trial_seed(0, "kettle", 0) == 3432542425


def test_every_method_sees_the_same_trials():
    experiment = load_experiment(SHORT)
    tasks = make_tasks(experiment)
    assert len(tasks) == 3 * 2 * 4
    by_trial: dict = {}
    for t in tasks:
        by_trial.setdefault((t.object, t.trial), []).append(t)
    seeds = {key: {t.seed for t in group} for key, group in by_trial.items()}
    assert all(len(s) == 1 for s in seeds.values())  # one seed (one pose) for every method
    assert len({next(iter(s)) for s in seeds.values()}) == len(seeds)  # trials differ
    for (name, trial), group in by_trial.items():
        assert {t.method for t in group} == {"gbh-10", "gbh-1", "antipodal", "gbh+fallback"}
        assert group[0].seed == trial_seed(11, name, trial)
        assert group[0].is_control == make_object(name).is_control
        docs = {t.method: yaml.load(t.scenario_yaml, Loader=_AnyTag) for t in group}
        for doc in docs.values():
            assert doc["seed"] == group[0].seed and doc["object"]["name"] == name
            assert doc["object"]["random_pose"] == docs["gbh-10"]["object"]["random_pose"]
            assert doc["max_time"] == 0.6 and doc["settle_time"] == 0.1  # base_overrides
        assert docs["gbh-10"]["scan"]["num_views"] == 10 and docs["gbh-10"]["gbh"]["d2"] == 0.0
        assert docs["gbh-1"]["scan"]["num_views"] == 1 and docs["gbh-1"]["gbh"]["d2"] == 0.005
        assert docs["antipodal"]["grasp_method"] == "antipodal"
        assert docs["gbh+fallback"]["grasp_method"] == "gbh_fallback"
        assert len({t.digest for t in group}) == 4


def test_a_trial_does_not_depend_on_the_others(tmp_path):
    """A smaller experiment (other objects, fewer trials and methods, another order) gives the
    very same tasks for the trials it shares."""
    whole = {t.key: t for t in make_tasks(load_experiment(SHORT))}
    part = load_experiment(SHORT, overrides=textwrap.dedent("""\
        objects: [box, mug_classic]
        trials: 1
        methods:
        - {name: antipodal, overrides: {grasp_method: antipodal, scan: {num_views: 1}}}
        """))
    tasks = make_tasks(part)
    assert [t.key for t in tasks] == [("box", "antipodal", 0, "stable"),
                                      ("mug_classic", "antipodal", 0, "stable")]
    for t in tasks:
        assert (t.seed, t.digest, t.scenario_yaml) == \
            (whole[t.key].seed, whole[t.key].digest, whole[t.key].scenario_yaml)


def test_overrides_as_mapping_or_text(tmp_path):
    """A method's overrides may be a mapping (Drake's tags kept) or YAML text: same scenario."""
    # The default directives, Drake's !Rpy tag included, as a mapping inside the overrides.
    directives = textwrap.indent(DEFAULT_DIRECTIVES.strip(), " " * 12)
    mapping = write(tmp_path, """\
        base: BASE
        objects: [mug_classic]
        base_overrides:
          max_time: 9.0
        methods:
        - name: tilted
          overrides:
            grasp_method: antipodal
""" + directives + "\n", "mapping.yaml")
    assert "!Rpy" in mapping.read_text()
    text = write(tmp_path, """\
        base: BASE
        objects: [mug_classic]
        base_overrides: "max_time: 9.0"
        methods:
        - name: tilted
          overrides: "grasp_method: antipodal"
        """, "text.yaml")
    a = method_scenarios(load_experiment(mapping))["tilted"]
    b = method_scenarios(load_experiment(text))["tilted"]
    assert a.grasp_method == b.grasp_method == "antipodal"
    assert a.max_time == b.max_time == 9.0
    assert make_tasks(load_experiment(mapping))[0].digest == \
        make_tasks(load_experiment(text))[0].digest


def test_shipped_experiments():
    full = load_experiment(SCENARIOS_DIR / "experiment.yaml")
    controls = [o for o in full.objects if make_object(o).is_control]
    assert len(full.objects) - len(controls) >= 15 and len(controls) == 4
    assert full.trials == 5 and full.seed == 0 and full.replays == "failures"
    scenarios = method_scenarios(full)
    assert list(scenarios) == ["gbh-10", "gbh-1", "antipodal", "gbh+fallback", "gbh+"]
    assert [(s.grasp_method, s.scan.num_views, s.gbh.d2) for s in scenarios.values()] == [
        ("gbh", 10, 0.0), ("gbh", 1, 0.005), ("antipodal", 1, scenarios["antipodal"].gbh.d2),
        ("gbh_fallback", 10, 0.0), ("gbh_plus", 10, 0.0)]
    assert [s.gripper for s in scenarios.values()] == ["paper"] * 4 + ["wedge"]
    assert [m.paper for m in full.methods] == ["GbH 10 views", "GbH 1 view",
                                               "GraspNet 1 view", "", ""]
    beyond = load_experiment(SCENARIOS_DIR / "experiment_beyond.yaml")
    assert beyond.objects == full.objects and beyond.protocols == ["stable"]
    assert [s.grasp_method for s in method_scenarios(beyond).values()] == ["gbh_scoop",
                                                                           "gbh_regrasp"]
    small = load_experiment(SCENARIOS_DIR / "experiment_small.yaml")
    assert len(make_tasks(small)) <= 20


@pytest.mark.parametrize("text, where", [
    ("objects: [mug_classic]\ntrails: 5\n", "trails"),
    ("objects: [no_such_thing]\n", "objects[0]"),
    ("objects: [box, box]\n", "objects[1]"),
    ("objects: []\n", "objects"),
    ("objects: [box]\ntrials: 0\n", "trials"),
    ("objects: [box]\nreplays: some\n", "replays"),
    ("objects: [box]\npose: {x: [0.6, 0.5]}\n", "pose.x"),
    ("objects: [box]\nmethods: [{name: a}, {name: a}]\n", "methods[1].name"),
    ("objects: [box]\nmethods: [{name: a, paper: GbH 3 views}]\n", "methods[0].paper"),
    ("objects: [box]\nmethods: [{name: a, overrides: {grasp_methd: gbh}}]\n", "grasp_methd"),
    ("objects: [box]\nmethods: [{name: a, overrides: {grasp_method: magic}}]\n", "grasp_method"),
    ("objects: [box]\nbase: nowhere.yaml\n", "base"),
    ("objects: [box]\n", "base"),
])
def test_errors_name_the_field(tmp_path, text, where):
    path = write(tmp_path, text if "base" in where else "base: BASE\n" + text)
    with pytest.raises(ExperimentError, match=r"exp\.yaml") as error:
        method_scenarios(load_experiment(path))
    assert where in str(error.value)


# ---- protocols: stable (today's) and natural ---------------------------------------------------
def test_the_stable_protocol_keeps_the_seeds_and_a_natural_one_has_its_own():
    assert trial_seed(0, "mug_classic", 0, "stable") == trial_seed(0, "mug_classic", 0) == \
        374982299
    natural = [trial_seed(0, "mug_classic", t, "natural") for t in range(3)]
    assert natural == [trial_seed(0, "mug_classic", t, "natural") for t in range(3)]
    assert natural[0] == 2109864392  # golden: sha256 of "natural" after (seed, name, trial)
    assert len(set(natural)) == 3
    assert not set(natural) & {trial_seed(0, "mug_classic", t) for t in range(3)}


def test_protocols_default_to_stable_and_leave_todays_trials_as_they_were():
    stable = load_experiment(SHORT)
    assert stable.protocols == ["stable"]
    both = load_experiment(SHORT, overrides="protocols: [stable, natural]")
    tasks = make_tasks(both)
    assert len(tasks) == 2 * len(make_tasks(stable))
    assert len({t.key for t in tasks}) == len(tasks)  # (object, method, trial, protocol)
    by_key = {t.key: t for t in tasks}
    for t in make_tasks(stable):  # same seed, same scenario text, same digest: rows resume
        assert t.protocol == "stable" and t.key[3] == "stable"
        assert (by_key[t.key].seed, by_key[t.key].digest) == (t.seed, t.digest)
        assert "rest:" not in t.scenario_yaml
    natural = [t for t in tasks if t.protocol == "natural"]
    for t in natural:
        twin = by_key[(t.object, t.method, t.trial, "stable")]
        assert t.seed == trial_seed(both.seed, t.object, t.trial, "natural") != twin.seed
        assert "rest: natural" in t.scenario_yaml and t.digest != twin.digest
    # every method sees the same natural pose of an (object, trial)
    assert len({(t.object, t.trial, t.seed) for t in natural}) == len(natural) // 4


def test_the_shipped_experiment_runs_both_protocols():
    assert load_experiment(SCENARIOS_DIR / "experiment.yaml").protocols == ["stable", "natural"]


def assert_refused(tmp_path, text: str, where: str, words: str) -> None:
    """An experiment file (a box, the base scenario, then ``text``) is refused with an error
    that names the file, the field ``where`` and its line, and says ``words``."""
    path = write(tmp_path, "base: BASE\nobjects: [box]\n" + text)
    with pytest.raises(ExperimentError, match=r"exp\.yaml") as error:
        load_experiment(path)
    assert re.search(rf": {re.escape(where)} \(line \d+\): ", str(error.value)), error.value
    assert words in str(error.value)


@pytest.mark.parametrize("text, where, words", [
    ("protocols: [stable, upright]\n", "protocols[1]", "must be one of stable, natural; got "
                                                        "'upright'"),
    ("protocols: [natural, natural]\n", "protocols[1]", "listed twice"),
    ("protocols: []\n", "protocols", "at least one"),
    ("protocols: [natural]\npose: {rest: natural}\n", "pose.rest", "set by each protocol"),
    ("protocols: [natural]\npose: {stable: false}\n", "pose.stable", "contradicts"),
])
def test_protocol_errors_name_the_file_and_field(tmp_path, text, where, words):
    assert_refused(tmp_path, text, where, words)


def test_an_object_without_a_natural_rest_is_refused_by_the_natural_protocol(
        tmp_path, monkeypatch):
    from gbh_drake.objects import catalog

    monkeypatch.delitem(catalog._RESTS, "kettle")  # as an object registered without rest=
    path = write(tmp_path, "base: BASE\nobjects: [box, kettle]\nprotocols: [stable, natural]\n")
    with pytest.raises(ExperimentError, match=r"exp\.yaml: protocols\[1\] \(line 3\): natural: "
                                              r"objects\[1\] 'kettle' \(line 2\) has no natural "
                                              r"rest"):
        load_experiment(path)
    load_experiment(path, overrides="protocols: [stable]")  # the stable protocol needs none


def test_one_trials_scenario_is_the_one_the_experiment_runs():
    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.experiment.config import ExperimentError, trial_scenario, trial_scenario_yaml

    experiment = load_experiment(SCENARIOS_DIR / "experiment.yaml")
    experiment.objects = ["mug_classic", "key_ring", "box"]
    tasks = {(t.object, t.method, t.trial, t.protocol): t for t in make_tasks(experiment)}
    for key in (("mug_classic", "gbh-10", 0, "stable"), ("key_ring", "gbh-1", 3, "natural"),
                ("box", "antipodal", 4, "stable")):
        scenario = trial_scenario(experiment, *key)
        assert trial_scenario_yaml(scenario) == tasks[key].scenario_yaml
    with pytest.raises(ExperimentError, match="no method 'graspnet'"):
        trial_scenario(experiment, "mug_classic", "graspnet", 0)


# ---- where the trials run: engine and ray_address ----------------------------------------------
def test_the_engine_is_local_by_default_and_the_file_may_name_a_ray_cluster(tmp_path):
    default = load_experiment(SHORT)
    assert (default.engine, default.ray_address, default.ray_engine_address()) == \
        ("local", "local", "")
    path = write(tmp_path, "base: BASE\nobjects: [box]\nengine: ray\n"
                           "ray_address: 10.0.0.5:6379\n")
    assert load_experiment(path).ray_engine_address() == "10.0.0.5:6379"
    for address in ("local", "auto", "head.example:6379", "ray://10.0.0.5:10001",
                    "[::1]:6379"):
        experiment = load_experiment(path, overrides=f"ray_address: '{address}'")
        assert experiment.ray_engine_address() == address
    # an address without engine: ray is not used (--set 'engine: local' runs locally)
    assert load_experiment(path, overrides="engine: local").ray_engine_address() == ""


def test_the_engine_changes_no_trial_nor_the_folders_definition():
    """Where the trials run is not what they are: the same tasks, digests and experiment.yaml
    (a folder's rows resume whatever engine ran them)."""
    from gbh_drake.experiment.config import experiment_yaml

    local = load_experiment(SHORT)
    ray = load_experiment(SHORT, overrides="{engine: ray, ray_address: '10.0.0.5:6379'}")
    assert make_tasks(ray) == make_tasks(local)
    assert experiment_yaml(ray) == experiment_yaml(local)
    assert "engine" not in experiment_yaml(ray) and "6379" not in experiment_yaml(ray)
    assert "engine" not in make_tasks(ray)[0].scenario_yaml


@pytest.mark.parametrize("text, where, words", [
    ("engine: Ray\n", "engine", "must be one of local, ray; got 'Ray' (local worker processes, "
                                "or Ray tasks at ray_address)"),
    ("engine: slurm\n", "engine", "got 'slurm'"),
    ("engine: ray\nray_address: 10.0.0.5\n", "ray_address", "not 'local', 'auto' or a "
                                                            "cluster's address host:port"),
    ("ray_address: ''\n", "ray_address", "got ''"),
    ("ray_address: 'head:99999'\n", "ray_address", "got 'head:99999'"),
    ("ray_address: [head]\n", "ray_address", "expected a string"),
])
def test_engine_errors_name_the_file_and_field(tmp_path, text, where, words):
    assert_refused(tmp_path, text, where, words)


def test_engine_ray_without_ray_is_one_line_naming_the_file_and_field(tmp_path, monkeypatch,
                                                                      capsys):
    import sys

    from gbh_drake.cli import main

    monkeypatch.setitem(sys.modules, "ray", None)  # as if Ray were not installed
    path = write(tmp_path, "base: BASE\nobjects: [box]\nengine: ray\n")
    assert main(["experiment", str(path), "--out", str(tmp_path / "out"),
                 "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert err.startswith(f"gbh: cannot use Ray: {path}: engine (line 3): ray needs Ray, which "
                          "is not installed in this environment: pip install "
                          "'gbh_drake[ray]' (or --set 'engine: local' "), err
    assert not (tmp_path / "out").exists()  # nothing ran


def test_each_task_is_the_trial_scenario_dumped_alone():
    """make_tasks dumps one YAML per (method, object, protocol) and sets the seed line for the
    other trials: every task's text, seed and digest equal those of its scenario dumped alone."""
    import copy
    import hashlib

    from gbh_drake.experiment.config import _set_trial, experiment_objects, trial_scenario_yaml

    experiment = load_experiment(SCENARIOS_DIR / "experiment_small.yaml",
                                 overrides="trials: 3\nprotocols: [stable, natural]\n")
    scenarios = method_scenarios(experiment)
    tasks = make_tasks(experiment, scenarios=scenarios)
    objects = {o.name: o for o in experiment_objects(experiment)}
    assert len(tasks) == 4 * 3 * 2 * len(experiment.methods)
    for task in tasks:
        scenario = copy.deepcopy(scenarios[task.method])
        _set_trial(scenario, experiment, objects[task.object], task.trial, task.protocol)
        text = trial_scenario_yaml(scenario)
        assert (task.scenario_yaml, task.seed) == (text, scenario.seed)
        assert task.digest == hashlib.sha256(text.encode()).hexdigest()


def test_the_seed_line_is_set_only_where_it_is_alone():
    from gbh_drake.experiment.config import _with_seed

    text = "seed: 12\nobject:\n  name: mug\n  seed: 12\n"
    assert _with_seed(12, text, 345) == "seed: 345\nobject:\n  name: mug\n  seed: 12\n"
    assert _with_seed(13, text, 345) is None  # not the seed it was dumped with
    assert _with_seed(12, "object: {}\n", 345) is None  # no top-level seed
    assert _with_seed(12, text + "seed: 12\n", 345) is None  # two


def test_a_relative_path_given_by_set_is_the_current_folders(tmp_path, monkeypatch):
    """``gbh experiment <packaged file> --set "output_dir: out"`` writes into ./out, not beside
    the file (site-packages for a wheel); the file's own relative paths stay its folder's."""
    files, here = tmp_path / "files", tmp_path / "here"
    files.mkdir()
    here.mkdir()
    (files / "base.yaml").write_text("seed: 1\n")
    (here / "mine.yaml").write_text("seed: 2\n")
    path = write(files, "base: base.yaml\noutput_dir: out\nobjects: [box]\n")
    monkeypatch.chdir(here)
    experiment = load_experiment(path)
    assert (experiment.output_path(), experiment.base_path) == (files / "out", files / "base.yaml")
    experiment = load_experiment(path, overrides=["output_dir: out", "base: mine.yaml"])
    assert (experiment.output_path(), experiment.base_path) == (here / "out", here / "mine.yaml")


@pytest.mark.parametrize(("args", "kwargs", "message"), [
    (("exp.yaml",), {}, "run_experiment(): experiment: expected an Experiment "
                        "(gbh_drake.experiment.config.load_experiment(path)), got 'exp.yaml' (a str)"),
    ((), {"workers": 0}, "run_experiment(): workers: expected an integer >= 1, got 0 (an int)"),
    ((), {"workers": "2"}, "run_experiment(): workers: expected an integer >= 1, got '2' (a str)"),
    ((), {"out": 3}, "run_experiment(): out: expected a folder's path or None, got 3 (an int)"),
])
def test_run_experiment_names_an_argument_of_the_wrong_type(tmp_path, args, kwargs, message):
    from gbh_drake.experiment.runner import run_experiment

    args = args or (load_experiment(SHORT),)
    with pytest.raises(TypeError) as info:
        run_experiment(*args, **kwargs)
    assert str(info.value) == message
    assert not (tmp_path / "output").exists()
