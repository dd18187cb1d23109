"""Determinism of the meshes and the on-disk set (.obj + ground_truth.yaml)."""

import hashlib
import subprocess
import sys

import numpy as np
import yaml

from gbh_drake.objects import list_objects, load_mesh_file, make_object, write_object_meshes
from gbh_drake.objects.export import obj_bytes

HASH_SCRIPT = """
import hashlib
from gbh_drake.objects import list_objects, make_object
from gbh_drake.objects.export import obj_bytes
for n in list_objects():
    print(n, hashlib.sha256(obj_bytes(make_object(n).mesh)).hexdigest())
"""


def test_same_parameters_same_bytes_in_process(specs):
    for name in ("mug_classic", "watering_can", "scissors"):
        assert obj_bytes(make_object(name).mesh) == obj_bytes(specs[name].mesh)
    a = obj_bytes(make_object("teacup", height=0.07).mesh)
    assert a == obj_bytes(make_object("teacup", height=0.07).mesh)
    assert a != obj_bytes(specs["teacup"].mesh)


def test_same_bytes_in_a_fresh_process(specs):
    out = subprocess.run([sys.executable, "-c", HASH_SCRIPT], capture_output=True, text=True,
                         check=True)
    theirs = dict(line.split() for line in out.stdout.strip().splitlines())
    ours = {n: hashlib.sha256(obj_bytes(s.mesh)).hexdigest() for n, s in specs.items()}
    assert theirs == ours


def test_write_object_meshes_round_trip(tmp_path, specs):
    paths = write_object_meshes(tmp_path)
    assert [p.stem for p in paths] == list_objects()
    for path in paths:
        spec = specs[path.stem]
        assert path == tmp_path / spec.name / f"{spec.name}.obj"
        truth = yaml.safe_load((path.parent / "ground_truth.yaml").read_text())
        assert truth["name"] == spec.name and truth["is_control"] == spec.is_control
        assert 0.03 < truth["mass_kg"] < 0.8
        assert len(truth["hangable_parts"]) == len(spec.hangable_parts)
        for part, saved in zip(spec.hangable_parts, truth["hangable_parts"], strict=True):
            np.testing.assert_allclose(saved["center_O"], part.center_O, atol=1e-6)
            assert saved["kind"] == part.kind
        if spec.genus is None:
            continue
        mesh = load_mesh_file(path)
        assert mesh.is_watertight and mesh.body_count == 1
        assert (2 - mesh.euler_number) // 2 == spec.genus
        assert abs(mesh.volume - spec.mesh.volume) < 1e-3 * spec.mesh.volume
        assert path.stat().st_size < 1_000_000
