"""tools/screen_rule.py: which methods share a detector's input, and when two detections are
the same."""

import importlib.util
from pathlib import Path

import numpy as np

from gbh_drake.core.results import HangingStructure
from gbh_drake.experiment.config import load_experiment, trial_scenario

ROOT = Path(__file__).parents[2]
spec = importlib.util.spec_from_file_location("screen_rule", ROOT / "tools" / "screen_rule.py")
screen_rule = importlib.util.module_from_spec(spec)
spec.loader.exec_module(screen_rule)
EXPERIMENT = load_experiment(ROOT / "scenarios" / "experiment.yaml")


def key(method: str, trial: int = 0, protocol: str = "stable", name: str = "mug_classic"):
    return screen_rule.share_key(trial_scenario(EXPERIMENT, name, method, trial, protocol))


def test_methods_that_differ_only_after_the_detector_share_one_screen():
    assert key("gbh-10") == key("gbh+fallback")  # the same scan, the same rules
    assert key("gbh-10") != key("gbh+")  # the wedge gripper is in the scene
    assert key("gbh-10") != key("gbh-1")  # one view
    assert key("gbh-10") != key("gbh-10", trial=1)  # another pose
    assert key("gbh-10") != key("gbh-10", protocol="natural")
    assert key("gbh-10") != key("gbh-10", name="teacup")


def structure(c, v=(0.0, 1.0, 0.0), clearance=0.01) -> HangingStructure:
    return HangingStructure(c=np.asarray(c, float), v=np.asarray(v, float), H=np.zeros((0, 3)),
                            m=1.0, a=np.zeros(3), clearance=clearance)


def test_the_same_structures_are_the_same_positions_axes_and_clearances():
    a = [structure((0.5, 0.0, 0.1)), structure((0.5, 0.05, 0.1))]
    assert screen_rule.same_structures(a, [structure((0.5, 0.0, 0.1)),
                                           structure((0.5, 0.05, 0.1))])
    assert not screen_rule.same_structures(a, a[:1])
    assert not screen_rule.same_structures(a[:1], [structure((0.5, 0.0, 0.1001))])
    assert not screen_rule.same_structures(a[:1], [structure((0.5, 0.0, 0.1), (1.0, 0.0, 0.0))])
    assert not screen_rule.same_structures(a[:1], [structure((0.5, 0.0, 0.1), clearance=0.02)])
