"""The arguments of the public functions: a value of the wrong type is refused at the call,
naming the function and the argument (``build_trial(): method: expected a GraspMethod ...,
got 'gbh' (a str)``), instead of failing deep inside with a message about something else.

A scenario's own fields are checked by its rules (:mod:`gbh_drake.core.ranges`,
:func:`gbh_drake.scenario.loader.require_scenario`); this is for the other arguments. Pure
Python (no pydrake): the core imports it.
"""

from gbh_drake.core.ranges import shown


def argument_problem(function: str, name: str, expected: str, value) -> str:
    """``<function>(): <name>: expected <expected>, got <value> (<its type>)``."""
    return f"{function}(): {name}: expected {expected}, got {shown(value)}"


def require(function: str, name: str, value, kinds, expected: str, error=TypeError):
    """``value`` when it is an instance of ``kinds`` (a type or tuple of types; None allowed
    only when listed), else raises ``error`` (:func:`argument_problem`)."""
    if not isinstance(value, kinds):
        raise error(argument_problem(function, name, expected, value))
    return value
