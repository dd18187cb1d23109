"""Depth images out of the simulation and back in through ``gbh grasps``: the same scan
functions, the same grasps.

* ``gbh run --save-views`` writes the scan (``scan.ply``), its views (16-bit PNG + views.yaml)
  and ``grasps.json``; ``gbh grasps`` on the views gives the run's ranked list.
* Sample data: the mug rendered with the sensor noise model by a 16-bit sensor (depths in
  0.1 mm units, ``ScanConfig.depth_unit``), written as 16-bit PNG + YAML without the mesh:
  ``gbh grasps`` fuses them again and finds the simulated scan's best grasp within 2 mm and
  2 deg (here: the same grasp; the PNGs hold the very depths the scan fused).
"""

import json

import jsonschema
import numpy as np
import pytest

from gbh_drake.cli import main
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import scan_object
from gbh_drake.perception.scenes import build_scene
from gbh_drake.scan_grasps.document import JSON_SCHEMA
from gbh_drake.scan_grasps.run_export import write_views
from gbh_drake.scan_grasps.views import read_views

pytestmark = pytest.mark.sim


def _pose_gap(a, b) -> tuple[float, float]:
    """(m, deg) between two 4x4 poses."""
    a, b = np.asarray(a), np.asarray(b)
    R = a[:3, :3].T @ b[:3, :3]
    return (float(np.linalg.norm(a[:3, 3] - b[:3, 3])),
            float(np.degrees(np.arccos(np.clip(0.5 * (np.trace(R) - 1.0), -1.0, 1.0)))))


@pytest.fixture(scope="module")
def noisy_mug(tmp_path_factory):
    """The mug scanned with 10 noisy views of a 16-bit sensor, and those views written as
    16-bit PNG + YAML (no mesh: ``gbh grasps`` fuses them)."""
    scene = build_scene("mug_classic", tmp_path_factory.mktemp("mug"), yaw_deg=30.0)
    config = ScanConfig(noise=True, depth_unit=1e-4)
    scan = scan_object(scene.query_object, config, (0.55, 0.0, 0.06), noise_seed=5)
    folder = tmp_path_factory.mktemp("views")
    write_views(folder, scan, config, np.eye(4), seed=0)
    return scan, folder


def test_the_written_views_are_16_bit_pngs_with_their_yaml(noisy_mug):
    scan, folder = noisy_mug
    views = read_views(folder)
    assert len(views.views.depths) == 10 and len(views.first_look.depths) == 2
    from PIL import Image

    with Image.open(folder / "depth_000.png") as image:
        assert image.mode == "I;16" and image.size == (640, 480)
    # The depths read back are the measured (noisy) ones, as the sensor gave them.
    measured = np.nan_to_num(scan.free_space.views[0].depth, nan=0.0)
    back = views.views.depths[0]
    near = (measured > 0) & (measured < 1.5)
    np.testing.assert_array_equal(back[near], measured[near])
    assert views.views.depth_error > 0  # the noise model's bound, so the margin is the scan's


def test_depth_images_give_the_simulated_scans_best_grasp(noisy_mug, tmp_path):
    """The round trip of the sample data: PNG + YAML -> gbh grasps -> the best grasp of GbH on
    the simulated scan (same parameters and seed), within 2 mm and 2 deg."""
    scan, folder = noisy_mug
    expected = plan_grasps(scan.mesh_W, GbhParams(), seed=0, free_space=scan.free_space).ranked
    out = tmp_path / "grasps.json"
    assert main(["grasps", str(folder), "--out", str(out)]) == 0
    doc = json.loads(out.read_text())
    jsonschema.validate(doc, JSON_SCHEMA)
    assert doc["input"]["kind"] == "depth_images" and doc["input"]["free_space"]
    assert expected and doc["grasps"], doc["none"]
    best = doc["grasps"][0]
    distance, angle = _pose_gap(best["X_BG"]["matrix"], expected[0].X_WG)
    assert best["kind"] == expected[0].kind
    assert distance <= 0.002 and angle <= 2.0, (distance, angle)


def test_gbh_run_writes_its_scan_and_gbh_grasps_ranks_them_the_same(tmp_path, capsys):
    """A short pick (it ends once the scan is taken and GbH has ranked): scan.ply, views/ and
    grasps.json in B; gbh grasps on the views (the run's mesh, the views' free space) gives the
    run's ranked list."""
    out = tmp_path / "run"
    assert main(["run", "--save-views", "--set", f"output_dir: {out}",
                 "--set", "max_time: 1.2"]) == 0
    capsys.readouterr()
    for name in ("scan.ply", "grasps.json", "views/views.yaml", "views/depth_000.png",
                 "views/first_look_000.png"):
        assert (out / name).is_file(), name
    run_doc = json.loads((out / "grasps.json").read_text())
    jsonschema.validate(run_doc, JSON_SCHEMA)
    assert run_doc["input"]["kind"] == "simulation" and len(run_doc["grasps"]) > 10
    again = tmp_path / "again.json"
    assert main(["grasps", str(out / "views"), "--out", str(again)]) == 0
    doc = json.loads(again.read_text())
    assert [g["kind"] for g in doc["grasps"]] == [g["kind"] for g in run_doc["grasps"]]
    for a, b in zip(doc["grasps"], run_doc["grasps"], strict=True):
        np.testing.assert_allclose(a["X_BG"]["matrix"], b["X_BG"]["matrix"], atol=1e-12)
        np.testing.assert_allclose(a["X_B_link8"]["matrix"], b["X_B_link8"]["matrix"],
                                   atol=1e-12)
        assert a["score"] == pytest.approx(b["score"], abs=1e-12)
    assert doc["gbh"]["params"] == run_doc["gbh"]["params"]
