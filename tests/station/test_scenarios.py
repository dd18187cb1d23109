"""Every scenario file in scenarios/ loads, builds and simulates briefly (a smoke test each)."""

import pytest

from gbh_drake import SCENARIOS_DIR
from gbh_drake.run import run
from gbh_drake.scenario import load_scenario

SCENARIOS = sorted(SCENARIOS_DIR.glob("*.yaml"))


def test_there_are_scenarios():
    assert any(p.name == "default.yaml" for p in SCENARIOS)


@pytest.mark.parametrize("path", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_scenario_runs_briefly(path, tmp_path):
    scenario = load_scenario(path, overrides=f"settle_time: 0.05\noutput_dir: {tmp_path}")
    summary = run(scenario)
    assert summary.sim_time == pytest.approx(0.05)
    assert (tmp_path / "replay.html").is_file()
    assert summary.object_drift < 0.01
