"""Wilson intervals, McNemar's exact test and Holm's adjustment against values computed by hand
(or published: Newcombe 1998, Statistics in Medicine 17:857, Table I, method 3)."""

import pytest

from gbh_drake.experiment.stats import holm, mcnemar, wilson


@pytest.mark.parametrize("k, n, lo, hi", [
    (81, 263, 0.2553, 0.3662),  # Newcombe's examples
    (15, 148, 0.0624, 0.1605),
    (0, 10, 0.0, 0.2775),
    (1, 29, 0.0061, 0.1718),
    # by hand: z^2 = 3.8416; 0/5: centre = (3.8416/10) / (1 + 3.8416/5) = 0.21725 = half
    (0, 5, 0.0, 0.4345),
    (5, 5, 0.5655, 1.0),
    (1, 2, 0.0945, 0.9055),
])
def test_wilson_matches_published_and_hand_values(k, n, lo, hi):
    got = wilson(k, n)
    assert got == pytest.approx((lo, hi), abs=1e-4)
    assert got[0] <= k / n <= got[1]


def test_wilson_is_symmetric_and_narrows_with_more_trials():
    lo, hi = wilson(3, 10)
    assert wilson(7, 10) == pytest.approx((1 - hi, 1 - lo))
    assert wilson(30, 100)[1] - wilson(30, 100)[0] < hi - lo
    assert wilson(3, 10, z=2.576)[0] < lo  # 99 % is wider


def test_wilson_of_nothing_raises_and_says_what_was_asked():
    with pytest.raises(ValueError, match="0 successes in 0 trials"):
        wilson(0, 0)
    with pytest.raises(ValueError, match="6 successes in 5 trials"):
        wilson(6, 5)


def test_mcnemar_exact_by_hand():
    # n10 = 5, n01 = 0: p = 2 x 0.5^5 = 0.0625; the difference 5/8 in rate
    a = [True] * 5 + [True, False, False]
    b = [False] * 5 + [True, False, False]
    t = mcnemar(a, b)
    assert (t.pairs, t.both, t.n10, t.n01, t.neither) == (8, 1, 5, 0, 2)
    assert t.p_value == pytest.approx(0.0625)
    assert t.diff == pytest.approx(5 / 8)
    assert t.diff_lo <= t.diff <= t.diff_hi <= 1.0
    # n10 = 8, n01 = 2: p = 2 (1 + 10 + 45) / 1024 = 0.109375; the sign follows the order
    a, b = [True] * 8 + [False] * 2, [False] * 8 + [True] * 2
    assert mcnemar(a, b).p_value == pytest.approx(0.109375)
    swapped = mcnemar(b, a)
    assert (swapped.n10, swapped.n01) == (2, 8) and swapped.diff == pytest.approx(-0.6)
    assert swapped.p_value == pytest.approx(0.109375)


def test_mcnemar_without_discordant_pairs_and_its_misuse():
    t = mcnemar([True, False], [True, False])
    assert t.p_value == 1.0 and t.diff == 0.0 and (t.diff_lo, t.diff_hi) == (0.0, 0.0)
    assert mcnemar([True, False, True], [False, True, True]).p_value == pytest.approx(1.0)
    with pytest.raises(ValueError, match="paired"):
        mcnemar([True], [True, False])
    with pytest.raises(ValueError, match="no pairs"):
        mcnemar([], [])


def test_paired_bootstrap_is_deterministic():
    a = [i % 3 == 0 for i in range(40)]
    b = [i % 4 == 0 for i in range(40)]
    assert mcnemar(a, b) == mcnemar(a, b)


def test_holm_by_hand():
    # sorted 0.01, 0.03, 0.04: x3 = 0.03, x2 = 0.06, x1 = 0.04 -> kept monotone: 0.06
    assert holm([0.01, 0.04, 0.03]) == pytest.approx([0.03, 0.06, 0.06])
    assert holm([0.5, 0.9]) == pytest.approx([1.0, 1.0])
    assert holm([]) == []
