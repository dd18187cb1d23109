"""The "your own diagram" example of docs/own_diagram.md runs as written and carries the mug by a
cage."""

import re

import pytest

from gbh_drake import REPO_ROOT

pytestmark = pytest.mark.sim


def _example() -> str:
    text = (REPO_ROOT / "docs" / "own_diagram.md").read_text()
    after = text[text.index("<!-- own-diagram -->"):]
    return re.search(r"```python\n(.*?)```", after, re.S).group(1)


@pytest.mark.trial
def test_own_diagram_example_runs(capsys):
    namespace: dict = {}
    exec(compile(_example(), "docs/own_diagram.md", "exec"), namespace)
    verdict = namespace["verdict"]
    assert verdict.outcome == "success" and verdict.held_by == "cage", verdict.reason
    assert capsys.readouterr().out.startswith("success cage")
