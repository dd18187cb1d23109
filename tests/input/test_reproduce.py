"""Every run's folder holds its resolved scenario.yaml (file plus overrides); ``gbh run`` of
that file, from anywhere, gives the same record (timings and paths aside)."""

from __future__ import annotations

import pytest
import yaml

from gbh_drake.cli import main

pytestmark = pytest.mark.sim

#: Keys of summary.yaml that differ between two identical runs.
VARYING = ("timings", "scenario", "replay")


def _record(folder) -> dict:
    summary = yaml.safe_load((folder / "summary.yaml").read_text())
    return {k: v for k, v in summary.items() if k not in VARYING}


def _body(text: str) -> str:
    """scenario.yaml without its comment header (which names the source and the folder)."""
    return "\n".join(line for line in text.splitlines() if not line.startswith("#"))


def _rerun(tmp_path, monkeypatch, scenario_text: str, overrides: list[str]):
    source = tmp_path / "src" / "scenario_in.yaml"
    source.parent.mkdir(exist_ok=True)
    source.write_text(scenario_text)
    first, second = tmp_path / "first", tmp_path / "second"
    argv = ["run", str(source), "--set", f"output_dir: {first}"]
    for text in overrides:
        argv += ["--set", text]
    assert main(argv) == 0
    saved = first / "scenario.yaml"
    assert "output_dir: ''" in saved.read_text()  # a rerun does not overwrite this folder
    other = tmp_path / "elsewhere"  # relative paths in the saved file were made absolute
    other.mkdir()
    monkeypatch.chdir(other)
    assert main(["run", str(saved), "--set", f"output_dir: {second}"]) == 0
    assert _record(first) == _record(second)
    assert _body(saved.read_text()) == _body((second / "scenario.yaml").read_text())
    return _record(first)


def test_settle_run_is_reproduced_from_its_folder(tmp_path, monkeypatch):
    from input_corpus import CUBE_OBJ

    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "cube.obj").write_text(CUBE_OBJ)
    record = _rerun(tmp_path, monkeypatch, "seed: 3\nobject:\n  mesh: ../meshes/cube.obj\n"
                    "  random_pose: {x: [0.5, 0.6]}\n",
                    ["task: settle\nsettle_time: 0.05", "object: {density: 800}"])
    assert record["task"] == "settle" and record["seed"] == 3


@pytest.mark.trial
def test_pick_is_reproduced_from_its_folder(tmp_path, monkeypatch):
    """A real (short) pick: settle, scan, GbH, planning and the start of the motion."""
    record = _rerun(tmp_path, monkeypatch, "seed: 1\nsettle_time: 0.2\n", ["max_time: 4"])
    assert record["task"] == "pick" and record["n_ranked"] > 0 and record["grasp_rank"] >= 0
