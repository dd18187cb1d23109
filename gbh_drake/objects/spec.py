"""What an object of the set is: its mesh, mass data, colour and ground-truth hangable parts.

Frame O (the object frame): metres, z up, the object resting in its natural stable pose on the
plane z = 0 (its lowest point at z = 0), x and y roughly centred on its footprint.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation

#: Kinds of hangable part: a ``"closed"`` loop (a through hole) or an ``"open"`` hook.
HANGABLE_KINDS = ("closed", "open")


@dataclass
class HangablePart:
    """A ground-truth hangable structure in frame O.

    ``center_O`` (3,) is the centre of the hole (the point a rod through it should pass, metres),
    ``axis_O`` (3,) the unit hole axis (sign arbitrary), ``kind`` ``"closed"`` or ``"open"``, and
    ``clear_diameter`` the diameter (m) of the largest rod that passes along the axis through the
    centre without touching the object.
    """

    name: str
    center_O: np.ndarray
    axis_O: np.ndarray
    kind: str
    clear_diameter: float

    def __post_init__(self) -> None:
        self.center_O = np.asarray(self.center_O, dtype=np.float64).reshape(3)
        axis = np.asarray(self.axis_O, dtype=np.float64).reshape(3)
        self.axis_O = axis / np.linalg.norm(axis)
        if self.kind not in HANGABLE_KINDS:
            raise ValueError(f"hangable part {self.name!r}: kind {self.kind!r} not in "
                             f"{HANGABLE_KINDS}")

    def as_dict(self) -> dict:
        """Plain-python form (lists and floats), e.g. for YAML."""
        return {
            "name": self.name,
            "center_O": [round(float(v), 6) for v in self.center_O],
            "axis_O": [round(float(v), 6) for v in self.axis_O],
            "kind": self.kind,
            "clear_diameter": round(float(self.clear_diameter), 6),
        }


@dataclass(frozen=True)
class NaturalRest:
    """The rest a person would set the object down in (the ``natural`` protocol's orientation).

    ``rpy_deg`` (3,): roll, pitch, yaw (deg; Drake's RollPitchYaw, R = Rz(yaw) Ry(pitch)
    Rx(roll)) turning frame O into that rest, before the trial's random yaw about z; (0, 0, 0)
    when O itself is the natural rest. ``reason``: one line saying why a person would set it
    down so.
    """

    rpy_deg: tuple[float, float, float]
    reason: str

    def __post_init__(self) -> None:
        if len(self.rpy_deg) != 3 or not all(np.isfinite(self.rpy_deg)):
            raise ValueError(f"natural rest: rpy_deg needs 3 finite numbers, got {self.rpy_deg}")
        if not self.reason.strip() or "\n" in self.reason:
            raise ValueError("natural rest: give a one-line reason")

    @property
    def R(self) -> np.ndarray:
        """(3, 3) the rotation taking O to the rest (applied to O's coordinates)."""
        return Rotation.from_euler("xyz", self.rpy_deg, degrees=True).as_matrix()


@dataclass
class ObjectSpec:
    """One object of the set.

    ``mesh`` is in frame O (metres); ``density`` (kg/m^3) applies to the mesh's solid volume (for
    the procedural objects it is chosen so that the mass is realistic, see ``catalog``);
    ``rgba`` the display colour in [0, 1]. ``genus`` is the designed genus of the (single,
    watertight) body, or None for imported meshes that are not watertight. ``natural_rest``:
    the rest a person would set it down in (declared once per object where the object set
    registers it, ``catalog``), None when none was declared.
    """

    name: str
    mesh: trimesh.Trimesh
    density: float
    hangable_parts: list[HangablePart]
    is_control: bool
    rgba: tuple[float, float, float, float]
    description: str
    genus: int | None = None
    metadata: dict = field(default_factory=dict)
    natural_rest: NaturalRest | None = None
