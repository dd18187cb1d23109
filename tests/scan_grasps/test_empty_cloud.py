"""A point cloud in which no object is found is a result, not a crash: ``none: empty_scan`` with
why (and the option that may fix it: the argument, ``target=``, or the flag, ``--target``),
exit 0, the document valid and holding the table."""

import json

import jsonschema
import numpy as np
import trimesh

import gbh_drake
from gbh_drake.cli import main
from gbh_drake.scan_grasps.document import JSON_SCHEMA, document
from gbh_drake.scan_grasps.inputs import NO_FREE_SPACE

#: What a cluster taken for the robot's own points says (a cloud in the object's frame).
ROBOT = ("clusters dropped: 1 robot (within 0.2 m of the robot's base at x, y = 0, 0 m in B, "
         "taken for the robot's own points: a cloud in another frame, e.g. the object's own, "
         "centred at its origin? give its pose in B with --frame)")


def box_cloud(centre) -> np.ndarray:
    """Points (m) on a 8 x 8 x 10 cm box standing on z = 0 at ``centre`` (x, y): its corners and
    20000 samples of its surface."""
    box = trimesh.creation.box([0.08, 0.08, 0.1])
    box.apply_translation([centre[0], centre[1], 0.05])
    samples, _ = trimesh.sample.sample_surface(box, 20000, seed=0)
    return np.vstack([box.vertices, samples])


def table_cloud() -> np.ndarray:
    """A table alone: a 1 cm grid on z = 0, x 0.3-0.7 m, y -0.2-0.2 m."""
    x, y = np.meshgrid(np.linspace(0.3, 0.7, 41), np.linspace(-0.2, 0.2, 41))
    return np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])


def _empty(result, message: str) -> None:
    assert result.grasps == [] and result.none.outcome == "empty_scan"
    assert result.none.message == message
    assert result.notes == [NO_FREE_SPACE]  # no empty note for the fusion that did not run
    doc = document(result)
    jsonschema.validate(doc, JSON_SCHEMA)
    assert doc["input"]["table"] == {"normal": [0.0, 0.0, 1.0], "height": 0.0,
                                     "source": result.table_source}


def test_a_cloud_in_the_objects_own_frame_says_give_its_pose(tmp_path):
    np.save(tmp_path / "c.npy", box_cloud((0.0, 0.0)))
    r = gbh_drake.grasps(tmp_path / "c.npy", target=[0.0, 0.0, 0.05])
    _empty(r, "empty scan: no cluster of the cloud stands on the table within 0.3 m of the "
              f"target (0.000, 0.000, 0.050) m; {ROBOT.replace('--frame', 'frame=')}")


def test_the_command_exits_0_with_the_reason(tmp_path, capsys):
    np.save(tmp_path / "c.npy", box_cloud((0.0, 0.0)))
    out = tmp_path / "g.json"
    assert main(["grasps", str(tmp_path / "c.npy"), "--out", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["none"]["outcome"] == "empty_scan" and doc["grasps"] == []
    assert doc["none"]["message"].endswith(ROBOT)
    assert doc["input"]["notes"] == [NO_FREE_SPACE]
    stdout, stderr = capsys.readouterr()
    assert stderr == "" and f"  none: empty_scan: {doc['none']['message']}\n" in stdout
    assert "table z = 0.0000 m (lowest point)" in stdout and "  note: \n" not in stdout


def test_a_cloud_of_the_table_alone(tmp_path):
    np.save(tmp_path / "t.npy", table_cloud())
    r = gbh_drake.grasps(tmp_path / "t.npy")
    _empty(r, "empty scan: no point of the cloud lies 4 mm or more above the table (z = 0.0000 "
              f"m, {r.table_source}; the points: (0.300, -0.200, 0.000) m to (0.700, 0.200, "
              "0.000) m in B): a cloud of the table alone?")
    assert r.table_source in ("verified", "fitted")


def test_a_target_away_from_the_cloud_says_where_its_points_are(tmp_path):
    np.save(tmp_path / "c.npy", box_cloud((0.55, 0.0)))
    r = gbh_drake.grasps(tmp_path / "c.npy", target=[5.0, 5.0, 5.0])
    _empty(r, "empty scan: no point of the cloud lies in the workspace round the target "
              "(5.000, 5.000, 5.000) m (+-0.6 m in x and y; the points: (0.510, -0.040, 0.000) "
              "m to (0.590, 0.040, 0.100) m in B): give target= where the object is")


def test_a_cloud_in_millimetres_scaled_reads_in_metres(tmp_path):
    """--scale 0.001 on a cloud in millimetres: read in metres (the table alone: its span in
    the message is in metres)."""
    np.save(tmp_path / "t_mm.npy", table_cloud() * 1000.0)
    r = gbh_drake.grasps(tmp_path / "t_mm.npy", scale=0.001)
    assert r.none.outcome == "empty_scan"
    assert "(0.300, -0.200, 0.000) m to (0.700, 0.200, 0.000) m in B" in r.none.message
