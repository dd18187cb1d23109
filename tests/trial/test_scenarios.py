"""Every shipped scenario file and every named test scenario runs through the real command line
(a short settle-only override each), in the style of Drake's hardware_sim tests."""

import dataclasses

import pytest
import yaml

from gbh_drake import SCENARIOS_DIR
from gbh_drake.cli import main
from gbh_drake.scenario import Scenario, load_scenario

SCENARIOS = sorted(p for p in SCENARIOS_DIR.glob("*.yaml") if not p.stem.startswith("experiment"))
NAMED_FILE = __import__("pathlib").Path(__file__).with_name("named_scenarios.yaml")
NAMED = yaml.safe_load(NAMED_FILE.read_text().replace("!Rpy", "")) or {}
SHORT = "task: settle\nsettle_time: 0.05"


def test_there_are_scenarios():
    assert any(p.name == "default.yaml" for p in SCENARIOS)
    assert {"Defaults", "OneOfEverything"} <= set(NAMED)


def test_one_of_everything_sets_every_field():
    text = NAMED_FILE.read_text()
    body = text[text.index("OneOfEverything:"):]
    top = {line.split(":")[0].strip() for line in body.splitlines()[1:]
           if line.startswith("  ") and not line.startswith("   ") and ":" in line}
    fields = {f.name for f in dataclasses.fields(Scenario)} - {"source_path"}
    assert fields <= top, f"OneOfEverything misses {sorted(fields - top)}"


def _named_file(tmp_path, name):
    """The named scenario ``name`` written as a file of its own (YAML tags kept)."""
    text = NAMED_FILE.read_text()
    start = text.index(f"\n{name}:") + 1
    lines = text[start:].splitlines()[1:]
    body = []
    for line in lines:
        if line and not line.startswith(" "):
            break
        body.append(line[2:])
    if text[start:].splitlines()[0].strip().endswith("{}"):
        body = ["{}"]
    path = tmp_path / f"{name}.yaml"
    path.write_text("\n".join(body) + "\n")
    return path


@pytest.mark.sim
@pytest.mark.parametrize("name", sorted(NAMED))
def test_named_scenario_runs_from_the_command_line(name, tmp_path, capsys):
    path = _named_file(tmp_path, name)
    assert main(["run", str(path), "--set", f"{SHORT}\noutput_dir: {tmp_path / 'out'}"]) == 0
    out = capsys.readouterr().out
    assert "scenario" in out and "replay" in out
    for file in ("replay.html", "summary.yaml", "scenario.yaml"):
        assert (tmp_path / "out" / file).is_file()


@pytest.mark.sim
@pytest.mark.parametrize("path", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_shipped_scenario_runs_from_the_command_line(path, tmp_path, capsys):
    assert main(["run", str(path), "--set", f"{SHORT}\noutput_dir: {tmp_path}"]) == 0
    for name in ("replay.html", "summary.yaml", "scenario.yaml"):
        assert (tmp_path / name).is_file()
    saved = load_scenario(tmp_path / "scenario.yaml")
    assert saved.seed == load_scenario(path).seed
