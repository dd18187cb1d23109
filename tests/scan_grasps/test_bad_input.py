"""Bad input to ``gbh grasps``: one line naming the file and the field, exit 2, before any work.

A cloud in millimetres, an empty or all-NaN depth image, a camera pose that is not a rotation or
holds a NaN, intrinsics that do not fit the image, depth images of the wrong size, a depth scale
that puts every pixel out of range, an 8-bit depth PNG, an unknown key."""

import copy

import numpy as np
import pytest
import trimesh
import yaml

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
