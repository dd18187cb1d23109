"""The station: settling is quiet, the robot holds its pose, seeds decide random poses."""

import numpy as np
import pytest

from gbh_drake.run import run
from gbh_drake.scenario import load_scenario
from gbh_drake.station import ObjectAsset, sample_object_pose


def test_settle_keeps_object_and_writes_replay(scenario, staple_mesh):
    scenario.settle_time = 0.3
    scenario.task = "settle"
    asset = ObjectAsset("staple", staple_mesh, 500.0, (0.2, 0.4, 0.8, 1.0), "test")
    summary = run(scenario, object_asset=asset)
    assert summary.settle_drift < 0.005
    assert summary.pick is None
    replay = scenario.output_path() / "replay.html"
    html = replay.read_text()
    assert "<html" in html.lower() and len(html) > 10_000
    assert (scenario.output_path() / "summary.yaml").is_file()


RANDOM_POSE = """
object:
  pose:
    translation: !UniformVector {min: [0.4, -0.2, 0.0], max: [0.7, 0.2, 0.0]}
    rotation: !Rpy {deg: !UniformVector {min: [0, 0, -180], max: [0, 0, 180]}}
"""


def _random_pose_scenario(tmp_path, seed):
    path = tmp_path / "random.yaml"
    path.write_text(RANDOM_POSE)
    return load_scenario(path, overrides=f"seed: {seed}")


def test_seed_decides_the_random_pose(tmp_path):
    scenario = _random_pose_scenario(tmp_path, 3)
    a = sample_object_pose(scenario)
    b = sample_object_pose(_random_pose_scenario(tmp_path, 3))
    c = sample_object_pose(_random_pose_scenario(tmp_path, 4))
    np.testing.assert_array_equal(a.GetAsMatrix4(), b.GetAsMatrix4())
    assert not np.allclose(a.translation(), c.translation())
    assert 0.4 <= a.translation()[0] <= 0.7
    assert a.translation()[2] == pytest.approx(scenario.object.drop_height)
