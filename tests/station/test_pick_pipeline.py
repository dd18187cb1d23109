"""The whole trial: scan, GbH, IK, execution and verdict, on objects whose answer is known."""

import pytest

from gbh_drake.run import run


def test_default_mug_is_picked_and_carried(scenario):
    """mug_classic at its default pose: the handle is found and the hook carries the mug."""
    scenario.settle_time = 0.1
    summary = run(scenario)
    pick = summary.pick
    assert pick.n_structures >= 1 and pick.n_ranked >= 1
    assert pick.chosen_rank >= 0
    assert pick.success, pick.reason
    assert pick.lift > 0.09 and pick.clearance > 0.02


def test_box_has_nothing_to_hang_by(scenario):
    """A control object: 'no hangable structure found' is a result, not a crash."""
    scenario.object.name = "box"
    scenario.settle_time = 0.05
    summary = run(scenario)
    assert summary.pick.n_structures == 0
    assert not summary.pick.success
    assert "no hangable structure" in summary.pick.reason


def test_object_out_of_view_gives_empty_scan(scenario):
    """The cameras look at the scan target; an object far from it gives an empty scan result."""
    scenario.object.name = "mug_classic"
    scenario.scan_target = [0.55, 0.4, 0.06]  # 40 cm beside the mug: outside the crop box
    scenario.settle_time = 0.05
    summary = run(scenario)
    assert summary.pick.scan_faces == 0
    assert "empty scan" in summary.pick.reason
    assert not summary.pick.success


@pytest.mark.parametrize("seed", [0])
def test_same_seed_same_trial(scenario, seed, tmp_path):
    scenario.settle_time = 0.05
    scenario.seed = seed
    a = run(scenario).pick
    scenario.output_dir = str(tmp_path / "again")
    b = run(scenario).pick
    assert (a.n_structures, a.n_candidates, a.chosen_rank, a.success) == (
        b.n_structures, b.n_candidates, b.chosen_rank, b.success)
    assert a.lift == pytest.approx(b.lift, abs=1e-9)
