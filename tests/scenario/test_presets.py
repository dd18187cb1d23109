"""The paper's values stay available as a preset: gbh: {preset: paper}."""

import dataclasses

import pytest

from gbh_drake.core.params import PRESETS, GbhInputError, GbhParams
from gbh_drake.scenario import ScenarioError, load_scenario


def _load(tmp_path, *overrides):
    path = tmp_path / "s.yaml"
    path.write_text("task: settle\n")
    return load_scenario(path, overrides=list(overrides))


def test_the_paper_preset_sets_the_papers_rules(tmp_path):
    ours, paper = GbhParams(), _load(tmp_path, "gbh: {preset: paper}").gbh
    assert paper.preset == "paper"
    for name, value in PRESETS["paper"].items():
        if hasattr(paper, name):
            assert getattr(paper, name) == value
    changed = {f.name for f in dataclasses.fields(GbhParams)
               if getattr(paper, f.name) != getattr(ours, f.name)}
    assert changed <= {"preset", *PRESETS["paper"]}
    assert paper.p_theta == 0.95 and paper.approach_rotations_deg == [0.0]


def test_the_robust_preset_turns_the_provisional_rules_on(tmp_path):
    """Opt-in until swept (docs/robustness.md): the defaults leave the provisional rules off
    (the paper's score, one position per cluster, no rods' clearance; forty grasps offered
    since it was measured, the paper's ten in its preset); ``robust`` turns them on at their
    provisional values, and nothing else."""
    ours, robust = GbhParams(), _load(tmp_path, "gbh: {preset: robust}").gbh
    assert GbhParams(preset="paper").top_k == 10
    assert (ours.hang_slide_scale, ours.positions_per_cluster, ours.rod_clearance,
            ours.top_k) == (0.0, 1, -1.0, 40)
    assert (robust.hang_slide_scale, robust.positions_per_cluster, robust.rod_clearance,
            robust.top_k) == (0.02, 4, 0.0025, 40)
    changed = {f.name for f in dataclasses.fields(GbhParams)
               if getattr(robust, f.name) != getattr(ours, f.name)}
    assert changed == {"preset", *PRESETS["robust"]}


def test_fields_written_beside_the_preset_or_later_still_win(tmp_path):
    gbh = _load(tmp_path, "gbh: {preset: paper, snap_tilt_max_deg: 10}", "gbh: {d2: 0.005}").gbh
    assert (gbh.preset, gbh.snap_tilt_max_deg, gbh.d2) == ("paper", 10.0, 0.005)
    assert gbh.approach_rotations_deg == [0.0]


def test_back_to_ours(tmp_path):
    gbh = _load(tmp_path, "gbh: {preset: paper}", "gbh: {preset: ''}").gbh
    assert gbh == GbhParams()


def test_an_unknown_preset_is_refused_in_yaml_and_code(tmp_path):
    with pytest.raises(ScenarioError, match=r"gbh\.preset \(line 1\): must be one of '', paper"):
        _load(tmp_path, "gbh: {preset: papr}")
    with pytest.raises(GbhInputError, match="preset"):
        GbhParams().with_preset("papr")


@pytest.mark.parametrize("name", list(PRESETS))
def test_a_preset_means_the_same_in_python_as_in_yaml(tmp_path, name):
    """``GbhParams(preset=name)`` is ``gbh: {preset: name}`` field by field, and so is
    ``GbhParams().with_preset(name)``; a field given beside it wins in both."""
    loaded = _load(tmp_path, f"gbh: {{preset: '{name}'}}").gbh
    for made in (GbhParams(preset=name), GbhParams().with_preset(name), GbhParams(name)):
        for f in dataclasses.fields(GbhParams):
            assert getattr(made, f.name) == getattr(loaded, f.name), (name, f.name)
    beside = _load(tmp_path, f"gbh: {{preset: '{name}', contact_angle_deg: 33, "
                             "approach_rotations_deg: [0, 10]}").gbh
    made = GbhParams(preset=name, contact_angle_deg=33.0, approach_rotations_deg=[0.0, 10.0])
    assert made == beside
    made.check()


def test_the_paper_preset_in_python_is_the_papers_rules():
    paper = GbhParams(preset="paper")
    assert (paper.snap_tilt_max_deg, paper.approach_rotations_deg, paper.contact_angle_deg,
            paper.unknown_is_occupied) == (0.0, [0.0], 30.0, False)
    assert GbhParams(preset="paper", contact_angle_deg=35.0).contact_angle_deg == 35.0  # given
    ours = dataclasses.replace(paper, d2=0.005)  # every field passed on: nothing re-applied
    assert ours.contact_angle_deg == 30.0 and ours.d2 == 0.005
    kept = dataclasses.replace(GbhParams(preset="paper", contact_angle_deg=35.0), d2=0.0)
    assert kept.contact_angle_deg == 35.0
    assert GbhParams(preset="papr").snap_tilt_max_deg == 45.0  # unknown: check() refuses it
    with pytest.raises(GbhInputError, match="preset"):
        GbhParams(preset="papr").check()
