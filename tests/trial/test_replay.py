"""A trial's replay, drawn after the trial from its recorded poses (gbh_drake/replay.py): what it
shows, that it reads alone (title, legend), that it fetches nothing, and that the trial itself
drew nothing while it ran."""

from __future__ import annotations

import pytest
from pydrake.geometry import MeshcatVisualizer
from replay_pages import commands, fetched, tracks

from gbh_drake.replay import title, with_overlay
from gbh_drake.scenario import Scenario
from gbh_drake.scenario.loader import apply_overrides
from gbh_drake.trial import record_trial
from gbh_drake.viz import palette
from gbh_drake.viz.meshcat_server import local_meshcat


def test_the_overlay_is_plain_html_with_the_title_legend_and_nothing_to_fetch():
    page = "<html><body><div id='meshcat-pane'></div></body></html>"
    out = with_overlay(page, "a <mug> · SUCCESS", "held & carried", [palette.LEGEND[0]],
                       ["/drake/illustration/mug"])
    assert out.index("gbh-title") < out.index("</body>")
    assert "a &lt;mug&gt; · SUCCESS" in out and "held &amp; carried" in out
    assert palette.LEGEND[0].label in out and palette.css(palette.SCAN) in out
    assert "modulated_opacity" in out and '"/drake/illustration/mug"' in out
    assert fetched(out) == []


@pytest.mark.sim
def test_a_failed_replay_shows_the_cameras_what_they_did_not_see_and_why():
    """A can has nothing to hang it by: its replay says why in its title (what the detector
    saw), shows the cameras and the unseen space from the scan on, the object see-through, and
    fetches nothing. The trial ran without any Meshcat visualiser: the replay was drawn after."""
    meshcat = local_meshcat()
    scenario = apply_overrides(Scenario(), "{object: {name: can}, scan: {num_views: 1}}")
    done = record_trial(scenario, meshcat=meshcat)
    record, page = done.record, done.replay_html
    assert record.outcome == "no_hangable_structure"
    assert not [s for s in done.trial.diagram.GetSystems() if isinstance(s, MeshcatVisualizer)]
    assert title(record) == "can · gbh, 1 view · FAILURE: no_hangable_structure"
    assert title(record) in page and "contact candidates" in page  # the detector's summary
    for key in ("object (can)", "scan (fused views)", "cameras", "what the cameras did not see"):
        assert f"{key}</div>" in page, key
    assert "ranked grasps" not in page
    for path in ("gbh/object", "gbh/cameras/views/0", "gbh/cameras/first_look/0", "gbh/unseen"):
        assert meshcat.HasPath(path), path
    animation = tracks(page)
    for path in ("/drake/gbh/cameras", "/drake/gbh/unseen", "/drake/gbh/object"):
        shown = animation[path][".visible"]
        assert shown[0] == {"time": 0, "value": False} and shown[-1]["value"] is True, path
    assert "/drake" in animation  # the view follows the object (here: it settles 2 mm)
    assert any(c["type"] == "set_target" for c in commands(page))
    assert fetched(page) == []
