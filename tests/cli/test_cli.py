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


@pytest.mark.sim
def test_diagram_writes_under_output_by_default_and_says_when_graphviz_is_missing(
        tmp_path, monkeypatch, capsys):
    """Without --out nothing tracked is rewritten: the diagrams go to ./output/diagrams; with
    no Graphviz the .dot files are written and the output says why there is no SVG."""
    import gbh_drake.diagrams

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(gbh_drake.diagrams.shutil, "which", lambda name: None)
    assert main(["diagram"]) == 0
    out = capsys.readouterr().out
    assert (tmp_path / "output" / "diagrams" / "trial.dot").is_file()
    assert not list((tmp_path / "output" / "diagrams").glob("*.svg"))
    assert "Graphviz's dot is not installed" in out


@pytest.mark.sim
def test_drakes_info_lines_are_kept_out_unless_verbose(caplog):
    """Meshcat's "listening at" line (a dead link once the run is over) and Drake's other INFO
    messages are not printed by default; --verbose brings them back."""
    import logging

    from gbh_drake.cli import quiet_drake
    from gbh_drake.viz.meshcat_server import local_meshcat

    caplog.set_level(logging.DEBUG, logger="")
    try:
        quiet_drake()
        local_meshcat()
        assert not [r for r in caplog.records if "Meshcat listening" in r.getMessage()]
        quiet_drake(verbose=True)
        local_meshcat()
        assert [r for r in caplog.records if "Meshcat listening" in r.getMessage()]
    finally:
        quiet_drake()


def test_a_port_out_of_range_is_refused():
    with pytest.raises(SystemExit) as e:
        main(["run", "--meshcat", "--port", "70000"])
    assert e.value.code == 2


def test_a_mesh_in_millimetres_is_refused_before_anything_is_simulated_with_the_hint_once(
        tmp_path):
    """A 16 cm staple written in millimetres (read as a 160 m object): exit 2, one line naming
    the file and object.scale with the scale hint, said once (no log line repeats it), and no
    output folder."""
    import subprocess
    import sys

    import trimesh

    from gbh_drake import SCENARIOS_DIR

    mesh = trimesh.load(SCENARIOS_DIR / "meshes" / "staple.obj")
    mesh.apply_scale(1000.0)
    mesh.export(tmp_path / "staple_mm.obj")
    (tmp_path / "mm.yaml").write_text("object:\n  mesh: staple_mm.obj\n  density: 500\n")
    done = subprocess.run([sys.executable, "-m", "gbh_drake.cli", "run", str(tmp_path / "mm.yaml")],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("give scale: 0.001") == 1, done.stderr
    assert done.stderr.startswith(f"gbh: invalid scenario: {tmp_path / 'mm.yaml'}: object.scale: ")
    assert "larger than the workspace" in done.stderr and not done.stdout
    assert not (tmp_path / "output").exists()
