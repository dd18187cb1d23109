"""The gbh command: objects and diagram subcommands (run is covered by the scenario tests)."""

import pytest

from gbh_drake.cli import main


def test_objects_list(capsys):
    assert main(["objects", "list"]) == 0
    out = capsys.readouterr().out
    assert "mug_classic" in out and "none (control)" in out


@pytest.mark.sim
def test_diagram_writes_dot(tmp_path):
    assert main(["diagram", "--out", str(tmp_path)]) == 0
    station = (tmp_path / "station.dot").read_text()
    for port in ("panda.desired_state", "hook_gripper.command", "panda.state",
                 "hook_gripper.state", "body_poses", "contact_results", "query_object"):
        assert port in station
    trial = (tmp_path / "trial.dot").read_text()
    for name in ("scanner", "hangability_detector", "grasp_synthesizer", "grasp_scorer",
                 "pick_and_carry", "cage_monitor", "station"):
        assert name in trial
