"""One seed per scenario, and the independent streams derived from it in one place.

``numpy.random.SeedSequence(seed).spawn`` gives statistically independent children; each stage
gets its own, so adding a random draw to one stage never changes another's draws. Same seed,
same streams, same trial.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: The streams, in spawning order (append new ones at the end: earlier ones keep their values).
STREAMS = ("pose", "sampling", "noise", "planner", "grasps")


@dataclass(frozen=True)
class Seeds:
    """32-bit seeds of the random streams of one trial."""

    pose: int
    """The object's start pose (Drake's ``RandomGenerator`` for ``schema.Transform``
    distributions, numpy for random resting poses)."""
    sampling: int
    """GbH's Poisson-disk surface sampling."""
    noise: int
    """The depth cameras' noise."""
    planner: int
    """RRT-Connect."""
    grasps: int
    """The antipodal grasp sampler."""


def derive_seeds(seed: int) -> Seeds:
    """The streams of scenario ``seed`` (any non-negative integer)."""
    children = np.random.SeedSequence(int(seed)).spawn(len(STREAMS))
    values = [int(c.generate_state(1, dtype=np.uint32)[0]) for c in children]
    return Seeds(**dict(zip(STREAMS, values, strict=True)))
