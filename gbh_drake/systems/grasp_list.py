"""The ``GraspList`` system: grasps given from outside, held in the context."""

from __future__ import annotations

from pydrake.common.value import AbstractValue
from pydrake.systems.framework import LeafSystem


class GraspList(LeafSystem):
    """Outputs the grasps it holds: given ones (each with ``X_WG`` and ``kind``), kept in an
    abstract parameter of the context, so that a caller may give other grasps to a built
    diagram between runs (:meth:`set_grasps`; the studio executes the grasp chosen on its
    page this way).

    .. pydrake_system::

        name: GraspList
        output_ports:
        - grasps
    """

    def __init__(self, grasps=()):
        """``grasps``: what the output holds in a new context."""
        super().__init__()
        self._grasps = self.DeclareAbstractParameter(AbstractValue.Make(list(grasps)))
        self.DeclareAbstractOutputPort(
            "grasps", lambda: AbstractValue.Make([]),
            lambda context, output: output.set_value(list(self.grasps(context))),
            prerequisites_of_calc={self.all_parameters_ticket()})

    def grasps(self, context) -> list:
        """The grasps held in ``context`` (this system's)."""
        return context.get_abstract_parameter(self._grasps).get_value()

    def set_grasps(self, context, grasps) -> None:
        """Holds ``grasps`` (a list, best first) in ``context`` (this system's)."""
        context.get_mutable_abstract_parameter(self._grasps).set_value(list(grasps))
