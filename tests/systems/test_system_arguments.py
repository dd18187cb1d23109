"""The systems built by hand in a diagram of one's own refuse a bad argument at construction,
naming the system and the argument, instead of failing (or turning it into a result: "unusable
mesh") when the diagram first evaluates them."""

import numpy as np
import pytest
import trimesh
from pydrake.common.value import AbstractValue
from pydrake.systems.sensors import CameraInfo

from gbh_drake.core.params import GbhParams
from gbh_drake.perception.config import ScanConfig
from gbh_drake.systems import (
    AntipodalGraspSampler,
    DepthImageScanner,
    GraspScorer,
    GraspSearchReport,
    GraspSynthesizer,
    HangabilityDetector,
    RegraspPlanner,
    ScoopSynthesizer,
    ShapeCompleter,
)

INFO = CameraInfo(64, 48, 1.0)


@pytest.mark.parametrize(("make", "message"), [
    (lambda: HangabilityDetector("paper"),
     "HangabilityDetector(): params: expected a GbhParams or None, got 'paper' (a str)"),
    (lambda: HangabilityDetector(seed=-1),
     "HangabilityDetector(): seed: expected an integer in [0, 2^64), got -1 (an int)"),
    (lambda: GraspSynthesizer({"top_k": 3}), "GraspSynthesizer(): params: expected a GbhParams"),
    (lambda: GraspScorer(3), "GraspScorer(): params: expected a GbhParams or None, got 3"),
    (lambda: AntipodalGraspSampler(GbhParams()),
     "AntipodalGraspSampler(): params: expected an AntipodalParams or None, got GbhParams("),
    (lambda: AntipodalGraspSampler(seed="1"), "AntipodalGraspSampler(): seed: expected an "
                                              "integer"),
    (lambda: ShapeCompleter(GbhParams()), "ShapeCompleter(): params: expected a "
                                          "CompletionParams"),
    (lambda: ScoopSynthesizer(scoop=GbhParams()), "ScoopSynthesizer(): scoop: expected a "
                                                  "ScoopParams"),
    (lambda: RegraspPlanner(pinch_seed=1.5), "RegraspPlanner(): pinch_seed: expected an integer"),
    (lambda: GraspSearchReport(params="paper"), "GraspSearchReport(): params: expected a "
                                                "GbhParams"),
])
def test_a_stage_names_its_bad_argument(make, message):
    with pytest.raises(TypeError) as info:
        make()
    assert str(info.value).startswith(message), str(info.value)


def test_a_detector_given_good_arguments_still_finds_a_handle():
    detector = HangabilityDetector(None, seed=np.uint64(3))
    context = detector.CreateDefaultContext()
    detector.get_input_port().FixValue(context, AbstractValue.Make(
        trimesh.creation.torus(0.04, 0.008)))
    result = detector.get_output_port().Eval(context)
    assert len(result.structures) == 1 and result.message == ""


@pytest.mark.parametrize(("args", "kwargs", "message"), [
    ((None, INFO, [0.5, 0, 0]), {}, "config: expected a ScanConfig"),
    ((ScanConfig(), "640x480", [0.5, 0, 0]), {}, "intrinsics: expected a pydrake CameraInfo or "
                                                 "a CameraIntrinsics, got '640x480'"),
    ((ScanConfig(), INFO, [0.5, 0]), {}, "p_WT: expected 3 finite coordinates"),
    ((ScanConfig(), INFO, [np.nan, 0, 0]), {}, "p_WT: expected 3 finite coordinates"),
    ((ScanConfig(), INFO, [0.5, 0, 0]), {"num_cameras": 2.0},
     "num_cameras: expected an integer >= 1, got 2.0"),
    ((ScanConfig(), INFO, [0.5, 0, 0]), {"num_cameras": 0}, "num_cameras: expected an integer"),
    ((ScanConfig(), INFO, [0.5, 0, 0]), {"capture_times": 1.0},
     "capture_times: expected a non-empty list of times >= 0 (s), or None (scan on demand), "
     "got 1.0"),
    ((ScanConfig(), INFO, [0.5, 0, 0]), {"capture_times": [0.5, -1.0]}, "capture_times:"),
    ((ScanConfig(), INFO, [0.5, 0, 0]), {"capture_times": [np.nan]}, "capture_times:"),
    ((ScanConfig(), INFO, [0.5, 0, 0]), {"sensor_error": -0.004},
     "sensor_error: expected a distance >= 0 (m) or None, got -0.004"),
    ((ScanConfig(), INFO, [0.5, 0, 0]), {"noise_seed": "7"}, "noise_seed: expected an integer"),
])
def test_the_depth_image_scanner_names_its_bad_argument(args, kwargs, message):
    with pytest.raises(TypeError) as info:
        DepthImageScanner(*args, **kwargs)
    assert str(info.value).startswith(f"DepthImageScanner(): {message}"), str(info.value)


def test_the_depth_image_scanner_takes_numpy_arguments():
    scanner = DepthImageScanner(ScanConfig(), INFO, np.array([0.5, 0.0, 0.0]),
                                num_cameras=np.int64(2), capture_times=np.array([0.5, 0.2]),
                                sensor_error=0.004)
    assert scanner.num_input_ports() == 4
