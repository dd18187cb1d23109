"""A bad scenario file fails with one clear message naming the file and the field."""

import pytest

from gbh_drake.cli import main
from gbh_drake.scenario import ScenarioError, load_scenario


def _write(tmp_path, text, name="bad.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ("object:\n  name: mug\n  bogus: 1\n", "object.bogus"),
        ("seed: seven\n", "seed"),
        ("object:\n  scale: [1, 2]\n", "object.scale"),
        ("robot:\n  q_home: [0, 0, 0]\n", "robot.q_home"),
        ("object:\n  mesh: does_not_exist.obj\n", "object.mesh"),
        ("plant_config:\n  time_stepp: 0.001\n", "plant_config"),
        ("cameras:\n- {name: c, width: wide}\n", "cameras[0]"),
        ("object:\n  pose:\n    translation: [1, 2]\n", "object.pose"),
        ("settle_time: -1\n", "settle_time"),
        ("object:\n  name: unicorn\n", "object.name"),
        ("task: dance\n", "task"),
        ("scan:\n  num_views: 0\n", "scan"),
        ("gbh:\n  contact_angle_deg: 120\n", "gbh"),
        ("scan:\n  bogus: 1\n", "scan.bogus"),
        ("object:\n  drop_height: -0.5\n", "object.drop_height"),
        ("robot:\n  hand: {kp: -3}\n", "robot"),
        ("visualization:\n  publish_period: 0\n", "visualization.publish_period"),
        ("gbh:\n  seed: 4\n", "gbh.seed"),
        ("directives: []\n", "directives"),
        ("seed: 0\nseed: 1\n", "seed (line 2): given twice"),
    ],
)
def test_error_names_file_and_field(tmp_path, text, field):
    path = _write(tmp_path, text)
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    message = str(info.value)
    assert str(path) in message
    assert field in message


def test_malformed_yaml_names_file_and_line(tmp_path):
    path = _write(tmp_path, "seed: 1\nobject: [\n")
    with pytest.raises(ScenarioError, match=r"bad\.yaml.*line"):
        load_scenario(path)


def test_missing_file(tmp_path):
    with pytest.raises(ScenarioError, match="nope.yaml: scenario file not found"):
        load_scenario(tmp_path / "nope.yaml")


def test_cli_reports_error_without_traceback(tmp_path, capsys):
    path = _write(tmp_path, "object:\n  nmae: mug\n")
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert "object.nmae" in err and "bad.yaml" in err and "Traceback" not in err


def test_relative_mesh_resolves_against_scenario_dir(tmp_path, staple_mesh):
    staple_mesh.export(tmp_path / "m.obj")
    scenario = load_scenario(_write(tmp_path, "object:\n  mesh: m.obj\n"))
    assert scenario.resolve(scenario.object.mesh) == tmp_path / "m.obj"


def test_overrides_apply_over_the_file(tmp_path):
    scenario = load_scenario(_write(tmp_path, "seed: 1\n"), overrides="seed: 5")
    assert scenario.seed == 5


def test_broken_mesh_file_is_named(tmp_path, capsys):
    (tmp_path / "broken.obj").write_text("hello world\n")
    path = _write(tmp_path, "object:\n  mesh: broken.obj\n")
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert "broken.obj" in err and "Traceback" not in err


def test_bad_directive_names_file_and_field(tmp_path, capsys):
    text = ("directives:\n"
            "- add_model: {name: panda, file: 'package://gbh_drake/panda_arm.urdf'}\n"
            "- add_model: {name: hook_gripper, file: 'package://gbh_drake/hook_gripper.sdf'}\n"
            "- add_model: {name: table, file: 'package://gbh_drake/no_such_table.sdf'}\n")
    path = _write(tmp_path, text)
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert "bad.yaml" in err and "directives" in err and "Traceback" not in err


def test_broken_mesh_is_refused_when_loading(tmp_path):
    (tmp_path / "flat.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(ScenarioError, match=r"bad\.yaml: object\.mesh: .*flat\.obj"):
        load_scenario(_write(tmp_path, "object:\n  mesh: flat.obj\n"))
