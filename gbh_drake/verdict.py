"""Did the grasp hold? The trial verdict from the simulated poses alone.

Success follows the paper (Sec. 3.1): the object is picked up and transported without falling.
Here: by the end of the lift the object has risen by at least ``min_lift_fraction`` of the
gripper's rise, and at the end of every later phase (carry, hold) its lowest point is still at
least ``min_clearance`` above the table (z = 0 in W): a dropped object lies on the table again.
A hooked object may swing about the hook, so its pose relative to the gripper is not part of the
rule. Contact only: the object is a free body throughout, so only caging and friction carried it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Sample:
    """Poses at the end of one phase: object O and gripper G in W (4x4), time (s)."""

    t: float
    label: str
    X_WO: np.ndarray
    X_WG: np.ndarray


@dataclass
class Verdict:
    """``success`` and why; ``lift`` (m): how far the object rose by the end of the lift;
    ``clearance`` (m): its lowest point above the table at the end."""

    success: bool
    reason: str
    lift: float = 0.0
    clearance: float = 0.0


def lowest_point_z(X_WO: np.ndarray, p_OV: np.ndarray) -> float:
    """Lowest z (m, in W) of the object's points ``p_OV`` (n, 3, frame O) at pose ``X_WO``."""
    return float((p_OV @ X_WO[2, :3] + X_WO[2, 3]).min())


def judge(samples: list[Sample], p_OV: np.ndarray, *, grasp_label: str = "close",
          lift_label: str = "lift", lift_height: float = 0.15, min_lift_fraction: float = 0.6,
          min_clearance: float = 0.02) -> Verdict:
    """The verdict from poses sampled at the ends of the pick's phases (see module docstring).

    ``p_OV`` (n, 3): the object's mesh vertices in its frame O (m)."""
    labels = [s.label for s in samples]
    if grasp_label not in labels or lift_label not in labels:
        return Verdict(False, "the pick did not reach its lift phase")
    start = samples[labels.index(grasp_label)]
    i_lift = labels.index(lift_label)
    lift = float(samples[i_lift].X_WO[2, 3] - start.X_WO[2, 3])
    if lift < min_lift_fraction * lift_height:
        return Verdict(False, f"not lifted: the object rose {lift * 100:.1f} cm of "
                              f"{lift_height * 100:.0f} cm", lift)
    clearance = lift
    for s in samples[i_lift:]:
        clearance = lowest_point_z(s.X_WO, p_OV)
        if clearance < min_clearance:
            return Verdict(False, f"dropped during {s.label}: its lowest point is "
                                  f"{clearance * 100:.1f} cm above the table", lift, clearance)
    return Verdict(True, "picked and carried", lift, clearance)
