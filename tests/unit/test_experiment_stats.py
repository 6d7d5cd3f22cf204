"""The exact Wilcoxon signed-rank test and the rank-biserial effect size."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core.experiment.stats import StatsError, paired_comparison, signed_ranks, wilcoxon_exact


def _brute_force_p(ranks, w_plus):
    """Enumerate every sign assignment: the definition of the exact p-value."""
    sums = [sum(r for r, s in zip(ranks, signs) if s) for signs in itertools.product((0, 1), repeat=len(ranks))]
    low = sum(1 for s in sums if s <= w_plus + 1e-9) / len(sums)
    high = sum(1 for s in sums if s >= w_plus - 1e-9) / len(sums)
    return min(1.0, 2 * min(low, high))


def test_all_pairs_in_one_direction_give_the_smallest_exact_p_and_r_of_one():
    # 6 participants all squeeze harder without feedback: p = 2 / 2^6
    result = paired_comparison([9, 8, 7, 12, 10, 11], [3, 2, 4, 5, 1, 6])
    assert result.p_value == pytest.approx(2 / 64)
    assert result.rank_biserial == 1.0 and result.w_minus == 0 and result.n_nonzero == 6


def test_one_small_negative_pair_among_eight_gives_the_exact_tail_count():
    # Ranks 1..8 with rank 4 negative: W- = 4. Subsets of {1..8} summing to <= 4 are
    # {}, {1}, {2}, {3}, {1,2}, {4}, {1,3}: 7 of 256, so the two-sided p is 2 * 7 / 256.
    result = paired_comparison([1, 2, 3, -4, 5, 6, 7, 8], [0] * 8)
    assert (result.w_plus, result.w_minus) == (32, 4)
    assert result.p_value == pytest.approx(2 * 7 / 256)
    assert result.rank_biserial == pytest.approx((32 - 4) / 36)


def test_ties_share_the_mean_rank_and_zeros_are_dropped():
    ranked = signed_ranks([0.0, 2.0, -2.0, 5.0])
    assert ranked == [(2.0, 1.5), (-2.0, 1.5), (5.0, 3.0)]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(min_value=-6, max_value=6), min_size=2, max_size=10))
def test_the_dynamic_programme_equals_enumerating_every_sign_assignment(diffs):
    ranked = signed_ranks(diffs)
    if not ranked:
        return
    ranks = [r for _, r in ranked]
    w_plus = sum(r for d, r in ranked if d > 0)
    assert wilcoxon_exact(ranks, w_plus) == pytest.approx(_brute_force_p(ranks, w_plus))


def test_swapping_the_conditions_flips_the_effect_and_keeps_p():
    a, b = [5.0, 7.1, 3.2, 9.9, 4.4], [4.0, 7.5, 1.0, 6.0, 4.3]
    ab, ba = paired_comparison(a, b), paired_comparison(b, a)
    assert ab.p_value == pytest.approx(ba.p_value) and ab.rank_biserial == pytest.approx(-ba.rank_biserial)
    assert "Wilcoxon" in ab.describe() and "symmetric" in ab.assumptions


@pytest.mark.parametrize("a, b, expected", [
    ([1, 2], [1], "as many values in each condition"),
    ([1], [2], "at least 2 participants"),
    ([1, float("nan")], [2, 3], "NaN"),
])
def test_unusable_data_is_a_one_line_error(a, b, expected):
    with pytest.raises(StatsError, match=expected):
        paired_comparison(a, b)


def test_on_one_trial_per_condition_outcomes_the_exact_test_is_the_exact_sign_test():
    """Crushed yes/no per participant: all differences are +-1 (tied), so the p-value is the
    two-sided binomial one of McNemar's exact test on the discordant pairs."""
    from math import comb

    without = [1.0] * 6 + [0.0] * 3 + [1.0]
    with_fb = [0.0] * 6 + [0.0] * 3 + [1.0]  # 6 discordant pairs, all crushed only without feedback
    result = paired_comparison(without, with_fb)
    assert result.n_nonzero == 6 and result.p_value == pytest.approx(2 * comb(6, 6) / 2 ** 6)
    mixed = paired_comparison([1.0, 1.0, 1.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, 1.0, 0.0])
    binomial = 2 * sum(comb(5, k) for k in range(0, 2)) / 2 ** 5  # 4 of 5 discordant one way
    assert mixed.p_value == pytest.approx(min(1.0, binomial)) and mixed.rank_biserial == pytest.approx(3 / 5)
