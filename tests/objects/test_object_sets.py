"""Object sets as data: manifests load (the built-in one too), refuse bad entries naming the
manifest, the entry, the field and its line, and give assets with their ground truth in O."""

import numpy as np
import pytest
import trimesh
from mesh_shapes import filled_mug

from gbh_drake import SCENARIOS_DIR
from gbh_drake.modeling.object_asset import load_object_asset
from gbh_drake.modeling.object_config import ObjectConfig
from gbh_drake.objects.sets import ObjectSetError, load_object_set


@pytest.fixture
def meshes(tmp_path):
    """A mug (handle on +x, hole axis +y) written y-up, in millimetres, and a box."""
    mug = filled_mug()
    y_up = trimesh.transformations.rotation_matrix(-np.pi / 2, (1, 0, 0))  # z -> y
    mug.apply_transform(y_up)
    mug.apply_scale(1000.0)
    mug.export(tmp_path / "mug_mm_yup.stl")
    trimesh.creation.box((0.06, 0.08, 0.1)).export(tmp_path / "box.obj")
    return tmp_path


def write(folder, text: str):
    path = folder / "set.yaml"
    path.write_text(text)
    return path


MUG = """  - name: my_mug
    mesh: mug_mm_yup.stl
    scale: 0.001
    mass: 0.32
    rest: {rpy_deg: [90, 0, 0], reason: upright on its base}
    tags: [cup]
    hangable_parts:
      - {name: handle, center: [58.0e-3, 47.5e-3, 0], axis: [0, 0, 1], kind: closed,
         clear_diameter: 0.035}
"""


def test_the_builtin_set_is_a_manifest_of_the_generated_objects():
    from gbh_drake.objects import list_objects

    own = load_object_set(SCENARIOS_DIR / "object_sets" / "own.yaml")
    assert sorted(own.names) == list_objects()
    assert {n for n in own.names if "cup" in own.entry(n).tags} == {
        "mug_classic", "mug_large", "mug_square_handle", "pybullet_mug", "teacup"}
    assert own.object("box").is_control and not own.object("kettle").is_control


def test_a_mesh_entry_gives_its_asset_with_the_ground_truth_moved_into_O(meshes):
    path = write(meshes, "name: mine\nobjects:\n" + MUG + "  - {builtin: teapot}\n")
    object_set = load_object_set(path)
    assert object_set.names == ["my_mug", "teapot"]
    asset = load_object_asset(ObjectConfig(set=str(path), name="my_mug"), meshes)
    assert asset.name == "my_mug" and asset.mass == pytest.approx(0.32)
    (part,) = asset.hangable_parts
    # Turned into its natural rest (the file is y-up), then placed: frame O is the rest, the
    # ground truth moved with the mesh (the handle's hole halfway up, its axis along y).
    extent = asset.mesh.bounds[1] - asset.mesh.bounds[0]
    assert asset.mesh.bounds[0][2] == pytest.approx(0.0, abs=1e-9)
    assert extent[2] == pytest.approx(0.095, abs=1e-3)
    assert part.center_O[2] == pytest.approx(0.0475, abs=1e-3)
    assert abs(part.axis_O[1]) == pytest.approx(1.0, abs=1e-6)
    assert asset.natural_rest.rpy_deg == (0.0, 0.0, 0.0)  # as modelled, like a built-in's
    builtin = load_object_asset(ObjectConfig(set=str(path), name="teapot"), meshes)
    assert builtin.name == "teapot" and builtin.hangable_parts


@pytest.mark.parametrize("entry, where, words", [
    ("  - {name: Bad-Name, mesh: box.obj, mass: 0.1}\n", r"objects\[0\] \(Bad-Name\)\.name "
     r"\(line 3\)", "letters a-z, digits and underscores"),
    ("  - {name: box, mesh: box.obj}\n", r"objects\[0\] \(box\)\.mass \(line 3\)",
     "real object's mass"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, density: 500}\n",
     r"objects\[0\] \(box\)\.mass \(line 3\)", "not both"),
    ("  - {name: box, mesh: pypi://somepkg/a/box.obj, mass: 0.1}\n",
     r"objects\[0\] \(box\)\.source \(line 3\)", "needs its source"),
    ("  - {name: box, mesh: pypi://somepkg/a/box.obj, mass: 0.1, source: {package: other, "
     "version: '1', license: MIT}}\n", r"objects\[0\] \(box\)\.source\.package \(line 3\)",
     "'somepkg'"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, rest: {as_given: true}}\n",
     r"objects\[0\] \(box\)\.rest\.reason \(line 3\)", "one-line reason"),
    ("  - {builtin: teapot, mass: 2.0}\n", r"objects\[0\] \(teapot\)\.mass \(line 3\)",
     "brings its own mesh"),
    ("  - {builtin: teapott}\n", r"objects\[0\] \(teapott\)\.builtin \(line 3\)",
     "unknown built-in object 'teapott'"),
    ("  - {name: box, mesh: box.obj, mass: 0.1}\n  - {name: box, mesh: box.obj, mass: 0.2}\n",
     r"objects\[1\] \(box\)\.name \(line 4\)", "objects[0] too"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, control: true, hangable_parts: "
     "[{center: [0, 0, 0], axis: [0, 0, 1], clear_diameter: 0.01}]}\n",
     r"objects\[0\] \(box\)\.hangable_parts \(line 3\)", "a control has nothing"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, hangable_parts: [{center: [0, 0], axis: "
     "[0, 0, 1], clear_diameter: 0.01}]}\n",
     r"objects\[0\] \(box\)\.hangable_parts\[0\]\.center \(line 3\)", "needs 3"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, scale: -1}\n",
     r"objects\[0\] \(box\)\.scale \(line 3\)", "in (0, 1000]"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, colour: red}\n",
     r"objects\[0\] \(box\)\.colour \(line 3\)", "unknown"),
    # An unknown or mistyped field names its entry too (it read "objects[1].densty").
    ("  - {name: a, mesh: box.obj, mass: 0.1}\n  - name: box\n    mesh: box.obj\n"
     "    densty: 900\n", r"objects\[1\] \(box\)\.densty \(line 6\)", "did you mean 'density'"),
    ("  - {builtin: teapot}\n  - name: box\n    mesh: box.obj\n    mass: heavy\n",
     r"objects\[1\] \(box\)\.mass \(line 6\)", "heavy"),
    # Written over several lines, a field left out is the line of what holds it (it read
    # "line 2", the line of objects:, for every entry).
    ("  - {name: a, mesh: box.obj, mass: 0.1}\n  - name: box\n    mesh: box.obj\n",
     r"objects\[1\] \(box\)\.mass \(line 4\)", "real object's mass"),
    ("  - {name: a, mesh: box.obj, mass: 0.1}\n  - name: box\n    mesh: box.obj\n"
     "    mass: 0.1\n    rest:\n      as_given: true\n", r"objects\[1\] \(box\)\.rest\.reason "
     r"\(line 7\)", "one-line reason"),
    ("  - {name: a, mesh: box.obj, mass: 0.1}\n  - name: box\n    mass: 0.1\n"
     "    mesh: pypi://somepkg/a/box.obj\n", r"objects\[1\] \(box\)\.source \(line 4\)",
     "needs its source"),
])
def test_a_bad_entry_names_the_manifest_the_entry_and_the_field(meshes, entry, where, words):
    path = write(meshes, "name: mine\nobjects:\n" + entry)
    with pytest.raises(ObjectSetError, match=str(path).replace(".", r"\.") + ": " + where) as e:
        load_object_set(path)
    assert words in str(e.value)


def test_a_missing_mesh_is_found_missing_when_its_object_is_used(meshes):
    path = write(meshes, "objects:\n  - name: gone\n    mass: 0.1\n    mesh: nowhere.obj\n")
    object_set = load_object_set(path)
    with pytest.raises(ObjectSetError, match=r"set\.yaml: objects\[0\] \(gone\)\.mesh \(line 4\): "
                                             r"no mesh file .*nowhere\.obj"):
        object_set.object("gone")


def test_a_misspelt_mesh_file_names_the_nearest_file_as_a_pypi_one_does(meshes):
    # It said only "no mesh file .../bxo.obj"; a pypi:// path said "(did you mean ...?)".
    path = write(meshes, "objects:\n  - {name: crate, mass: 0.1, mesh: bxo.obj}\n"
                         "  - {name: far, mass: 0.1, mesh: nofolder/box.obj}\n")
    object_set = load_object_set(path)
    with pytest.raises(ObjectSetError, match=r"objects\[0\] \(crate\)\.mesh \(line 2\): no mesh "
                                             r"file .*bxo\.obj \(did you mean box\.obj\?\)$"):
        object_set.object("crate")
    with pytest.raises(ObjectSetError, match=r"objects\[1\] \(far\)\.mesh \(line 3\): no mesh "
                                             r"file .*nofolder/box\.obj \(no folder .*nofolder\)$"):
        object_set.object("far")


def test_an_uncached_pypi_mesh_says_how_to_fetch_it(meshes, monkeypatch, tmp_path):
    monkeypatch.setenv("GBH_DRAKE_CACHE", str(tmp_path / "cache"))
    path = write(meshes, "objects:\n  - {name: far, mesh: pypi://nosuchdist/x/mug.obj, "
                         "mass: 0.1, source: {package: nosuchdist, version: '1.0', "
                         "license: MIT}}\n")
    with pytest.raises(ObjectSetError, match=r"\.mesh \(line 2\): pypi://nosuchdist/x/mug\.obj: "
                                             r"not in the cache .*; run `gbh objects fetch --set "
                                             + str(path).replace(".", r"\.") + "`"):
        load_object_set(path).object("far")


PYPI_MUG = ("objects:\n  - name: toy\n    mesh: pypi://toypkg/toypkg/assets/objects/mug/{file}\n"
            "    source: {{package: toypkg, version: '{version}', license: MIT}}\n"
            "    mass: 0.1\n")


def test_a_pypi_mesh_is_read_from_the_installed_distribution(meshes, installed_toypkg):
    path = write(meshes, PYPI_MUG.format(file="mug.obj", version="1.0"))
    assert load_object_set(path).object("toy").mesh_path == \
        installed_toypkg / "toypkg/assets/objects/mug/mug.obj"


@pytest.mark.parametrize("file, version, where, words", [
    # a typo: the installed files are the wheel's, so fetching cannot help (it said to)
    ("mugg.obj", "1.0", r"\.mesh \(line 3\)", r"no such file in toypkg 1\.0 \(.*site\): "
     r"toypkg/assets/objects/mug/mugg\.obj \(did you mean mug\.obj\?\)"),
    # another version than the installed one, not fetched (it said: not in the cache)
    ("mug.obj", "9.9.9", r"\.source\.version \(line 4\)", r"installed 1\.0, the entry asks "
     r"9\.9\.9, which is not in the cache either \(.*\): give version: '1\.0', or run "
     r"`gbh objects fetch --set "),
])
def test_a_pypi_mesh_not_found_says_what_to_fix(meshes, installed_toypkg, monkeypatch, tmp_path,
                                               file, version, where, words):
    monkeypatch.setenv("GBH_DRAKE_CACHE", str(tmp_path / "cache"))
    path = write(meshes, PYPI_MUG.format(file=file, version=version))
    with pytest.raises(ObjectSetError, match=r"objects\[0\] \(toy\)" + where + ": " + words):
        load_object_set(path).object("toy")


def test_a_set_mesh_whose_size_cannot_be_simulated_is_refused_as_a_plain_mesh_is(meshes):
    """A mug in millimetres without ``scale: 0.001``: 132 m across. A scenario's ``object.mesh``
    refused it, an object set's was simulated (empty scan, a failed trial)."""
    from gbh_drake.scenario import ScenarioError, load_scenario

    path = write(meshes, "objects:\n  - name: my_mug\n    mesh: mug_mm_yup.stl\n"
                         "    mass: 0.32\n")
    with pytest.raises(ObjectSetError) as refused:
        load_object_set(path).rest_mesh("my_mug")
    assert (refused.value.field, refused.value.line) == ("objects[0] (my_mug).scale", 2)
    assert refused.value.problem.startswith(f"{meshes / 'mug_mm_yup.stl'}: largest extent ")
    assert "is larger than the workspace" in refused.value.problem
    assert "looks like millimetres: give scale: 0.001" in refused.value.problem
    mesh = meshes / "mug_mm_yup.stl"
    with pytest.raises(ScenarioError) as plain:
        load_scenario(SCENARIOS_DIR / "default.yaml",
                      overrides=f"object: {{mesh: {mesh}, mass: 0.32}}")
    assert plain.value.problem == refused.value.problem  # the same refusal, word for word
    with pytest.raises(ScenarioError) as run:  # gbh run's
        load_scenario(SCENARIOS_DIR / "default.yaml",
                      overrides=f"object: {{set: {path}, name: my_mug}}")
    assert run.value.field == "object.set" and run.value.problem == str(refused.value)
    scaled = write(meshes, "objects:\n  - {name: my_mug, mesh: mug_mm_yup.stl, mass: 0.32, "
                           "scale: 0.001}\n")
    assert max(load_object_set(scaled).rest_mesh("my_mug").extents) == pytest.approx(0.1325)


@pytest.mark.parametrize("part, field, scale, hinted", [
    ("{center: [58, 47.5, 0], axis: [0, 0, 1], clear_diameter: 30}", "center[0]", "", True),
    ("{center: [0.058, 0.047, 0], axis: [0, 0, 1], clear_diameter: 30}", "clear_diameter", "",
     True),
    # scale given: the part's length is wrong by itself, no millimetre hint
    ("{center: [0.058, 0.047, 0], axis: [0, 0, 1], clear_diameter: 30}", "clear_diameter",
     "    scale: 0.001\n", False),
])
def test_a_part_in_millimetres_names_the_missing_scale(meshes, part, field, scale, hinted):
    """The mug's handle written in millimetres, as its file is: the part's range refused it
    before the mesh's size could say "looks like millimetres", with nothing about scale."""
    path = write(meshes, f"objects:\n  - name: my_mug\n    mesh: mug_mm_yup.stl\n{scale}"
                         f"    mass: 0.32\n    hangable_parts:\n      - {part}\n")
    with pytest.raises(ObjectSetError) as refused:
        load_object_set(path)
    assert refused.value.field == f"objects[0] (my_mug).hangable_parts[0].{field}"
    assert refused.value.problem.startswith("must be in ")
    hint = "parts are in metres, after the entry's scale; a mesh in millimetres needs scale: 0.001"
    assert (hint in refused.value.problem) is hinted


def test_a_hangable_part_off_its_mesh_is_refused_on_its_center(meshes):
    """A handle's centre given in centimetres (5.8, 4.75, 0 for 0.058, 0.0475, 0): inside the
    field's range of +-10 m, it was taken as ground truth 7 m away from the 13-cm mug, and every
    trial's "part found" would read 0."""
    from gbh_drake.scenario import ScenarioError, load_scenario

    text = "objects:\n" + MUG
    path = write(meshes, text.replace("center: [58.0e-3, 47.5e-3, 0]", "center: [5.8, 4.75, 0]"))
    with pytest.raises(ObjectSetError) as refused:
        load_object_set(path).rest_mesh("my_mug")
    assert (refused.value.field, refused.value.line) == (
        "objects[0] (my_mug).hangable_parts[0].center", 9)
    assert refused.value.problem.startswith(
        f"{meshes / 'mug_mm_yup.stl'}: (5.8, 4.75, 0) lies ")
    assert refused.value.problem.endswith("cm outside the mesh (x -0.041 to 0.091, y 0.000 to "
                                          "0.095, z -0.041 to 0.041 m): give the centre in "
                                          "metres in the file's frame, after scale")
    with pytest.raises(ScenarioError) as run:  # gbh run's
        load_scenario(SCENARIOS_DIR / "default.yaml",
                      overrides=f"object: {{set: {path}, name: my_mug}}")
    assert run.value.problem == str(refused.value)
    load_object_set(write(meshes, text)).rest_mesh("my_mug")  # in metres: taken


def test_a_file_that_is_not_a_mesh_names_the_manifest_entry_and_field(meshes, tmp_path):
    """It said ``invalid mesh: nofaces.obj: not a mesh``; from a scenario in another folder,
    the manifest's path read ``.../a/../b/set.yaml``."""
    from gbh_drake.scenario import ScenarioError, load_scenario

    (meshes / "points.obj").write_text("v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\n")
    path = write(meshes, "name: mine\nobjects:\n  - {name: box, mesh: box.obj, mass: 0.1}\n"
                         "  - name: dots\n    mesh: points.obj\n    mass: 0.1\n")
    with pytest.raises(ObjectSetError) as e:
        load_object_set(path).rest_mesh("dots")
    assert str(e.value).startswith(f"{path}: objects[1] (dots).mesh (line 5): "
                                   f"{meshes / 'points.obj'}: ")
    (tmp_path / "elsewhere").mkdir()
    scenario = tmp_path / "elsewhere" / "s.yaml"
    scenario.write_text("object: {set: ../set.yaml, name: dots}\n")
    with pytest.raises(ScenarioError) as run:
        load_scenario(scenario)
    assert run.value.problem == str(e.value) and "/../" not in str(run.value)


def test_gbh_objects_list_shows_a_set_as_text_csv_and_json(meshes, capsys):
    import csv
    import io
    import json

    from gbh_drake.cli import main

    path = write(meshes, "name: mine\nobjects:\n" + MUG + "  - {builtin: box}\n")
    assert main(["objects", "list", "--set", str(path), "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [r["name"] for r in rows] == ["my_mug", "box"]
    assert rows[0]["mass_g"] == pytest.approx(320.0) and rows[0]["tags"] == ["cup"]
    assert rows[0]["hangable_parts"].startswith("handle (closed, 35.0 mm)")
    assert rows[1]["control"] and rows[1]["hangable_parts"] == "none (control)"
    assert main(["objects", "list", "--set", str(path), "--csv"]) == 0
    table = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert [r["name"] for r in table] == ["my_mug", "box"] and table[0]["tags"] == "cup"
    assert main(["objects", "list", "--set", str(path)]) == 0
    header, mug, *_ = capsys.readouterr().out.splitlines()
    assert header.split()[:5] == ["object", "size", "x,", "y,", "z"] and "mass" in header
    assert mug.startswith("my_mug") and "320 g" in mug
    assert main(["objects", "list", "--set", str(meshes / "nothere.yaml")]) == 2
    assert "invalid object set" in capsys.readouterr().err


def test_gbh_objects_list_shows_an_object_that_cannot_be_used_as_refused(meshes, capsys):
    """It listed a mug in millimetres as 8200 x 12163 x 10000 cm (a warning below), exit 0."""
    import json

    from gbh_drake.cli import main

    path = write(meshes, "objects:\n  - {name: box, mesh: box.obj, mass: 0.3}\n"
                         "  - {name: my_mug, mesh: mug_mm_yup.stl, mass: 0.32}\n")
    assert main(["objects", "list", "--set", str(path)]) == 2
    out, err = capsys.readouterr()
    _, box, mug = out.splitlines()
    assert box.startswith("box ") and "300 g" in box
    where = f"{path}: objects[1] (my_mug).scale (line 3): {meshes / 'mug_mm_yup.stl'}: largest"
    assert mug.split()[:2] == ["my_mug", "refused:"] and where in mug
    assert len(err.splitlines()) == 1 and err.startswith(f"gbh: invalid object set: {where}")
    assert main(["objects", "list", "--set", str(path), "--json"]) == 2
    rows = json.loads(capsys.readouterr().out)
    assert rows[0]["error"] == "" and rows[1]["error"].startswith(where)
    assert rows[1]["size_cm"] is None and rows[1]["mass_g"] is None


@pytest.mark.parametrize("heavy, field, line", [("mass: 5.0", "mass", 2),
                                                ("density: 20000", "density", 2)])
def test_a_set_mesh_heavier_than_the_payload_is_refused_by_run_experiment_and_list(
        meshes, capsys, heavy, field, line):
    """A 6 x 8 x 10 cm box of 5 kg (or of 20000 kg/m^3: 9.6 kg): ``gbh run`` refused it, but
    ``gbh experiment`` ran it (a 5 kg load the Franka may not carry) and ``gbh objects list``
    listed it."""
    from gbh_drake.cli import main
    from gbh_drake.experiment.config import ExperimentError, load_experiment
    from gbh_drake.scenario import ScenarioError, load_scenario

    path = write(meshes, f"objects:\n  - {{name: box, mesh: box.obj, {heavy}}}\n"
                         "  - {name: light, mesh: box.obj, mass: 0.3}\n")
    where = f"{path}: objects[0] (box).{field} (line {line}): {meshes / 'box.obj'}: weighs "
    with pytest.raises(ScenarioError) as run:
        load_scenario(SCENARIOS_DIR / "default.yaml", overrides=f"object: {{set: {path}, "
                                                                "name: box}")
    assert run.value.field == "object.set" and str(run.value.problem).startswith(where)
    assert "kg, above the Franka's payload (3 kg)" in run.value.problem
    (meshes / "exp.yaml").write_text(f"base: {SCENARIOS_DIR / 'default.yaml'}\n"
                                     "object_set: set.yaml\ntrials: 1\n"
                                     "methods: [{name: gbh-10}]\n")
    with pytest.raises(ExperimentError) as experiment:  # before any trial
        load_experiment(meshes / "exp.yaml")
    assert str(experiment.value.problem).startswith(where)
    assert main(["objects", "list", "--set", str(path)]) == 2
    _, box, light = capsys.readouterr().out.splitlines()
    assert box.split()[:2] == ["box", "refused:"] and where in box and "300 g" in light
    load_object_set(path).check_payload("light", 3.0)  # the payload itself is allowed
