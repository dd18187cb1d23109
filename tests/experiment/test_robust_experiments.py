"""The robustness experiments (docs/robustness.md) pair with the committed ones: every trial of
their gbh-10 is, scenario for scenario, that experiment's gbh-10 trial of the same object, trial
and protocol, and gbh-10r's differs from it only in the provisional rules turned on."""

import difflib

import pytest

from gbh_drake import SCENARIOS_DIR
from gbh_drake.core.params import PRESETS
from gbh_drake.experiment.config import load_experiment, make_tasks


def _changed_fields(a: str, b: str) -> set[str]:
    """The field names on the lines where the scenario YAML ``a`` and ``b`` differ."""
    return {line[1:].split(":")[0].strip() for line in difflib.unified_diff(
        a.splitlines(), b.splitlines(), lineterm="", n=0)
        if line[:1] in "+-" and not line.startswith(("+++", "---"))}


@pytest.mark.parametrize("robust, committed", [
    ("experiment_robust.yaml", "experiment.yaml"),
    ("experiment_robust_external.yaml", "experiment_external.yaml"),
])
def test_a_robust_experiment_pairs_with_the_committed_one(robust, committed):
    ours, theirs = (load_experiment(SCENARIOS_DIR / name) for name in (robust, committed))
    assert [m.name for m in ours.methods] == ["gbh-10", "gbh-10r", "gbh+r"]
    assert (ours.name, ours.objects, ours.trials, ours.seed, ours.pose, ours.protocols) == \
        (theirs.name, theirs.objects, theirs.trials, theirs.seed, theirs.pose, theirs.protocols)
    tasks = {t.key: t for t in make_tasks(ours)}
    plain = [t for t in make_tasks(theirs) if t.method == "gbh-10"]
    assert plain
    for t in plain:
        assert tasks[t.key].scenario_yaml == t.scenario_yaml, t.key
    obj, _, trial, protocol = plain[0].key
    robust_yaml = tasks[(obj, "gbh-10r", trial, protocol)].scenario_yaml
    assert _changed_fields(plain[0].scenario_yaml, robust_yaml) == \
        {"preset", *PRESETS["robust"], "slide_lift"}
