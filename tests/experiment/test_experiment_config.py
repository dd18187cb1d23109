"""The experiment file: methods as overrides of a base scenario, seeds from (seed, object, trial)
alone, the shipped experiments, and errors that name the field."""

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
    assert [t.key for t in tasks] == [("box", "antipodal", 0), ("mug_classic", "antipodal", 0)]
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
    assert list(scenarios) == ["gbh-10", "gbh-1", "antipodal", "gbh+fallback"]
    assert [(s.grasp_method, s.scan.num_views, s.gbh.d2) for s in scenarios.values()] == [
        ("gbh", 10, 0.0), ("gbh", 1, 0.005), ("antipodal", 1, scenarios["antipodal"].gbh.d2),
        ("gbh_fallback", 10, 0.0)]
    assert [m.paper for m in full.methods] == ["GbH 10 views", "GbH 1 view",
                                               "GraspNet 1 view", ""]
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
