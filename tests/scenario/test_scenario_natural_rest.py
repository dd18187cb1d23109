"""The scenario's ``object.random_pose.rest``: ``natural`` starts a named object in its declared
natural rest (random yaw and position as for ``stable``); a mesh file, an object without a
declared rest, an unknown value or ``stable: false`` beside it are errors naming the field."""

import numpy as np
import pytest

from gbh_drake import SCENARIOS_DIR
from gbh_drake.scenario import ScenarioError, load_scenario

DEFAULT = SCENARIOS_DIR / "default.yaml"


def _start_pose(scenario):
    from gbh_drake.modeling.object_asset import initial_object_pose, load_object_asset

    asset = load_object_asset(scenario.object, scenario.directory)
    return initial_object_pose(scenario.object, asset, scenario.seed)


@pytest.mark.parametrize("name", ["mug_classic", "clothes_hanger"])
def test_natural_starts_the_object_in_its_rest_with_a_random_yaw(name):
    scenario = load_scenario(DEFAULT, overrides=f"{{seed: 3, object: {{name: {name}, "
                                                "random_pose: {rest: natural}}}")
    assert scenario.object.random_pose.rest == "natural"
    R = _start_pose(scenario).rotation().matrix()
    np.testing.assert_allclose(R[:, 2], [0.0, 0.0, 1.0], atol=1e-9)  # upright or flat: z up
    yaws = set()
    for seed in range(4):
        scenario.seed = seed
        R = _start_pose(scenario).rotation().matrix()
        yaws.add(round(float(np.arctan2(R[1, 0], R[0, 0])), 6))
    assert len(yaws) == 4


def test_stable_is_the_default_and_unchanged():
    scenario = load_scenario(DEFAULT, overrides="{object: {name: mug_classic, random_pose: {}}}")
    assert scenario.object.random_pose.rest == "stable"


@pytest.mark.parametrize("override, where, words", [
    ("{object: {random_pose: {rest: upright}}}", "object.random_pose.rest", "one of stable, natural"),
    ("{object: {random_pose: {rest: natural, stable: false}}}", "object.random_pose.stable",
     "give one of them"),
    (f"{{object: {{mesh: {SCENARIOS_DIR / 'meshes' / 'staple.obj'}, "  # (an override's path is
     "pose: {translation: [0.55, 0, 0]}}}\n"                        # the current folder's)
     "---\n{object: {random_pose: {rest: natural}}}", "object.random_pose.rest",
     "a mesh file (object.mesh) has none"),
])
def test_bad_rests_name_the_file_and_field(override, where, words):
    with pytest.raises(ScenarioError) as error:
        load_scenario(SCENARIOS_DIR / "default.yaml", overrides=override.split("\n---\n"))
    text = str(error.value)
    assert "default.yaml" in text and where in text and words in text, text


def test_an_object_without_a_declared_rest_is_an_error(monkeypatch):
    from gbh_drake.objects import catalog

    monkeypatch.delitem(catalog._RESTS, "kettle")
    with pytest.raises(ScenarioError, match=r"object\.random_pose\.rest.*kettle has no natural "
                                            r"rest declared"):
        load_scenario(DEFAULT, overrides="{object: {name: kettle, random_pose: {rest: natural}}}")
