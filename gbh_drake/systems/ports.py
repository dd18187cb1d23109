"""Typed connections for Python values: a wrong ``Connect()`` fails when the diagram is built.

pydrake holds every Python value on an abstract port as ``Value[object]``, so Drake's own type
check at ``Connect()`` accepts any pair of such ports and a wrong wire fails only at the first
``Eval``, deep inside a calc. Every port of gbh_drake's systems is declared with a typed model
value (a ``ScanResult``, a ``Hangability``, a ``PickStatus``...); :func:`check_connections`
compares the model values on both ends of every ``Value[object]`` connection of a built diagram
(sub-diagrams included) and :func:`build_checked` builds and checks. ``build_trial`` uses it.

An input accepts the type of its model value, or the types a system lists for it in its
``input_types`` attribute (``{port name: (type, ...)}``; e.g. the GbH stages take a
``ScanResult`` or a ``trimesh.Trimesh``).
"""

from __future__ import annotations

from pydrake.common.value import Value
from pydrake.systems.framework import Diagram, DiagramBuilder, InputPort, PortDataType


def accepted_types(port: InputPort) -> tuple[type, ...]:
    """The Python types ``port`` (abstract, ``Value[object]``) accepts."""
    declared = getattr(port.get_system(), "input_types", {}).get(port.get_name())
    return tuple(declared) if declared else (type(port.Allocate().get_value()),)


def check_connections(diagram: Diagram) -> None:
    """Raises ``TypeError`` for the first connection of ``diagram`` (or of a sub-diagram)
    whose output's model value is not of a type its input accepts, naming both ports."""
    for (in_system, in_index), (out_system, out_index) in diagram.connection_map().items():
        port = in_system.get_input_port(in_index)
        if port.get_data_type() != PortDataType.kAbstractValued:
            continue
        model = out_system.get_output_port(out_index).Allocate()
        if not isinstance(model, Value[object]):
            continue  # a C++ type: Drake checked it at Connect()
        accepts = accepted_types(port)
        value = model.get_value()
        if not isinstance(value, accepts):
            names = " or ".join(t.__name__ for t in accepts)
            raise TypeError(
                f"{diagram.get_name() or 'diagram'}: output "
                f"{out_system.get_name()}.{out_system.get_output_port(out_index).get_name()} "
                f"({type(value).__name__}) is connected to input "
                f"{in_system.get_name()}.{port.get_name()}, which takes {names}")
    for system in diagram.GetSystems():
        if isinstance(system, Diagram):
            check_connections(system)


def build_checked(builder: DiagramBuilder) -> Diagram:
    """``builder.Build()``, then :func:`check_connections` on the result."""
    diagram = builder.Build()
    check_connections(diagram)
    return diagram
