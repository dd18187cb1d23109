# TEMPORARY, NOT COMMITTED: keeps the other engineer's imports working until the one-pass sed.
from gbh_drake.scenario.schema import *  # noqa: F403
from gbh_drake.scenario.schema import DEFAULT_Q_HOME, default_directives  # noqa: F401
