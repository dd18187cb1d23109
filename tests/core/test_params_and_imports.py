"""GbhParams loads from YAML with Drake's loader; the core imports no pydrake. (Its ranges are
tested with the scenario's, in tests/scenario/test_ranges.py.)"""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import pytest

from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import GbhInputError


def test_params_load_from_yaml_with_drake():
    from pydrake.common.yaml import yaml_load_typed

    data = "{n_points: 3000, ground_normal: [0, 1, 0], d2: 0.005, ground_clearance: -1}"
    p = yaml_load_typed(schema=GbhParams, data=data)
    assert (p.n_points, p.ground_normal, p.d2) == (3000, [0.0, 1.0, 0.0], 0.005)
    assert p.ground_clearance == -1.0
    assert p.gamma_alpha == GbhParams().gamma_alpha
    with pytest.raises(RuntimeError, match="n_point"):
        yaml_load_typed(schema=GbhParams, data="{n_point: 3000}")


def test_params_fields_are_yaml_friendly_with_defaults():
    allowed = {float, int, bool, str, list[float]}
    for f in dataclasses.fields(GbhParams):
        assert f.type in allowed, f.name
        assert f.default is not dataclasses.MISSING or f.default_factory is not dataclasses.MISSING


def test_core_does_not_import_pydrake():
    code = (
        "import sys\n"
        "import gbh_drake.core.pipeline, gbh_drake.core.gripper\n"
        "assert not any(m.startswith('pydrake') for m in sys.modules), 'pydrake imported'\n"
    )
    repo = Path(__file__).resolve().parents[2]
    subprocess.run([sys.executable, "-c", code], check=True, cwd=repo)


def test_prepared_object_must_match_the_sampling_params():
    from gbh_shapes import make_ring

    from gbh_drake.core.object_model import prepare_object

    obj = prepare_object(make_ring(), GbhParams(n_points=800))
    assert prepare_object(obj, GbhParams(n_points=800)) is obj
    with pytest.raises(GbhInputError, match="prepare it again"):
        prepare_object(obj, GbhParams(n_points=900))


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"params": {"n_points": 500}}, "plan_grasps(): params: expected a GbhParams "
                                    "(gbh_drake.core.params), got {'n_points': 500} (a dict)"),
    ({"params": GbhParams}, "plan_grasps(): params: expected a GbhParams (gbh_drake.core.params), "
                            "got the class GbhParams (not an instance of it)"),
    ({"seed": "1"}, "plan_grasps(): seed: expected an integer in [0, 2^64), got '1' (a str)"),
    ({"seed": -1}, "plan_grasps(): seed: expected an integer in [0, 2^64), got -1 (an int)"),
    ({"seed": 1.5}, "plan_grasps(): seed: expected an integer in [0, 2^64), got 1.5 (a float)"),
    ({"free_space": "scan"}, "plan_grasps(): free_space: expected a FreeSpace (a scan's "
                             "ScanResult.free_space) or None, got 'scan' (a str)"),
    ({"params": GbhParams(parallel_grasps="no")},
     "GbhParams.parallel_grasps: expected true or false, got 'no' (a str)"),
])
def test_plan_grasps_names_an_argument_of_the_wrong_type(kwargs, message):
    import trimesh

    from gbh_drake.core.pipeline import plan_grasps

    with pytest.raises(GbhInputError) as info:
        plan_grasps(trimesh.creation.box((0.05, 0.05, 0.05)), **kwargs)
    assert str(info.value) == message
