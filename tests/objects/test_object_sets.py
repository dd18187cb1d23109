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
    ("  - {name: box, mesh: box.obj}\n", r"objects\[0\] \(box\)\.mass", "real object's mass"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, density: 500}\n", r"objects\[0\] \(box\)\.mass",
     "not both"),
    ("  - {name: box, mesh: pypi://somepkg/a/box.obj, mass: 0.1}\n",
     r"objects\[0\] \(box\)\.source", "needs its source"),
    ("  - {name: box, mesh: pypi://somepkg/a/box.obj, mass: 0.1, source: {package: other, "
     "version: '1', license: MIT}}\n", r"objects\[0\] \(box\)\.source\.package", "'somepkg'"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, rest: {as_given: true}}\n",
     r"objects\[0\] \(box\)\.rest\.reason", "one-line reason"),
    ("  - {builtin: teapot, mass: 2.0}\n", r"objects\[0\] \(teapot\)\.mass",
     "brings its own mesh"),
    ("  - {builtin: teapott}\n", r"objects\[0\] \(teapott\)\.builtin",
     "unknown built-in object 'teapott'"),
    ("  - {name: box, mesh: box.obj, mass: 0.1}\n  - {name: box, mesh: box.obj, mass: 0.2}\n",
     r"objects\[1\] \(box\)\.name", "objects[0] too"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, control: true, hangable_parts: "
     "[{center: [0, 0, 0], axis: [0, 0, 1], clear_diameter: 0.01}]}\n",
     r"objects\[0\] \(box\)\.hangable_parts", "a control has nothing"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, hangable_parts: [{center: [0, 0], axis: "
     "[0, 0, 1], clear_diameter: 0.01}]}\n", r"objects\[0\] \(box\)\.hangable_parts\[0\]\.center",
     "needs 3"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, scale: -1}\n", r"objects\[0\] \(box\)\.scale",
     "in (0, 1000]"),
    ("  - {name: box, mesh: box.obj, mass: 0.1, colour: red}\n", r"objects\[0\]\.colour",
     "unknown"),
])
def test_a_bad_entry_names_the_manifest_the_entry_and_the_field(meshes, entry, where, words):
    path = write(meshes, "name: mine\nobjects:\n" + entry)
    with pytest.raises(ObjectSetError, match=str(path).replace(".", r"\.") + ": " + where) as e:
        load_object_set(path)
    assert words in str(e.value)


def test_a_missing_mesh_is_found_missing_when_its_object_is_used(meshes):
    path = write(meshes, "objects:\n  - {name: gone, mesh: nowhere.obj, mass: 0.1}\n")
    object_set = load_object_set(path)
    with pytest.raises(ObjectSetError, match=r"objects\[0\] \(gone\)\.mesh: no mesh file .*"
                                             r"nowhere\.obj"):
        object_set.object("gone")


def test_an_uncached_pypi_mesh_says_how_to_fetch_it(meshes, monkeypatch, tmp_path):
    monkeypatch.setenv("GBH_DRAKE_CACHE", str(tmp_path / "cache"))
    path = write(meshes, "objects:\n  - {name: far, mesh: pypi://nosuchdist/x/mug.obj, "
                         "mass: 0.1, source: {package: nosuchdist, version: '1.0', "
                         "license: MIT}}\n")
    with pytest.raises(ObjectSetError, match=r"run `gbh objects fetch"):
        load_object_set(path).object("far")


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
    assert capsys.readouterr().out.splitlines()[0].startswith("my_mug")
    assert main(["objects", "list", "--set", str(meshes / "nothere.yaml")]) == 2
    assert "invalid object set" in capsys.readouterr().err
