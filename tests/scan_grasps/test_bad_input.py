"""Bad input to ``gbh grasps``: one line naming the file and the field, exit 2, before any work.

A cloud or a mesh in millimetres (the hint's --scale follows from the size), an object ``gbh run``
refuses (under 5 mm, over 1.2 m), a table given above the object, a cloud array that is not
(n, 3) or (n, 6), an empty or all-NaN depth image, a camera pose that is not a rotation or
holds a NaN, intrinsics that do not fit the image, depth images of the wrong size, a depth scale
that puts every pixel out of range, an 8-bit depth PNG, an unknown key, masks (of the object's
or the robot's pixels) of the wrong size or for some views only."""

import copy

import numpy as np
import pytest
import trimesh
import yaml

import gbh_drake
from gbh_drake.cli import main
from gbh_drake.scan_grasps.errors import GraspsInputError
from gbh_drake.scan_grasps.views import read_views, write_png

#: A camera 0.5 m above the table looking straight down (+z_C = -z_B, +x_C = +x_B).
X_BC = [[1.0, 0.0, 0.0, 0.5], [0.0, -1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.5], [0.0, 0.0, 0.0, 1.0]]
WIDTH, HEIGHT = 32, 24


def _views(folder, **changes) -> dict:
    """A valid views file (two 32x24 images of the table) in ``folder``; ``changes`` replace
    top-level keys (the views' own entries are edited by the tests)."""
    depth = np.full((HEIGHT, WIDTH), 500, dtype=np.uint16)  # 0.5 m at 1 mm units
    for i in range(2):
        write_png(folder / f"d{i}.png", depth)
    data = {"version": 1, "depth_scale": 0.001, "depth_range": [0.2, 1.5],
            "intrinsics": {"width": WIDTH, "height": HEIGHT, "fx": 30.0, "fy": 30.0,
                           "cx": 15.5, "cy": 11.5},
            "views": [{"depth": f"d{i}.png", "X_BC": copy.deepcopy(X_BC)} for i in range(2)]}
    data.update(changes)
    return data


def _write(folder, data) -> None:
    (folder / "views.yaml").write_text(yaml.safe_dump(data))


def _refused(folder, data, field: str, words: str, file: str = "views.yaml") -> str:
    """Writes ``data``, reads it: refused naming ``file`` and ``field``, saying ``words``;
    ``gbh grasps`` says it in one line and exits 2."""
    _write(folder, data)
    with pytest.raises(GraspsInputError) as error:
        read_views(folder)
    message = str(error.value)
    assert message.startswith(f"{folder / file}: {field}: "), message
    assert words in message, message
    return message


def test_a_valid_file_reads(tmp_path):
    _write(tmp_path, _views(tmp_path))
    views = read_views(tmp_path)
    assert len(views.views.depths) == 2 and views.views.depths[0][0, 0] == np.float32(0.5)
    assert views.views.intrinsics.cx == 16.0  # OpenCV's 15.5, Drake's pixel convention + 0.5


def test_a_camera_pose_that_is_not_a_rotation(tmp_path):
    data = _views(tmp_path)
    data["views"][1]["X_BC"][0][0] = 2.0
    _refused(tmp_path, data, "views[1].X_BC", "not a rotation")


def test_a_camera_pose_with_a_nan(tmp_path):
    data = _views(tmp_path)
    data["views"][0]["X_BC"][2][3] = float("nan")
    _refused(tmp_path, data, "views[0].X_BC[2][3]", "finite number")


def test_a_mirrored_camera_pose(tmp_path):
    data = _views(tmp_path)
    data["views"][0]["X_BC"][2][2] = 1.0  # det -1: a reflection
    _refused(tmp_path, data, "views[0].X_BC", "not a rotation")


def test_intrinsics_that_do_not_fit_the_image(tmp_path):
    data = _views(tmp_path)
    data["intrinsics"]["cx"] = 320.0  # a 640-pixel camera's, on a 32-pixel image
    _refused(tmp_path, data, "intrinsics.cx", "outside the image")


def test_depth_images_of_the_wrong_size(tmp_path):
    data = _views(tmp_path)
    write_png(tmp_path / "small.png", np.full((12, 16), 500, dtype=np.uint16))
    data["views"][1]["depth"] = "small.png"
    _refused(tmp_path, data, "views[1].depth", "16x12 pixels; the intrinsics say 32x24",
             file="small.png")


def test_an_empty_depth_image(tmp_path):
    data = _views(tmp_path)
    write_png(tmp_path / "empty.png", np.zeros((HEIGHT, WIDTH), dtype=np.uint16))
    data["views"][0]["depth"] = "empty.png"
    _refused(tmp_path, data, "views[0].depth", "no valid depth pixel", file="empty.png")


def test_an_all_nan_depth_image(tmp_path):
    data = _views(tmp_path)
    np.save(tmp_path / "nan.npy", np.full((HEIGHT, WIDTH), np.nan, dtype=np.float32))
    data["views"][0]["depth"] = "nan.npy"
    _refused(tmp_path, data, "views[0].depth", "all NaN", file="nan.npy")


def test_a_depth_scale_that_puts_every_pixel_out_of_range(tmp_path):
    data = _views(tmp_path, depth_scale=1.0)  # millimetres read as metres: 500 m
    _refused(tmp_path, data, "views[0].depth", "is depth_scale right?", file="d0.png")


def test_an_8_bit_depth_png(tmp_path):
    data = _views(tmp_path)
    write_png(tmp_path / "d0.png", np.full((HEIGHT, WIDTH), 50, dtype=np.uint8))
    _refused(tmp_path, data, "views[0].depth", "8-bit", file="d0.png")


def test_an_unknown_key_and_a_missing_one(tmp_path):
    _refused(tmp_path, _views(tmp_path, camera="realsense"), "camera", "unknown key")
    data = _views(tmp_path)
    del data["views"][0]["X_BC"]
    _refused(tmp_path, data, "views[0].X_BC", "missing")


@pytest.mark.parametrize("key", ["mask", "robot_mask"])
def test_masks_of_the_wrong_size_or_for_some_views_only(tmp_path, key):
    data = _views(tmp_path)
    write_png(tmp_path / "m.png", np.ones((HEIGHT, WIDTH), dtype=bool))
    write_png(tmp_path / "small.png", np.ones((12, 16), dtype=bool))
    data["views"][0][key] = "m.png"
    _refused(tmp_path, data, f"views[1].{key}", "give a mask for every view or for none")
    data["views"][1][key] = "small.png"
    _refused(tmp_path, data, f"views[1].{key}", "16x12 pixels; the depth image is 32x24",
             file="small.png")
    data["views"][1][key] = "m.png"
    _write(tmp_path, data)
    views = read_views(tmp_path).views
    masks = views.masks if key == "mask" else views.robot_masks
    assert len(masks) == 2 and all(m.all() for m in masks)
    assert (views.robot_masks if key == "mask" else views.masks) is None


def test_a_quaternion_pose_reads_as_the_matrix(tmp_path):
    data = _views(tmp_path)
    data["views"][0]["X_BC"] = {"translation": [0.5, 0.0, 0.5],
                                "quaternion_xyzw": [1.0, 0.0, 0.0, 0.0]}  # ROS's order: x
    _write(tmp_path, data)
    np.testing.assert_allclose(read_views(tmp_path).views.X_BCs[0], X_BC, atol=1e-12)


def _one_line(capsys) -> str:
    out, err = capsys.readouterr()
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err.strip()


def test_the_command_says_it_in_one_line_and_exits_2(tmp_path, capsys):
    data = _views(tmp_path)
    data["views"][1]["X_BC"][0][0] = 2.0
    _write(tmp_path, data)
    assert main(["grasps", str(tmp_path)]) == 2
    line = _one_line(capsys)
    assert line.startswith(f"gbh: invalid input: {tmp_path / 'views.yaml'}: views[1].X_BC: "), line
    assert not (tmp_path / "grasps.json").exists()


def test_a_cloud_in_millimetres(tmp_path, capsys):
    points = trimesh.creation.icosphere(radius=40.0).vertices + [550.0, 0.0, 40.0]
    np.save(tmp_path / "cloud.npy", points)
    assert main(["grasps", str(tmp_path / "cloud.npy")]) == 2
    line = _one_line(capsys)
    assert line.startswith(f"gbh: invalid input: {tmp_path / 'cloud.npy'}: points: "), line
    assert "millimetres" in line


def test_a_mesh_in_millimetres(tmp_path, capsys):
    trimesh.creation.box([80.0, 80.0, 100.0]).export(tmp_path / "box.stl")
    assert main(["grasps", str(tmp_path / "box.stl")]) == 2
    line = _one_line(capsys)
    assert line.startswith(f"gbh: invalid input: {tmp_path / 'box.stl'}: vertices: "), line
    assert "millimetres" in line


def test_a_cloud_of_nan(tmp_path, capsys):
    np.save(tmp_path / "cloud.npy", np.full((500, 3), np.nan))
    assert main(["grasps", str(tmp_path / "cloud.npy")]) == 2
    assert "points: all 500 points are NaN" in _one_line(capsys)


@pytest.mark.parametrize(("flag", "value", "words"), [
    ("--frame", "0,0,0,0,0", "a pose is x,y,z,roll,pitch,yaw"),
    ("--frame", "2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1", "not a rotation"),
    ("--table-plane", "0,0,0,1", "table_plane is a, b, c, d"),
    ("--target", "0.5,nan,0", "--target: 3 finite numbers"),
])
def test_bad_flags_are_usage_errors(tmp_path, capsys, flag, value, words):
    trimesh.creation.box([0.08, 0.08, 0.1]).export(tmp_path / "box.stl")
    with pytest.raises(SystemExit) as exit_:
        main(["grasps", str(tmp_path / "box.stl"), flag, value])
    assert exit_.value.code == 2
    assert words in capsys.readouterr().err


def _box_file(path, extents, z0: float = 0.0):
    """A box mesh of ``extents`` (in the file's units) standing at z = ``z0`` at x = 0.55 m."""
    box = trimesh.creation.box(extents)
    box.apply_translation([0.55, 0.0, z0 + extents[2] / 2])
    box.export(path)
    return path


@pytest.mark.parametrize(("extents", "refusal"), [
    ((0.82, 1.22, 1.0), "largest extent 1.22 m is larger than the workspace (> 1.2 m): looks "
                        "like inches: give {} 0.0254 (then 3.1 cm)"),
    ((82.0, 121.6, 100.0), "largest extent 122 m is larger than the workspace (> 1.2 m): looks "
                           "like millimetres: give {} 0.001 (then 12.2 cm)"),
    ((8.2, 12.16, 10.0), "largest extent 12.2 m is larger than the workspace (> 1.2 m): looks "
                         "like centimetres: give {} 0.01 (then 12.2 cm)"),
    ((0.0025, 0.0036, 0.003), "largest extent 3.6 mm is smaller than the scan and the gripper "
                              "can sense (< 5 mm): looks 100x too small: give {} 100 (then "
                              "36 cm)"),
])
def test_sizes_gbh_run_refuses_are_refused_with_its_hint_naming_scale(tmp_path, capsys, extents,
                                                                      refusal):
    """The thresholds, words and unit hint of ``gbh run``'s refusal (object.scale), the hint
    naming --scale: the factor follows from the size."""
    from gbh_drake.objects.plausibility import size_refusal

    path = _box_file(tmp_path / "box.stl", extents)
    assert main(["grasps", str(path)]) == 2
    assert _one_line(capsys) == f"gbh: invalid input: {path}: vertices: {refusal.format('--scale')}"
    assert size_refusal(trimesh.load(path)) == refusal.format("scale:")  # gbh run's words


def test_scale_gives_the_file_in_metres_and_the_hint_counts_it(tmp_path, capsys):
    """--scale 0.1 on a file in millimetres: still 12 m; the hint gives the total scale."""
    path = _box_file(tmp_path / "box.stl", (82.0, 121.6, 100.0))
    assert main(["grasps", str(path), "--scale", "0.1"]) == 2
    assert _one_line(capsys) == (f"gbh: invalid input: {path}: vertices: largest extent 12.2 m "
                                 "is larger than the workspace (> 1.2 m): looks like "
                                 "centimetres: give --scale 0.001 (then 12.2 cm)")


def test_a_cloud_in_millimetres_gets_the_scale_its_size_asks(tmp_path, capsys):
    box = trimesh.creation.box([82.0, 121.6, 100.0])
    points = np.vstack([box.vertices, trimesh.sample.sample_surface(box, 2000, seed=0)[0]])
    np.save(tmp_path / "cloud.npy", points + [550.0, 0.0, 50.0])
    assert main(["grasps", str(tmp_path / "cloud.npy")]) == 2
    assert _one_line(capsys) == (f"gbh: invalid input: {tmp_path / 'cloud.npy'}: points: spans "
                                 "82 x 121.6 x 100 (its units): not metres; looks like "
                                 "millimetres: give --scale 0.001 (then 12.2 cm)")


@pytest.mark.parametrize(("value", "words"), [
    ("0", "--scale: the file's units in metres, a positive finite number; got 0.0"),
    ("nan", "--scale: the file's units in metres, a positive finite number; got nan"),
])
def test_a_bad_scale_is_a_usage_error(tmp_path, capsys, value, words):
    path = _box_file(tmp_path / "box.stl", (0.08, 0.08, 0.1))
    with pytest.raises(SystemExit) as exit_:
        main(["grasps", str(path), "--scale", value])
    assert exit_.value.code == 2
    assert capsys.readouterr().err.endswith(f"gbh: error: {words}\n")
    with pytest.raises(ValueError, match="^scale: the file's units in metres, a positive "
                                         "finite number; got -1.0$"):
        gbh_drake.grasps(path, scale=-1.0)


@pytest.mark.parametrize(("kwargs", "words"), [
    ({"frame": 2.0 * np.eye(4)}, "frame: not a pose: its 3x3 part is not a rotation"),
    ({"frame": np.eye(3)}, "frame: a pose is a 4x4 matrix, got shape (3, 3)"),
    ({"target": [0.5, 0.0]}, "target: expected 3 finite coordinates (m, in B) or None, got "
                             "[0.5, 0.0] (a list)"),
    ({"table_z": "0"}, "table_z: expected a finite height (m, in B) or None, got '0' (a str)"),
    ({"seed": "3"}, "seed: expected an integer or None, got '3' (a str)"),
    ({"top": 2.5}, "top: expected an integer or None, got 2.5 (a float)"),
    ({"params": "paper"}, "params: expected a GbhParams or None, got 'paper' (a str)"),
    ({"pick": {"approach_distance": 0.1}}, "pick: expected a PickConfig or None"),
])
def test_a_bad_argument_of_grasps_is_named(tmp_path, kwargs, words):
    """The Python call checks its arguments as the command checks its flags (a frame that is no
    pose was taken as one; the others failed deep inside with numpy's or int()'s words)."""
    path = _box_file(tmp_path / "box.stl", (0.08, 0.08, 0.1))
    with pytest.raises(ValueError) as error:
        gbh_drake.grasps(path, **kwargs)
    assert str(error.value).startswith(f"grasps(): {words}"), str(error.value)


def test_an_input_that_is_not_a_path_is_named():
    with pytest.raises(ValueError, match=r"^grasps\(\): input: expected a path \(a mesh, a point "
                                         r"cloud or a folder of depth images\), got .*\(a "
                                         r"Trimesh\)$"):
        gbh_drake.grasps(trimesh.creation.torus(0.04, 0.008))


def test_the_python_call_names_its_arguments_not_the_flags(tmp_path):
    """``gbh_drake.grasps`` told its caller to give ``--scale`` (the command's flag): its size
    and units hints name ``scale=``, as the call takes it."""
    path = _box_file(tmp_path / "box.stl", (82.0, 121.6, 100.0))
    with pytest.raises(GraspsInputError) as error:
        gbh_drake.grasps(path, scale=0.1)
    assert str(error.value) == (f"{path}: vertices: largest extent 12.2 m is larger than the "
                                "workspace (> 1.2 m): looks like centimetres: give scale=0.001 "
                                "(then 12.2 cm)")
    box = trimesh.creation.box([82.0, 121.6, 100.0])
    points = np.vstack([box.vertices, trimesh.sample.sample_surface(box, 200, seed=0)[0]])
    np.save(tmp_path / "cloud.npy", points + [550.0, 0.0, 50.0])
    with pytest.raises(GraspsInputError, match=r"not metres; looks like millimetres: give "
                                               r"scale=0\.001 \(then 12\.2 cm\)$"):
        gbh_drake.grasps(tmp_path / "cloud.npy")
    _write(tmp_path, _views(tmp_path))
    with pytest.raises(GraspsInputError, match=f"^{tmp_path}: scale: scales a mesh"):
        gbh_drake.grasps(tmp_path, scale=0.001)
    # A mesh's table note names the arguments too.
    small = _box_file(tmp_path / "small.stl", (0.08, 0.08, 0.1))
    assert any(note.endswith("give table_z= or table_plane= if it is elsewhere")
               for note in gbh_drake.grasps(small).notes)


def test_scale_on_depth_images_is_refused(tmp_path, capsys):
    _write(tmp_path, _views(tmp_path))
    assert main(["grasps", str(tmp_path), "--scale", "0.001"]) == 2
    assert _one_line(capsys) == (f"gbh: invalid input: {tmp_path}: --scale: scales a mesh or a "
                                 "point cloud; depth images are scaled by depth_scale in "
                                 "views.yaml")


def test_a_table_above_the_object_is_refused_naming_the_option(tmp_path, capsys):
    path = _box_file(tmp_path / "box.stl", (0.08, 0.08, 0.1))
    assert main(["grasps", str(path), "--table-z", "0.5"]) == 2
    assert _one_line(capsys) == (
        f"gbh: invalid input: {path}: --table-z: the table z = 0.5000 m lies above 100 % of the "
        "mesh's vertices (z 0.000 to 0.100 m in B; down to 500 mm below it): a table under the "
        "object lies at its lowest point or below (z = 0.0000 m); or give the input's pose in B "
        "with --frame")
    with pytest.raises(GraspsInputError) as error:  # the plane names its own argument
        gbh_drake.grasps(path, table_plane=[0.0, 0.0, 2.0, -1.0])
    assert str(error.value).startswith(f"{path}: table_plane: the table z = 0.5000 m lies "
                                       "above 100 % of the mesh's vertices")
    assert str(error.value).endswith("give the input's pose in B with frame=")


def test_a_table_above_a_cloud_is_refused(tmp_path, capsys):
    box = trimesh.creation.box([0.08, 0.08, 0.1])
    points = trimesh.sample.sample_surface(box, 2000, seed=0)[0] + [0.55, 0.0, 0.05]
    np.save(tmp_path / "c.npy", points)
    assert main(["grasps", str(tmp_path / "c.npy"), "--table-z", "0.5"]) == 2
    assert _one_line(capsys) == (
        f"gbh: invalid input: {tmp_path / 'c.npy'}: --table-z: the table z = 0.5000 m lies above "
        "100 % of the cloud's points (z 0.000 to 0.100 m in B; down to 500 mm below it): a "
        "table under the object lies at its lowest point or below (z = 0.0000 m); or give the "
        "input's pose in B with --frame")


def test_a_table_through_the_object_is_warned_of(tmp_path):
    """Half the box's vertices 3 cm under the given table: read, with a warning."""
    from gbh_drake.scan_grasps.inputs import InputOptions, load_input

    path = _box_file(tmp_path / "box.stl", (0.08, 0.08, 0.1))
    options = InputOptions(table=(np.array([0.0, 0.0, 1.0]), 0.03), table_option="--table-z")
    scan = load_input(path, options).scan
    assert scan.table.height == 0.03 and scan.table.source == "given"
    assert scan.warnings[-1] == (
        "the table z = 0.0300 m lies above 50 % of the mesh's vertices (z 0.000 to 0.100 m in B; "
        "down to 30 mm below it): GbH takes that part for under the table; is --table-z where "
        "the object stands?")
    options = InputOptions(table=(np.array([0.0, 0.0, 1.0]), 0.004), table_option="--table-z")
    assert not any("table" in w for w in load_input(path, options).scan.warnings)


def test_a_table_plane_of_zeros_says_its_numbers_plainly(tmp_path, capsys):
    path = _box_file(tmp_path / "box.stl", (0.08, 0.08, 0.1))
    with pytest.raises(SystemExit):
        main(["grasps", str(path), "--table-plane", "0,0,0,0"])
    assert capsys.readouterr().err.endswith(
        "gbh: error: table_plane is a, b, c, d (a x + b y + c z + d = 0), got [0.0, 0.0, 0.0, "
        "0.0]\n")


@pytest.mark.parametrize("columns", [2, 4, 5, 7])
def test_a_cloud_array_of_another_width_is_refused(tmp_path, capsys, columns):
    np.save(tmp_path / "c.npy", np.zeros((200, columns)))
    assert main(["grasps", str(tmp_path / "c.npy")]) == 2
    assert _one_line(capsys) == (f"gbh: invalid input: {tmp_path / 'c.npy'}: points: a cloud is "
                                 "an (n, 3) array of numbers (or (n, 6) with normals), got "
                                 f"float64 (200, {columns})")
