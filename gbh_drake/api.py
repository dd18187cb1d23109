"""One call for one trial: ``gbh_drake.run_trial(scenario_or_path) -> TrialRecord``.

The same trial as ``gbh run`` (:func:`gbh_drake.trial.record_trial`: build, simulate until the
scenario's ``max_time`` or the machine is done, judge), without writing an output folder::

    import gbh_drake

    record = gbh_drake.run_trial("scenarios/default.yaml", overrides="seed: 3")
    print(record.outcome, record.held_by, record.reason)
"""

from __future__ import annotations

import os
from pathlib import Path

from pydrake.geometry import Meshcat

from gbh_drake.core.arguments import require
from gbh_drake.core.ranges import shown
from gbh_drake.scenario import Scenario, ScenarioError, load_scenario
from gbh_drake.scenario.loader import Overrides, apply_overrides, validate_scenario
from gbh_drake.trial import TrialRecord, record_trial


def run_trial(scenario_or_path: Scenario | str | Path | None = None, *,
              overrides: Overrides | None = None, meshcat: Meshcat | None = None) -> TrialRecord:
    """Simulates one trial and returns its :class:`~gbh_drake.trial.TrialRecord`.

    ``scenario_or_path``: a scenario file (default: the packaged ``scenarios/default.yaml``) or
    a :class:`~gbh_drake.scenario.Scenario` built in code (checked first); ``overrides``: YAML
    text (a str, or bytes read from a file: decoded as UTF-8), or several applied in order, on
    top, as ``gbh run --set`` (a relative path in them is relative to the current folder);
    ``meshcat``: a ``pydrake.geometry.Meshcat`` to draw the trial in as it runs (its scene is
    cleared first), or None. Raises :class:`~gbh_drake.scenario.ScenarioError` for a bad
    scenario or overrides (a value of the wrong type too), TypeError for a ``meshcat`` that is
    not one."""
    require("run_trial", "meshcat", meshcat, (Meshcat, type(None)),
            "a pydrake.geometry.Meshcat or None")
    if scenario_or_path is None:
        from gbh_drake import SCENARIOS_DIR

        scenario_or_path = SCENARIOS_DIR / "default.yaml"
    if not isinstance(scenario_or_path, Scenario | str | os.PathLike):
        raise ScenarioError("run_trial()", "scenario_or_path", None, "expected a Scenario, a "
                            f"scenario file's path or None, got {shown(scenario_or_path)}")
    overrides = "" if overrides is None else overrides
    if isinstance(scenario_or_path, Scenario):
        scenario = scenario_or_path
        validate_scenario(scenario, scenario.source_path or "<in memory>")
        scenario = apply_overrides(scenario, overrides, scenario.source_path or "<in memory>")
    else:
        scenario = load_scenario(scenario_or_path, overrides=overrides)
    return record_trial(scenario, meshcat=meshcat, keep_replay=False,
                        live=meshcat is not None).record
