"""A trial's reach on its scan and its true mesh (pure: meshes in, a plain dict out)."""

from gbh_shapes import RING_r, make_mug, make_ring

from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import detect
from gbh_drake.experiment.reach import reach_of_trial


def test_reach_of_a_flat_ring_and_of_a_scan_given_as_structures():
    ring = make_ring()
    ring.apply_translation([0.0, 0.0, RING_r])
    params = GbhParams()
    obj, structures = detect(make_mug(), params, 0)
    r = reach_of_trial(obj, ring, params, scan_structures=structures).to_dict()
    assert r["scan"] == "reachable" and r["true"] == "out of reach"
    assert r["best_margin_mm"] < -8.0 and r["poses"] > 0 and r["seconds"] > 0
    assert reach_of_trial(None, None, params).to_dict()["true"] == "no structure"
