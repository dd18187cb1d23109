"""One view completed by shape completion (``gbh_completed``), in the trial's diagram: the
record carries the completion's warnings beside the scan's."""

import pytest

import gbh_drake
from gbh_drake.scenario import Scenario

pytestmark = pytest.mark.trial


def test_a_box_seen_once_is_not_completed_and_the_record_says_so():
    """A box from one view is no body of revolution: GbH finds nothing on the scan as taken,
    and the record's scan warnings say that the completion added nothing."""
    record = gbh_drake.run_trial(Scenario(max_time=6.0), overrides=[
        "{grasp_method: gbh_completed, scan: {num_views: 1}, gbh: {d2: 0.005}}",
        "{object: {name: box}}"])
    assert record.outcome == "no_hangable_structure"
    assert any("shape completion" in w and "explains less than" in w
               for w in record.scan_warnings), record.scan_warnings
