"""docs/adding_a_method.md: its toy method, one spec and one add_systems, runs as written."""

import re

import pytest

from gbh_drake import REPO_ROOT

pytestmark = [pytest.mark.sim, pytest.mark.trial]


def test_the_toy_method_of_the_docs_runs_and_its_tiers_come_in_order():
    text = (REPO_ROOT / "docs" / "adding_a_method.md").read_text()
    code = re.search(r"<!-- toy-method -->\n```python\n(.*?)```", text, re.S).group(1)
    namespace: dict = {}
    exec(compile(code, "docs/adding_a_method.md", "exec"), namespace)
    record = namespace["record"]
    # The pinch is the first tier: the mug is pinched (two straight rods), the hooks untried.
    assert record.method == "pinch_first" and record.grasp_source == "grasps"
    assert record.grasp_kind == "antipodal"
    assert record.outcome in ("success", "not_lifted", "dropped_during_lift",
                              "dropped_during_carry"), record.reason
    assert record.held_by in ("", "pinch")
