"""How an object rests, in words: the tilt of its model's +z axis from the world's.

An object's mesh is modelled in the rest a person would set it down in, +z up; a start pose
(Drake's RollPitchYaw, R = Rz(yaw) Ry(pitch) Rx(roll)) tilts that axis by
acos(cos(pitch) cos(roll)), whatever the yaw.
"""

from __future__ import annotations

import math

#: Resting-pose classes by the tilt of the object's z axis from the world's (deg, [lo, hi)).
RESTING_POSES = (("upright", 0.0, 30.0), ("on its side", 30.0, 150.0), ("upside down", 150.0, 180.1))


def tilt_deg(roll: float, pitch: float) -> float:
    """Degrees between the object's +z and the world's, for a start pose's roll and pitch
    (rad)."""
    return math.degrees(math.acos(max(-1.0, min(1.0, math.cos(pitch) * math.cos(roll)))))


def resting_pose(pose: list[float]) -> str:
    """The class (:data:`RESTING_POSES`) of a start ``pose`` [x, y, z, roll, pitch, yaw] (m,
    rad)."""
    tilt = tilt_deg(float(pose[3]), float(pose[4]))
    return next(name for name, lo, hi in RESTING_POSES if lo <= tilt < hi)


def rest_in_words(pose: list[float]) -> str:
    """``"on its side (tilted 90 deg)"``: the class of ``pose`` and its tilt."""
    return f"{resting_pose(pose)} (tilted {tilt_deg(float(pose[3]), float(pose[4])):.0f} deg)"
