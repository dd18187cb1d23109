"""Joint-space trajectories for the arm and the fingers, as Drake ``PiecewisePolynomial``s.

A :class:`MotionScript` is a list of timed keyframes (arm q, finger q); it becomes arm and finger
trajectories, cubic between keyframes with zero velocity at each, whose ``TrajectorySource``s feed
the station's desired-state inputs ([q, v]).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

#: Fraction of Franka's joint velocity limits used when timing arm motions.
VELOCITY_SCALE = 0.35
#: Franka's joint velocity limits (rad/s).
FRANKA_V_MAX = np.array([2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61])


@dataclass
class MotionScript:
    """Keyframes ``(t, q_arm (7,), q_finger)``: seconds, radians, metres (one finger's position)."""

    times: list[float] = field(default_factory=list)
    arm: list[np.ndarray] = field(default_factory=list)
    finger: list[float] = field(default_factory=list)
    labels: list[str] = field(default_factory=list)

    def start(self, q_arm, q_finger: float, label: str = "start") -> MotionScript:
        self.times.append(0.0)
        self.arm.append(np.asarray(q_arm, dtype=float))
        self.finger.append(float(q_finger))
        self.labels.append(label)
        return self

    def move_arm(self, q_arm, label: str, *, min_duration: float = 0.5) -> MotionScript:
        """Moves the arm to ``q_arm`` at a speed bounded by :data:`VELOCITY_SCALE` of the limits."""
        q_arm = np.asarray(q_arm, dtype=float)
        dq = np.abs(q_arm - self.arm[-1])
        duration = max(min_duration, float(np.max(1.5 * dq / (VELOCITY_SCALE * FRANKA_V_MAX))))
        return self._append(duration, q_arm, self.finger[-1], label)

    def move(self, q_arm, q_finger: float, label: str, duration: float) -> MotionScript:
        """Arm and fingers together, over ``duration`` s."""
        return self._append(duration, np.asarray(q_arm, dtype=float), q_finger, label)

    def hold(self, duration: float, label: str = "hold") -> MotionScript:
        return self._append(duration, self.arm[-1], self.finger[-1], label)

    def _append(self, duration, q_arm, q_finger, label) -> MotionScript:
        self.times.append(self.times[-1] + float(duration))
        self.arm.append(np.asarray(q_arm, dtype=float))
        self.finger.append(float(q_finger))
        self.labels.append(label)
        return self

    @property
    def end_time(self) -> float:
        return self.times[-1]

    def time_of(self, label: str) -> float:
        """End time of the keyframe named ``label``."""
        return self.times[self.labels.index(label)]

    def arm_trajectory(self) -> PiecewisePolynomial:
        """Arm q(t): piecewise cubic with zero velocity at every keyframe (rad)."""
        return _zero_velocity_cubic(self.times, np.stack(self.arm, axis=1))

    def finger_trajectory(self) -> PiecewisePolynomial:
        """Both fingers' q(t) (2 rows, metres): the same zero-velocity cubic time-scaling as the
        arm, so that arm and fingers moving together (``move``) stay in step."""
        return _zero_velocity_cubic(self.times, np.stack([self.finger, self.finger]))


def _zero_velocity_cubic(times: list[float], q: np.ndarray) -> PiecewisePolynomial:
    """Cubic segments through the keyframes ``q`` (n, k) with zero velocity at each of them."""
    if len(times) == 1:
        return PiecewisePolynomial(q)
    return PiecewisePolynomial.CubicHermite(times, q, np.zeros_like(q))
