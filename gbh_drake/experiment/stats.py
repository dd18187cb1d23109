"""The statistics of an experiment's report, pure functions of counts and paired outcomes.

- :func:`wilson`: the Wilson score interval of a success rate (closed form; 95 % by default).
  Asked of zero trials it raises ``ValueError`` (there is no rate); the report prints "-".
- :func:`mcnemar`: two methods on the same (object, trial) poses. ``n10`` pairs that only the
  first method picked, ``n01`` only the second; McNemar's exact test is the two-sided binomial
  test of ``n10`` out of ``n10 + n01`` at 1/2 (``scipy.stats.binomtest``; p = 1 without a
  discordant pair). The difference in rate (first - second) = (n10 - n01) / pairs, with a 95 %
  **paired bootstrap** percentile interval: the pairs resampled with replacement, i.e. the four
  cell counts (both, first only, second only, neither) drawn from the multinomial of their
  observed shares, :data:`BOOTSTRAP_DRAWS` times with a fixed seed (the same rows give the
  same interval).
- :func:`holm`: Holm's step-down adjustment of a family of p-values (the report tests every
  pair of methods).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

#: Resamples of the paired bootstrap, and its seed.
BOOTSTRAP_DRAWS = 10000
BOOTSTRAP_SEED = 0


def wilson(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval (lo, hi) of ``successes`` out of ``n`` trials at the normal
    quantile ``z`` (1.96: 95 %). Raises ``ValueError`` for ``n < 1`` or ``successes`` outside
    0..n."""
    if n < 1:
        raise ValueError(f"Wilson interval of {successes} successes in {n} trials: no trials, "
                         "so no rate to bound")
    if not 0 <= successes <= n:
        raise ValueError(f"Wilson interval of {successes} successes in {n} trials: successes "
                         "must lie in 0..n")
    p, z2 = successes / n, z * z
    denominator = 1.0 + z2 / n
    centre = (p + z2 / (2 * n)) / denominator
    half = z / denominator * math.sqrt(p * (1.0 - p) / n + z2 / (4 * n * n))
    lo, hi = max(0.0, centre - half), min(1.0, centre + half)
    if successes == 0:  # exactly, not by rounding
        lo = 0.0
    if successes == n:
        hi = 1.0
    return lo, hi


@dataclass(frozen=True)
class Paired:
    """Two methods on the same poses (see the module docstring)."""

    pairs: int
    both: int
    n10: int
    """Pairs only the first method succeeded on."""
    n01: int
    """Pairs only the second method succeeded on."""
    p_value: float
    """McNemar's exact two-sided p-value."""
    diff: float
    """Rate of the first minus rate of the second."""
    diff_lo: float
    diff_hi: float
    """The paired-bootstrap 95 % interval of ``diff``."""

    @property
    def neither(self) -> int:
        return self.pairs - self.both - self.n10 - self.n01


def mcnemar(first: Sequence[bool], second: Sequence[bool], *, draws: int = BOOTSTRAP_DRAWS,
            seed: int = BOOTSTRAP_SEED) -> Paired:
    """McNemar's exact test and the paired difference in rate of two equally long sequences of
    outcomes on the same poses (``first[i]`` and ``second[i]``: pose i). Raises ``ValueError``
    when they differ in length or are empty."""
    import numpy as np
    from scipy.stats import binomtest

    if len(first) != len(second):
        raise ValueError(f"McNemar's test of {len(first)} outcomes against {len(second)}: they "
                         "must be paired one to one")
    n = len(first)
    if n == 0:
        raise ValueError("McNemar's test of no pairs: nothing to compare")
    both = sum(bool(a) and bool(b) for a, b in zip(first, second, strict=True))
    n10 = sum(bool(a) and not b for a, b in zip(first, second, strict=True))
    n01 = sum(not a and bool(b) for a, b in zip(first, second, strict=True))
    discordant = n10 + n01
    p_value = float(binomtest(n10, discordant, 0.5).pvalue) if discordant else 1.0
    shares = np.array([both, n10, n01, n - both - discordant], dtype=float) / n
    counts = np.random.default_rng(seed).multinomial(n, shares, size=draws)
    diffs = (counts[:, 1] - counts[:, 2]) / n
    lo, hi = np.percentile(diffs, [2.5, 97.5])
    return Paired(n, both, n10, n01, min(1.0, p_value), (n10 - n01) / n, float(lo), float(hi))


def holm(p_values: Sequence[float]) -> list[float]:
    """Holm's step-down adjusted p-values, in the order given (each at most 1)."""
    order = sorted(range(len(p_values)), key=lambda i: p_values[i])
    adjusted, running = [0.0] * len(p_values), 0.0
    for step, i in enumerate(order):
        running = max(running, min(1.0, (len(p_values) - step) * p_values[i]))
        adjusted[i] = running
    return adjusted
