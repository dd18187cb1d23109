"""ScenarioError as an API: origin, field, line and problem; the loader's behaviour on valid
YAML. The command-line corpus of bad inputs is in tests/input/."""

import pytest

from gbh_drake import SCENARIOS_DIR, station
from gbh_drake.modeling import names
from gbh_drake.scenario import RandomRestingPose, Scenario, ScenarioError, load_scenario, validate_scenario
from gbh_drake.scenario.checks import DRAKE_RULES
from gbh_drake.scenario.loader import apply_overrides


def _write(tmp_path, text, name="bad.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_error_has_origin_field_line_and_problem(tmp_path):
    path = _write(tmp_path, "seed: 1\nobject:\n  scale: -2\n")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    e = info.value
    assert (e.origin, e.field, e.line) == (str(path), "object.scale", 3)
    assert e.problem.startswith("must be in (0, 1000], got -2")
    assert str(e) == f"{path}: object.scale (line 3): {e.problem}"


def test_error_in_overrides_names_the_overrides(tmp_path):
    path = _write(tmp_path, "seed: 1\n")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path, overrides="seed: 2\nscan:\n  num_views: 0\n")
    assert (info.value.origin, info.value.field, info.value.line) == \
        (f"{path} (overrides)", "scan.num_views", 3)


def test_value_from_file_judged_after_overrides(tmp_path):
    """A field written in the file but made invalid by an override is reported where the
    override wrote what made it invalid: of two fields one of which bounds the other, the one
    written last is named."""
    path = _write(tmp_path, "settle_time: 1\nmax_time: 5\n")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path, overrides="settle_time: 6")
    assert (info.value.origin, info.value.field, info.value.line) == \
        (f"{path} (overrides)", "settle_time", 1)
    assert info.value.problem == "must be < max_time (5 s), got 6 s: the pick starts when " \
                                 "settling ends"
    with pytest.raises(ScenarioError) as info:  # written last in the file: there
        load_scenario(path, overrides="pick: {hold_time: 1}\nmax_time: 0.5")
    assert (info.value.origin, info.value.field, info.value.line) == \
        (f"{path} (overrides)", "max_time", 2)


def test_a_default_value_has_no_line(tmp_path):
    path = _write(tmp_path, "settle_time: 70\n")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    assert info.value.field == "settle_time" and info.value.line == 1
    path = _write(tmp_path, "task: pick\nsettle_time: 59\nmax_time: 58\n")
    with pytest.raises(ScenarioError, match=r"max_time \(line 3\): must exceed settle_time"):
        load_scenario(path)


def test_overrides_apply_over_the_file_in_order(tmp_path):
    path = _write(tmp_path, "seed: 1\n")
    assert load_scenario(path, overrides="seed: 5").seed == 5
    assert load_scenario(path, overrides=["seed: 5", "seed: 6"]).seed == 6
    assert load_scenario(path, overrides=["", "  \n", "# nothing\n"]).seed == 1


@pytest.mark.parametrize("text", [
    "", "\n\n  \n", "# a comment\n", "  # indented comment\n# another\n", "\ufeff# BOM\n",
])
def test_empty_file_is_the_default_scenario(tmp_path, text):
    scenario = load_scenario(_write(tmp_path, text))
    default = Scenario()
    assert scenario.seed == default.seed and scenario.object.name == default.object.name
    assert scenario.scan.num_views == default.scan.num_views


@pytest.mark.parametrize(("text", "check"), [
    ("scan:\n  voxel_size: 1e-3\n", lambda s: s.scan.voxel_size == 0.001),
    ("scan:\n  sdf_trunc: 4.0e-2\n", lambda s: s.scan.sdf_trunc == 0.04),
    ("pick:\n  max_lift: 3E-1\n", lambda s: s.pick.max_lift == 0.3),
    ("robot:\n  hand: {kp: 2.0e+4}\n", lambda s: s.robot.hand.kp == 20000.0),
    ("object:\n  pose:\n    translation: [5.5e-1, 0, 0]\n",
     lambda s: s.object.pose.translation[0] == 0.55),
    ("scan:\n# at column 0 inside the mapping\n  num_views: 1\n    # deeper\n  width: 320\n",
     lambda s: s.scan.num_views == 1 and s.scan.width == 320),
    ("object:\n  name: mug_classic  # trailing\n#\n  scale: 1.0\n",
     lambda s: s.object.scale == 1.0),
    ("seed: 3\r\nscan:\r\n  num_views: 1\r\n", lambda s: s.seed == 3 and s.scan.num_views == 1),
    ("seed: '7'\n", lambda s: s.seed == 7),
    ("_template: &views {num_views: 1}\nscan: *views\n", lambda s: s.scan.num_views == 1),
    ("base: &b {num_views: 1}\n", None),
    ("scan:\n  <<: {num_views: 1, width: 320}\n  width: 640\n",
     lambda s: s.scan.num_views == 1 and s.scan.width == 640),
    ("robot:\n  gripper_open: yes\n", lambda s: s.robot.gripper_open is True),
])
def test_valid_yaml_is_accepted(tmp_path, text, check):
    if check is None:  # an unknown top-level key is refused, private (_) ones are not
        with pytest.raises(ScenarioError, match="base"):
            load_scenario(_write(tmp_path, text))
        return
    assert check(load_scenario(_write(tmp_path, text)))


def test_relative_mesh_resolves_against_scenario_dir(tmp_path, staple_mesh):
    staple_mesh.export(tmp_path / "m.obj")
    scenario = load_scenario(_write(tmp_path, "object:\n  mesh: m.obj\n"))
    assert scenario.resolve(scenario.object.mesh) == tmp_path / "m.obj"


def test_broken_mesh_is_refused_when_loading(tmp_path):
    (tmp_path / "flat.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(ScenarioError, match=r"bad\.yaml: object\.mesh \(line 2\): .*flat\.obj"):
        load_scenario(_write(tmp_path, "object:\n  mesh: flat.obj\n"))


def test_validate_scenario_built_in_code():
    scenario = Scenario()
    validate_scenario(scenario, "<code>")
    scenario.robot.q_home = [0.0] * 7  # joint 4 at 0 is outside its limits
    with pytest.raises(ScenarioError, match=r"^<code>: robot.q_home\[3\]: 0 rad is outside"):
        validate_scenario(scenario, "<code>")


def test_station_names_match_the_validation():
    assert (names.ARM, names.GRIPPER) == (station.ARM, station.GRIPPER)
    assert names.HAND_ACTUATORS == station.HAND_ACTUATORS


def test_rules_name_existing_fields():
    """Every rule of the table of Drake's structs (DRAKE_RULES) names a field that exists (a
    renamed field would silently lose its check; our own fields carry their rules)."""
    scenario = Scenario()
    scenario.object.random_pose = RandomRestingPose()
    for section, rules in DRAKE_RULES.items():
        obj = scenario
        for part in section:
            obj = getattr(obj, part)
        missing = [name for name in rules if not hasattr(obj, name)]
        assert missing == [], f"{section}: {missing}"



def test_errors_pickle_with_their_parts():
    """Errors cross process boundaries (experiment workers) whole."""
    import pickle

    from gbh_drake.outputs import OutputError
    from gbh_drake.scenario import FieldError
    from gbh_drake.yamlfiles.yaml_text import YamlFieldError, YamlTextError

    for error in (ScenarioError("f.yaml", "seed", 2, "expected an integer", None),
                  ScenarioError("f.yaml", "", 3, "not valid YAML", 7),
                  OutputError("/x", "is a file"), FieldError(("robot", "q_home", 3), "outside"),
                  YamlFieldError(("a", 1), 4, "given twice"), YamlTextError("not UTF-8", 2, 5)):
        copy = pickle.loads(pickle.dumps(error))
        assert type(copy) is type(error) and str(copy) == str(error)
        assert vars(copy) == vars(error)


def test_a_later_layer_chooses_between_pose_and_random_pose(tmp_path):
    """The file gives a pose; an override asking for a random pose replaces it (and the other
    way round); both in one layer are refused with the field and line."""
    path = _write(tmp_path, "object:\n  name: kettle\n  pose: {translation: [0.5, 0.1, 0]}\n",
                  "posed.yaml")
    s = load_scenario(path, overrides="{object: {random_pose: {x: [0.5, 0.55]}}}")
    assert s.object.random_pose is not None and s.object.random_pose.x == [0.5, 0.55]
    assert list(s.object.pose.translation) == list(Scenario().object.pose.translation)
    s = load_scenario(path, overrides=["{object: {random_pose: {}}}",
                                       "{object: {pose: {translation: [0.6, 0, 0]}}}"])
    assert s.object.random_pose is None and list(s.object.pose.translation) == [0.6, 0, 0]
    with pytest.raises(ScenarioError) as e:
        load_scenario(path, overrides="{object: {pose: {translation: [0.5, 0, 0]}, "
                                      "random_pose: {}}}")
    assert "object.random_pose" in str(e.value) and "(overrides)" in str(e.value)
    assert "not both" in str(e.value)


# ---- overrides as given through the API: bytes, wrong types ------------------------------------


def test_overrides_given_as_bytes_are_read_as_a_file_is(tmp_path):
    path = _write(tmp_path, "seed: 1\n")
    assert load_scenario(path, overrides=b"seed: 5").seed == 5
    assert load_scenario(path, overrides=[b"\xef\xbb\xbfseed: 5", "seed: 6"]).seed == 6  # BOM
    from gbh_drake.scenario import dump_resolved

    text = "seed: 7\nscan: {num_views: 1}\ngbh: {preset: paper}\n"
    assert dump_resolved(load_scenario(path, overrides=text.encode())) == \
        dump_resolved(load_scenario(path, overrides=text))
    with pytest.raises(ScenarioError) as info:
        load_scenario(path, overrides="seed: 5".encode("utf-16"))
    assert str(info.value) == f"{path} (overrides): is UTF-16 text; save it as UTF-8"
    with pytest.raises(ScenarioError) as info:
        load_scenario(path, overrides=["seed: 2", b"# caf\xe9\nseed: 5"])
    assert str(info.value) == (f"{path} (overrides 2 of 2): line 1, column 6: is not UTF-8 text "
                               "(byte 0xe9); save it as UTF-8")


@pytest.mark.parametrize(("overrides", "where", "got"), [
    (None, "overrides", "None (a NoneType)"),
    (3, "overrides", "3 (an int)"),
    ({"seed": 3}, "overrides", "{'seed': 3} (a dict)"),
    (["seed: 3", None], "overrides[1]", "None (a NoneType)"),
])
def test_overrides_that_are_not_yaml_text_are_refused(tmp_path, overrides, where, got):
    path = _write(tmp_path, "seed: 1\n")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path, overrides=overrides)
    assert str(info.value) == (f"{path} ({where}): expected YAML text (a str, or bytes in UTF-8) "
                               f"or a list of them, got {got}")


@pytest.mark.parametrize("filename", [None, 3, b"x.yaml", Scenario()])
def test_a_file_name_that_is_not_a_path_is_refused(filename):
    with pytest.raises(ScenarioError, match=r"^load_scenario\(\): filename: expected a scenario "
                                            r"file's path \(a str or Path\), got "):
        load_scenario(filename)


@pytest.mark.parametrize("call", [
    lambda: validate_scenario("x.yaml", "o"),
    lambda: __import__("gbh_drake.scenario.loader").scenario.loader.apply_overrides("x.yaml", ""),
    lambda: __import__("gbh_drake.scenario.loader").scenario.loader.dump_resolved("x.yaml"),
])
def test_a_path_where_a_scenario_is_expected_is_named(call):
    with pytest.raises(ScenarioError, match=r"\(\): scenario: expected a Scenario \(of a file: "
                                            r"gbh_drake.scenario.load_scenario\(path\)\), got "
                                            r"'x.yaml' \(a str\)"):
        call()


# ---- relative paths: an override's are the current folder's, a file's its folder's ---------------


def test_a_relative_path_in_an_override_is_relative_to_the_current_folder(tmp_path, monkeypatch):
    here, there = tmp_path / "here", tmp_path / "there"
    here.mkdir()
    there.mkdir()
    import trimesh

    for folder in (here, there):
        trimesh.creation.box((0.05, 0.05, 0.05)).export(folder / "cube.obj")
    path = _write(there, "output_dir: out\nobject: {mesh: cube.obj}\n")
    monkeypatch.chdir(here)
    from_file = load_scenario(path)
    assert from_file.output_path() == there / "out"
    assert from_file.resolve(from_file.object.mesh) == there / "cube.obj"
    overridden = load_scenario(path, overrides=["output_dir: out", "object: {mesh: cube.obj}"])
    assert overridden.output_dir == str(here / "out") and overridden.output_path() == here / "out"
    assert overridden.object.mesh == str(here / "cube.obj")
    default = load_scenario(SCENARIOS_DIR / "default.yaml", overrides="output_dir: out")
    assert default.output_path() == here / "out"  # (not the packaged scenarios folder)
    assert load_scenario(path, overrides="output_dir: ~/out").output_dir == "~/out"  # absolute
    in_code = apply_overrides(Scenario(source_path=str(path)), "output_dir: out")
    assert in_code.output_path() == here / "out"
    (here / "cube.obj").unlink()
    with pytest.raises(ScenarioError) as info:  # the error names the override and its path
        load_scenario(path, overrides="object: {mesh: cube.obj}")
    assert (info.value.origin, info.value.field) == (f"{path} (overrides)", "object.mesh")
    assert str(here / "cube.obj") in info.value.problem
