"""Every scenario file in scenarios/ loads, builds and runs (a smoke test each)."""

import pytest

from gbh_drake import SCENARIOS_DIR
from gbh_drake.run import run
from gbh_drake.scenario import load_scenario

SCENARIOS = sorted(SCENARIOS_DIR.glob("*.yaml"))


def test_there_are_scenarios():
    assert any(p.name == "default.yaml" for p in SCENARIOS)


@pytest.mark.parametrize("path", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_scenario_runs(path, tmp_path):
    scenario = load_scenario(path, overrides=f"task: settle\nsettle_time: 0.05\n"
                                             f"output_dir: {tmp_path}")
    summary = run(scenario)
    assert summary.record.sim_time >= 0.05
    for name in ("replay.html", "summary.yaml", "scenario.yaml"):
        assert (tmp_path / name).is_file()
    assert summary.settle_drift < 0.01
