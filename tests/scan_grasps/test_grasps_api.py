"""``gbh_drake.grasps`` and ``gbh grasps`` on meshes: ranked grasps in B with their waypoints,
the document valid against its schema, the frame contract kept, nothing found said why."""

import base64
import json
import re
import subprocess
import sys

import jsonschema
import numpy as np
import pytest
import trimesh
import yaml
from gbh_shapes import make_mug, make_ring

import gbh_drake
from gbh_drake import REPO_ROOT
from gbh_drake.cli import main
from gbh_drake.core.gripper import HOOK_GRIPPER, X_link8_G
from gbh_drake.core.params import GbhParams
from gbh_drake.scan_grasps.document import JSON_SCHEMA, document, schema_markdown, to_json
from gbh_drake.scan_grasps.inputs import NO_FREE_SPACE

#: Where the test mug stands in B: on the table (z = 0) in front of the robot.
P_BO = np.array([0.55, 0.0, 0.0])


@pytest.fixture(scope="module")
def mug_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("mug") / "mug.obj"
    make_mug().apply_translation(P_BO).export(path)
    return path


@pytest.fixture(scope="module")
def mug_grasps(mug_file):
    return gbh_drake.grasps(mug_file)


def test_grasps_is_the_packages_function_and_import_stays_light():
    out = subprocess.run([sys.executable, "-c", "import sys, gbh_drake; "
                          "print(any(m.startswith(('pydrake', 'gbh_drake.scan_grasps', 'trimesh'))"
                          " for m in sys.modules)); print(callable(gbh_drake.grasps))"],
                         capture_output=True, text=True, check=True, cwd=REPO_ROOT)
    assert out.stdout.split() == ["False", "True"]


def test_a_mesh_gets_ranked_grasps_in_B_with_their_waypoints(mug_grasps):
    r = mug_grasps
    assert r.input_kind == "mesh" and not r.free_space and NO_FREE_SPACE in r.notes
    assert r.table_source == "lowest point" and r.table.height == pytest.approx(0.0, abs=1e-9)
    assert 10 < len(r.grasps) <= GbhParams().top_k and r.none is None  # more than the paper's ten
    assert [g.rank for g in r.grasps] == list(range(1, len(r.grasps) + 1))
    assert all(a.score >= b.score for a, b in zip(r.grasps[:-1], r.grasps[1:], strict=True))
    g = HOOK_GRIPPER
    for x in r.grasps:
        w = x.waypoints
        # The flange where the gripper frame says: X_BG = X_B_link8 X_link8_G.
        np.testing.assert_allclose(x.X_B_link8 @ X_link8_G(), x.X_BG, atol=1e-12)
        # The pre-grasp 10 cm back along the approach, the same orientation.
        np.testing.assert_allclose(w.pre_grasp[:3, 3], x.X_BG[:3, 3] - 0.10 * x.X_BG[:3, 2])
        np.testing.assert_allclose(w.pre_grasp[:3, :3], x.X_BG[:3, :3])
        # Closed: a vertical grasp moves along +y_G by the fingers' travel, a parallel stays.
        shift = g.q_open - g.q_closed if x.kind == "vertical" else 0.0
        np.testing.assert_allclose(w.closed[:3, 3], x.X_BG[:3, 3] + shift * x.X_BG[:3, 1])
        # Lifted straight up (the table's normal) within the pick's limits.
        assert 0.10 <= w.lift_height <= 0.40
        np.testing.assert_allclose(w.lift[:3, 3] - w.closed[:3, 3], [0, 0, w.lift_height])
        assert (w.q_open, w.q_closed) == (g.q_open, g.q_closed)
        # The hook point T (G's (0, 0, l_f)) of a parallel grasp is the hole's centre c.
        if x.kind == "parallel":
            T = x.X_BG[:3, :3] @ [0.0, 0.0, g.finger_length] + x.X_BG[:3, 3]
            assert np.linalg.norm(T - r.structures[x.structure].c) < 0.02


def test_the_document_validates_and_says_its_frame_and_version(mug_grasps, tmp_path):
    doc = document(mug_grasps)
    jsonschema.validate(doc, JSON_SCHEMA)
    assert doc["schema"] == "gbh_drake/grasps" and doc["schema_version"] == 1
    assert "panda_link0" in doc["frame"]
    np.testing.assert_allclose(doc["gripper"]["X_link8_G"]["matrix"], X_link8_G())
    best = doc["grasps"][0]
    X = np.asarray(best["X_B_link8"]["matrix"])
    q = best["X_B_link8"]["quaternion_wxyz"]
    np.testing.assert_allclose(best["X_B_link8"]["translation"], X[:3, 3])
    from gbh_drake.scan_grasps.poses import quaternion_matrix

    np.testing.assert_allclose(quaternion_matrix(q), X[:3, :3], atol=1e-12)
    assert json.loads(to_json(doc)) == doc  # plain JSON: no NaN


def test_the_command_writes_json_or_yaml_and_a_page(mug_file, tmp_path, capsys):
    out = tmp_path / "g.json"
    assert main(["grasps", str(mug_file), "--out", str(out), "--top", "3"]) == 0
    doc = json.loads(out.read_text())
    jsonschema.validate(doc, JSON_SCHEMA)
    assert len(doc["grasps"]) == 3
    assert main(["grasps", str(mug_file), "--yaml", "--out", str(tmp_path / "g.yaml"),
                 "--top", "3", "--html", str(tmp_path / "g.html")]) == 0
    again = yaml.safe_load((tmp_path / "g.yaml").read_text())
    again["timings"], doc["timings"] = {}, {}
    assert again == doc
    page = (tmp_path / "g.html").read_text()
    assert page.rstrip().endswith("</html>") and "meshcat" in page.lower()
    # The scene's commands are embedded base64-coded (msgpack); their paths are plain in them.
    commands = b"".join(base64.b64decode(m) for m in re.findall(
        r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", page))
    for drawn in ("gbh/object", "gbh/structures/0", "gbh/grasps/0", "gbh/best_flange",
                  "gbh/table", "gbh/B"):
        assert f"/drake/{drawn}".encode() in commands, drawn
    text = capsys.readouterr().out
    assert "free space: no" in text and "#1 " in text and "exit proof" in text


def test_an_input_in_its_own_frame_gives_the_same_grasps_in_B(tmp_path, mug_grasps):
    """The mug given in a frame I (turned and moved), with --frame X_BI: the grasps of the mug
    given in B."""
    from gbh_drake.scan_grasps.poses import parse_pose

    X_BI = parse_pose("0.3,-0.2,0.1,10,-20,35")
    path = tmp_path / "mug_I.obj"
    make_mug().apply_translation(P_BO).apply_transform(np.linalg.inv(X_BI)).export(path)
    r = gbh_drake.grasps(path, frame=X_BI, table_z=0.0)
    assert [g.kind for g in r.grasps] == [g.kind for g in mug_grasps.grasps]
    for a, b in zip(r.grasps, mug_grasps.grasps, strict=True):
        np.testing.assert_allclose(a.X_BG, b.X_BG, atol=1e-6)


def test_a_mesh_in_millimetres_with_scale_gives_the_same_grasps(tmp_path, mug_grasps, capsys):
    """The mug in a frame I and in millimetres: --scale 0.001 --frame X_BI (the scale applied
    first: X_BI's translation is in metres) gives the grasps of the mug given in B."""
    from gbh_drake.scan_grasps.poses import parse_pose

    X_BI = parse_pose("0.3,-0.2,0.1,10,-20,35")
    path = tmp_path / "mug_I_mm.obj"
    mug = make_mug().apply_translation(P_BO).apply_transform(np.linalg.inv(X_BI))
    mug.apply_scale(1000.0).export(path)
    out = tmp_path / "g.json"
    assert main(["grasps", str(path), "--scale", "0.001", "--frame", "0.3,-0.2,0.1,10,-20,35",
                 "--table-z", "0", "--out", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert [g["kind"] for g in doc["grasps"]] == [g.kind for g in mug_grasps.grasps]
    for a, b in zip(doc["grasps"], mug_grasps.grasps, strict=True):
        np.testing.assert_allclose(a["X_BG"]["matrix"], b.X_BG, atol=1e-6)
    assert capsys.readouterr().err == ""


def test_nothing_hangable_says_what_the_detector_saw(tmp_path):
    box = trimesh.creation.box([0.08, 0.08, 0.1])
    box.apply_translation(P_BO + [0, 0, 0.05])
    box.export(tmp_path / "box.obj")
    r = gbh_drake.grasps(tmp_path / "box.obj")
    assert r.grasps == [] and r.none.outcome == "no_hangable_structure"
    assert r.hangability is not None and r.hangability.structures == 0
    assert "contact candidates" in r.none.message and "exit proof did not run" in r.none.message
    jsonschema.validate(document(r), JSON_SCHEMA)


def test_no_collision_free_grasp_says_which_rule_removed_them(tmp_path):
    """A ring lying flat on the table: its hole is found, but the bar would pass under the
    material on the table: the table clearance removes every candidate."""
    ring = make_ring()
    ring.apply_translation(P_BO + [0, 0, -ring.bounds[0][2]])
    ring.export(tmp_path / "ring.obj")
    r = gbh_drake.grasps(tmp_path / "ring.obj")
    assert r.structures and r.grasps == [] and r.none.outcome == "no_grasp_found"
    assert r.none.rejected_by["table clearance"] > 0 and "closest:" in r.none.closest
    assert len(r.refused) == 3
    jsonschema.validate(document(r), JSON_SCHEMA)


def test_the_schema_page_is_current():
    text = (REPO_ROOT / "docs" / "grasps_schema.md").read_text()
    start = text.index("<!-- generated by gbh_drake.scan_grasps.document.schema_markdown -->\n")
    end = text.index("<!-- end of generated table -->")
    body = text[start:end].split("\n", 1)[1]
    assert body == schema_markdown(), \
        "regenerate docs/grasps_schema.md's table with schema_markdown()"


def test_the_paper_preset_ranks_as_the_paper(mug_file, tmp_path):
    r = gbh_drake.grasps(mug_file, preset="paper", top=10)
    assert r.params.preset == "paper" and r.params.distinct_distance == 0.0
    assert {g.turn_deg for g in r.grasps} == {0.0}  # no turned approaches
    assert document(r)["gbh"]["preset"] == "paper"
