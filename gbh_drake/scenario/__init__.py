"""Scenarios: one YAML file describes one run (robot, table, object, cameras, simulation).

* :mod:`.schema`: :class:`Scenario` and the config dataclasses it composes, each field with its
  unit, default and range (the rule types are :mod:`gbh_drake.core.ranges`);
* :mod:`.loader`: :func:`load_scenario` (a file, then ``--set`` overrides, as layers),
  :class:`ScenarioError`, :func:`validate_scenario`, :func:`dump_resolved`;
* :mod:`.yaml_text`: what Drake's ``yaml_load_typed`` does not check in the YAML text, and where
  a field is written;
* :mod:`.checks`: every field checked before anything is built (finite numbers, ranges,
  relations), with :mod:`.poses`, :mod:`.object_checks`, :mod:`.cameras` and
  :mod:`.start_state`; the model directives are checked by :mod:`gbh_drake.modeling.directives`.

docs/errors.md lists the checks and limits.
"""

from gbh_drake.core.ranges import FieldError
from gbh_drake.scenario.loader import ScenarioError, dump_resolved, load_scenario, validate_scenario
from gbh_drake.scenario.schema import (
    DEFAULT_DIRECTIVES,
    DEFAULT_Q_HOME,
    RESTS,
    TASKS,
    HandConfig,
    MonitorConfig,
    ObjectConfig,
    PickConfig,
    RandomRestingPose,
    RobotConfig,
    Scenario,
    default_directives,
)

__all__ = [
    "DEFAULT_DIRECTIVES", "DEFAULT_Q_HOME", "RESTS", "TASKS", "FieldError", "HandConfig",
    "MonitorConfig", "ObjectConfig", "PickConfig", "RandomRestingPose", "RobotConfig", "Scenario",
    "ScenarioError", "default_directives", "dump_resolved", "load_scenario", "validate_scenario",
]
