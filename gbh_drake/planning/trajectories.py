"""Timed joint-space trajectories of the arm, as Drake ``PiecewisePolynomial``s.

Paths through waypoints become cubic segments with zero velocity at every waypoint, each segment
as long as the slowest joint needs at :data:`VELOCITY_SCALE` of Franka's velocity limits (and at
least ``min_duration``). Evaluate with :func:`sample`, which holds the ends.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

#: Fraction of Franka's joint velocity limits used when timing arm motions.
VELOCITY_SCALE = 0.35
#: Franka's joint velocity limits (rad/s).
FRANKA_V_MAX = np.array([2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61])
#: The insert, approach to grasp (the rods go in beside the object): its velocity scale and
#: least duration (s).
INSERT_VELOCITY_SCALE, INSERT_MIN_DURATION = 0.15, 1.0


def segment_duration(q_a, q_b, *, velocity_scale: float = VELOCITY_SCALE,
                     min_duration: float = 0.5) -> float:
    """Seconds for a zero-velocity cubic from ``q_a`` to ``q_b`` (rad, 7 each): its peak
    velocity, 1.5 times the mean, stays within ``velocity_scale`` of the limits."""
    dq = np.abs(np.asarray(q_b, dtype=float) - np.asarray(q_a, dtype=float))
    return max(min_duration, float(np.max(1.5 * dq / (velocity_scale * FRANKA_V_MAX))))


def joint_path(waypoints: Sequence[np.ndarray], t0: float, *,
               velocity_scale: float = VELOCITY_SCALE,
               min_duration: float = 0.5) -> PiecewisePolynomial:
    """Zero-velocity cubic through ``waypoints`` (rad, 7 each) starting at time ``t0`` (s)."""
    q = np.stack([np.asarray(w, dtype=float) for w in waypoints], axis=1)
    if q.shape[1] == 1:
        q = np.concatenate([q, q], axis=1)
    times = [t0]
    for a, b in zip(q.T[:-1], q.T[1:], strict=True):
        times.append(times[-1] + segment_duration(a, b, velocity_scale=velocity_scale,
                                                  min_duration=min_duration))
    return PiecewisePolynomial.CubicHermite(times, q, np.zeros_like(q))


def linear_move(q_a, q_b, t0: float, duration: float) -> PiecewisePolynomial:
    """Constant joint velocity from ``q_a`` to ``q_b`` over ``duration`` s, from ``t0``."""
    q = np.stack([np.asarray(q_a, dtype=float), np.asarray(q_b, dtype=float)], axis=1)
    return PiecewisePolynomial.FirstOrderHold([t0, t0 + max(duration, 1e-3)], q)


def sample(trajectory: PiecewisePolynomial, t: float,
           derivative: PiecewisePolynomial | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity at ``t``, holding the ends (zero velocity outside the range);
    ``derivative``: the trajectory's derivative, if already at hand."""
    start, end = trajectory.start_time(), trajectory.end_time()
    tc = min(max(t, start), end)
    q = trajectory.value(tc).ravel()
    if not start < t < end:
        return q, np.zeros_like(q)
    v = (derivative.value(tc) if derivative is not None else trajectory.EvalDerivative(tc, 1))
    return q, v.ravel()


def polyline_path(waypoints: Sequence[np.ndarray], t0: float, *,
                  velocity_scale: float = VELOCITY_SCALE, min_duration: float = 0.5,
                  dt: float = 0.02) -> PiecewisePolynomial:
    """Through ``waypoints`` (rad, 7 each) along the straight joint segments between them,
    without stopping at each: one smooth time scaling (zero velocity at the two ends only, as
    :func:`joint_path`'s cubic) over the whole path, sampled every ``dt`` s (the segments'
    corners are cut by at most a sample's chord). The path's geometry is the one a planner
    checked segment by segment; two waypoints give :func:`joint_path`."""
    q = np.stack([np.asarray(w, dtype=float) for w in waypoints])
    if len(q) <= 2:
        return joint_path(list(q), t0, velocity_scale=velocity_scale, min_duration=min_duration)
    steps = np.abs(np.diff(q, axis=0))
    duration = segment_duration(np.zeros(7), steps.sum(axis=0), velocity_scale=velocity_scale,
                                min_duration=min_duration)
    # Arc parameter: each segment weighted by the time its slowest joint needs.
    length = np.concatenate([[0.0], np.cumsum((steps / FRANKA_V_MAX).max(axis=1))])
    length = length / max(length[-1], 1e-12)
    n = max(3, int(np.ceil(duration / dt)) + 1)
    tau = np.linspace(0.0, 1.0, n)
    sigma = tau * tau * (3.0 - 2.0 * tau)
    samples = np.stack([np.interp(sigma, length, q[:, j]) for j in range(q.shape[1])])
    times = t0 + duration * tau
    velocities = np.gradient(samples, times, axis=1)
    velocities[:, 0] = velocities[:, -1] = 0.0
    return PiecewisePolynomial.CubicHermite(times, samples, velocities)


def insert_path(descent: Sequence[np.ndarray], t0: float,
                press: np.ndarray | None = None) -> PiecewisePolynomial:
    """The insert through ``descent`` (rad, 7 each: the approach first, the grasp last; the
    plan's waypoints along the approach axis) from ``t0`` (s): along its straight joint
    segments without stopping (:func:`polyline_path`), at :data:`INSERT_VELOCITY_SCALE`, at
    least :data:`INSERT_MIN_DURATION` s; with ``press`` (a scoop's), on down to it as one
    segment more, the trajectory's last (its duration is the press's)."""
    path = polyline_path(descent, t0, velocity_scale=INSERT_VELOCITY_SCALE,
                         min_duration=INSERT_MIN_DURATION)
    if press is not None:
        path.ConcatenateInTime(joint_path([descent[-1], press], path.end_time(),
                                          velocity_scale=INSERT_VELOCITY_SCALE,
                                          min_duration=INSERT_MIN_DURATION))
    return path
