"""The stages' memo (``systems.stage.LastResult``): the same input objects give the last result
back without computing; a key object that dies drops the result (a Python LeafSystem is never
freed, so a memo that held its inputs kept every trial's scans: an experiment worker grew to
12 GB and was killed)."""

import gc

import numpy as np
import trimesh

from gbh_drake.systems.stage import LastResult


def test_the_same_objects_give_the_last_result_without_computing():
    memo, calls = LastResult(), []
    mesh, grasps = trimesh.creation.box(), [1, 2]  # a list allows no weak reference: held
    first = memo.get((mesh, grasps), lambda: calls.append(1) or object())
    assert memo.get((mesh, grasps), lambda: calls.append(1) or object()) is first
    assert len(calls) == 1
    other = memo.get((trimesh.creation.box(), grasps), lambda: calls.append(1) or object())
    assert other is not first and len(calls) == 2


def test_a_key_object_that_dies_drops_the_result():
    memo = LastResult()
    mesh = trimesh.creation.box()
    memo.get((mesh,), lambda: np.zeros(1000))
    assert memo._result is not None
    del mesh
    gc.collect()
    assert memo._result is None and memo._key is None
    # ... and a new object computes again, even if it takes the dead one's identity.
    assert memo.get((trimesh.creation.box(),), lambda: "again") == "again"
