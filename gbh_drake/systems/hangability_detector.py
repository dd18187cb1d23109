"""The ``HangabilityDetector`` system: a mesh in, the hanging structures out (paper Sec. 2.2)."""

from __future__ import annotations

from dataclasses import dataclass, field

import trimesh

from gbh_drake.core.object_model import ObjectModel
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import detect
from gbh_drake.core.results import GbhInputError, HangingStructure
from gbh_drake.systems.stage import AbstractStage


@dataclass
class Hangability:
    """The detector's output: the prepared object (samples, CoM; None when the input was
    unusable), its hanging structures (in W) and a message when there are none."""

    object: ObjectModel | None
    structures: list[HangingStructure] = field(default_factory=list)
    message: str = ""


class HangabilityDetector(AbstractStage):
    """Finds the structures an object can hang by.

    @system
    name: HangabilityDetector
    input_ports:
    - mesh_W
    output_ports:
    - hanging_structures
    @endsystem

    ``mesh_W``: a ``trimesh.Trimesh`` in W, or the Scanner's ``ScanResult`` (its ``mesh_W``).
    ``hanging_structures``: a :class:`Hangability`. "Nothing hangable", an empty scan or an
    unusable mesh are results (empty ``structures`` and a ``message``), not exceptions.
    """

    def __init__(self, params: GbhParams | None = None):
        super().__init__("mesh_W", "hanging_structures")
        self.params = params or GbhParams()

    def compute(self, value) -> Hangability:
        if getattr(value, "empty", False):
            return Hangability(None, [], value.message or "empty scan")
        mesh = getattr(value, "mesh_W", value)
        if not isinstance(mesh, trimesh.Trimesh):
            return Hangability(None, [], f"mesh_W holds {type(value).__name__}, not a mesh")
        try:
            obj, structures = detect(mesh, self.params)
        except GbhInputError as e:
            return Hangability(None, [], f"unusable mesh: {e}")
        return Hangability(obj, structures, "" if structures else "no hangable structure found")
