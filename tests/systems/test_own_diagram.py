"""The "your own diagram" example of docs/own_diagram.md runs as written and carries the mug by a
cage."""

import re

import pytest

from gbh_drake import REPO_ROOT

PAGE = (REPO_ROOT / "docs" / "own_diagram.md").read_text()


def _example() -> str:
    after = PAGE[PAGE.index("<!-- own-diagram -->"):]
    return re.search(r"```python\n(.*?)```", after, re.S).group(1)


def test_every_system_the_page_lists_is_exported_by_gbh_drake_systems():
    """The page's table says ``gbh_drake.systems`` exports every stage it lists (and its API
    reference is generated from that module)."""
    import gbh_drake.systems as systems

    table = re.search(r"```\n(make_station.*?)```", PAGE, re.S).group(1)
    listed = set(re.findall(r"^([A-Z]\w+)\(", table, re.M)) - {"Station"}
    assert {"Scanner", "DepthImageScanner", "ScoopSynthesizer", "RegraspPlanner"} <= listed
    assert listed <= set(systems.__all__), listed - set(systems.__all__)


@pytest.mark.sim
@pytest.mark.trial
def test_own_diagram_example_runs(capsys):
    from gbh_drake.systems.cage_monitor import NOT_JUDGED

    namespace: dict = {}
    exec(compile(_example(), "docs/own_diagram.md", "exec"), namespace)
    verdict = namespace["verdict"]
    assert verdict.outcome == "success" and verdict.held_by == "cage", verdict.reason
    assert NOT_JUDGED not in verdict.reason  # judged by what the loop encloses, as a trial is
    assert capsys.readouterr().out.startswith("success cage")
