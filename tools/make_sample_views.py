"""Writes sample depth images for ``gbh grasps``: the mug of the object set on the table beside
the robot (yaw 30 deg, as scenarios/default.yaml), scanned by the simulation with the depth
noise model of a 16-bit sensor in millimetres (``ScanConfig(noise=True, depth_unit=0.001)``),
10 views aimed as the Scanner aims them and its first look's two, written as 16-bit PNG with
their views.yaml (no mesh: ``gbh grasps`` fuses them). Deterministic (noise seed 0).

    .venv/bin/python tools/make_sample_views.py [FOLDER]   # default tests/scan_grasps/data/mug_views

The fast tests read the folder (tests/scan_grasps/test_sample_views.py) and docs/grasps.md's
example runs on it.
"""

import sys
import tempfile
from pathlib import Path

import numpy as np

from gbh_drake import REPO_ROOT
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import scan_object
from gbh_drake.perception.scenes import build_scene
from gbh_drake.scan_grasps.run_export import write_views

#: The sample's folder, and the scan it holds.
SAMPLE = REPO_ROOT / "tests" / "scan_grasps" / "data" / "mug_views"
CONFIG = ScanConfig(noise=True, depth_unit=0.001)
TARGET = (0.55, 0.0, 0.06)


def main(folder: Path = SAMPLE) -> Path:
    with tempfile.TemporaryDirectory() as models:
        scene = build_scene("mug_classic", models, yaw_deg=30.0)
        scan = scan_object(scene.query_object, CONFIG, TARGET, noise_seed=0)
    for old in folder.glob("*.png"):
        old.unlink()
    path = write_views(folder, scan, CONFIG, np.eye(4), seed=0)
    print(f"wrote {path} and {len(scan.X_WCs) + len(scan.first_look_X_WCs)} depth images")
    return path


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else SAMPLE)
