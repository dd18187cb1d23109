"""The README's "your own diagram" example runs as written and carries the mug by a cage."""

import re

import pytest

from gbh_drake import REPO_ROOT

pytestmark = pytest.mark.sim


def _readme_example() -> str:
    text = (REPO_ROOT / "README.md").read_text()
    after = text[text.index("<!-- own-diagram -->"):]
    return re.search(r"```python\n(.*?)```", after, re.S).group(1)


@pytest.mark.trial
def test_readme_own_diagram_example_runs(capsys):
    namespace: dict = {}
    exec(compile(_readme_example(), "README.md (own diagram)", "exec"), namespace)
    verdict = namespace["verdict"]
    assert verdict.outcome == "success" and verdict.held_by == "cage", verdict.reason
    assert capsys.readouterr().out.startswith("success cage")
