"""The README's example run is what ``gbh run scenarios/default.yaml`` prints today, wall times
and real-time factors aside, the physics' decimals to 2 % (tools/readme_run_output.py writes it)."""

import importlib.util

import pytest

from gbh_drake import REPO_ROOT

spec = importlib.util.spec_from_file_location("readme_run_output",
                                              REPO_ROOT / "tools" / "readme_run_output.py")
readme_run_output = importlib.util.module_from_spec(spec)
spec.loader.exec_module(readme_run_output)

RUN = """scenario scenarios/default.yaml
  simulated 11.68 s in 5.02 s wall (2.33x real time); phases: settle, plan, done
  verdict: SUCCESS [cage]: success: picked and carried
  timings: scan 0.74 s, grasps 0.17 s, simulate 5.02 s
  replay: output/default/replay.html"""


def test_only_the_machine_s_figures_are_normalised():
    slower = RUN.replace("5.02 s wall (2.33x", "15.94 s wall (0.73x").replace("scan 0.74", "scan 8.8")
    assert readme_run_output.normalised(slower) == readme_run_output.normalised(RUN)
    other = RUN.replace("simulated 11.68", "simulated 11.70")
    assert readme_run_output.normalised(other) != readme_run_output.normalised(RUN)
    assert readme_run_output.normalised(RUN.replace("[cage]", "[pinch]")) != \
        readme_run_output.normalised(RUN)


def test_a_processor_s_last_digits_are_the_same_run_and_anything_else_is_not():
    """Another processor moves the physics' last digits (11.68 s simulated, or 11.70); counts,
    words and a real change of a figure are another run."""
    same = RUN.replace("simulated 11.68", "simulated 11.70").replace("5.02 s wall", "9.1 s wall")
    assert readme_run_output.same_run(RUN, same)
    for other in (RUN.replace("simulated 11.68", "simulated 12.40"),
                  RUN.replace("[cage]", "[pinch]"), RUN.replace("plan, done", "plan, lift, done"),
                  RUN + "\n  grasps: 1 hanging structures, 720 candidates",
                  RUN.replace("scenario scenarios", "scenario 2 scenarios")):
        assert not readme_run_output.same_run(RUN, other)
    assert not readme_run_output.same_run(RUN + " 720", RUN + " 719")  # counts exactly


def test_the_block_round_trips():
    text = "before\n" + readme_run_output.block("old") + "\nafter\n"
    new = readme_run_output.with_block(text, RUN)
    assert readme_run_output.readme_output(new) == RUN
    assert new.startswith("before\n") and new.endswith("\nafter\n")


@pytest.mark.trial
def test_the_readme_shows_a_fresh_run():
    stated = readme_run_output.readme_output((REPO_ROOT / "README.md").read_text())
    fresh = readme_run_output.fresh_run()
    assert readme_run_output.same_run(stated, fresh), (
        "README.md's run output is stale: python tools/readme_run_output.py rewrites it")
