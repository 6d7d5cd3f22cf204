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


def test_a_comparison_describes_itself_in_one_sentence():
    result = paired_comparison([1.23456, 5, 9], [0, 0, 0])
    assert result.describe("peak") == ("peak: median difference 5 over 3 pairs; Wilcoxon signed-rank, exact, "
                                       "two-sided: W+ = 6, W- = 0, p = 0.250 (n = 3 nonzero); rank-biserial r = +1.00")
    mixed = paired_comparison([0.0125, -2, 3.5, 0], [0, 0, 0, 0])
    assert mixed.describe() == ("a - b: median difference 0.00625 over 4 pairs; Wilcoxon signed-rank, exact, "
                                "two-sided: W+ = 4, W- = 2, p = 0.750 (n = 3 nonzero); rank-biserial r = +0.33")
    assert mixed.test == "Wilcoxon signed-rank, exact, two-sided"
    assert mixed.assumptions == ("pairs independent of each other (one pair per participant); differences at least "
                                 "ordinal; differences symmetric about their median; zero differences dropped, ties "
                                 "get mean ranks")


def test_three_equal_sizes_share_the_mean_rank_in_the_order_given():
    assert signed_ranks([1, -1, 0, 1, 3, -3, -0.0, 0.5]) == [(1.0, 3.0), (-1.0, 3.0), (1.0, 3.0), (3.0, 5.5),
                                                             (-3.0, 5.5), (0.5, 1.0)]
    assert signed_ranks([4, 3, 2, 1]) == [(4.0, 4.0), (3.0, 3.0), (2.0, 2.0), (1.0, 1.0)]
    assert signed_ranks([2, 2]) == [(2.0, 1.5), (2.0, 1.5)]
    assert signed_ranks([-7]) == [(-7.0, 1.0)] and signed_ranks([0, 0.0]) == []
    assert all(type(d) is float for d, _ in signed_ranks([1, 2]))


@pytest.mark.parametrize("ranks, w_plus, p", [
    ([1, 2, 3], 6, 0.25),  # 1 of 8 sign assignments reaches 6, doubled: 2/8
    ([1, 2, 3], 0, 0.25),
    ([1, 2, 3], 5, 0.5),   # {2, 3} and {1, 2, 3}
    ([1, 2, 3], 1, 0.5),
    ([1, 2, 3], 3, 1.0),   # the middle: each tail 5/8, twice that capped at 1
    ([1.5, 1.5], 3, 0.5),  # a tie's mean ranks: {1.5, 1.5} is 1 of 4
    ([1.5, 1.5], 1.5, 1.0),
    ([1.5, 1.5, 3], 4.5, 0.75),  # {1.5, 3} twice and {1.5, 1.5, 3}: 3 of 8
    ([1.5, 1.5, 3], 3, 1.0),
    ([1.5, 1.5, 3], 6, 0.25),
    ([], 0, 1.0),
    ([], 5, 1.0),  # no nonzero difference: nothing to test, whatever W+ is said to be
])
def test_the_exact_p_value_counts_the_sign_assignments_at_least_as_extreme(ranks, w_plus, p):
    assert wilcoxon_exact(ranks, w_plus) == p


def test_the_median_difference_is_the_middle_one_or_the_mean_of_the_middle_two_zeros_included():
    assert paired_comparison([3, 1, 2], [0, 0, 0]).median_difference == 2.0
    assert paired_comparison([4, 1, 3, 2], [0, 0, 0, 0]).median_difference == 2.5
    assert paired_comparison([0, 0, 5], [0, 0, 0]).median_difference == 0.0
    assert paired_comparison([-1, 9], [0, 0]).median_difference == 4.0
    assert paired_comparison([10, 20], [9, 25]).median_difference == -2.0


def test_pairs_without_any_difference_give_p_1_and_no_effect():
    result = paired_comparison([2, 3, 4], [2, 3, 4])
    assert (result.n_pairs, result.n_nonzero, result.w_plus, result.w_minus, result.p_value,
            result.rank_biserial, result.median_difference) == (3, 0, 0, 0, 1.0, 0.0, 0.0)


def test_the_effect_counts_ranks_won_minus_ranks_lost_over_all_ranks():
    result = paired_comparison([1, -2, 3, 0], [0, 0, 0, 0])
    assert (result.n_pairs, result.n_nonzero, result.w_plus, result.w_minus) == (4, 3, 4.0, 2.0)
    assert result.rank_biserial == pytest.approx(2 / 6) and result.p_value == 0.75
    down = paired_comparison([0, 0], [1, 2])
    assert (down.w_plus, down.w_minus, down.rank_biserial, down.p_value) == (0.0, 3.0, -1.0, 0.5)


def test_up_to_25_nonzero_pairs_are_tested_exactly_and_26_are_refused():
    twenty_five = paired_comparison(list(range(1, 26)) + [0], [0] * 26)  # one zero difference is dropped
    assert twenty_five.n_pairs == 26 and twenty_five.n_nonzero == 25 and twenty_five.p_value == 2 / 2 ** 25
    with pytest.raises(StatsError) as info:
        paired_comparison(list(range(1, 27)), [0] * 26)
    assert str(info.value) == ("26 nonzero pairs: more than the exact test's 25; use a normal approximation "
                               "(scipy.stats.wilcoxon) for a study this large")


@pytest.mark.parametrize("a, b, message", [
    ([1, 2], [1], "paired data need as many values in each condition, got 2 and 1; keep one value per participant "
                  "and condition (e.g. their mean over trials)"),
    ([1], [1, 2], "paired data need as many values in each condition, got 1 and 2; keep one value per participant "
                  "and condition (e.g. their mean over trials)"),
    ([1], [2], "1 pair(s) cannot be compared; a paired test needs at least 2 participants"),
    ([], [], "0 pair(s) cannot be compared; a paired test needs at least 2 participants"),
    ([1, float("nan")], [2, 3], "paired data contain NaN or inf; drop the participant whose trial is missing"),
    ([1, 2], [float("inf"), 3], "paired data contain NaN or inf; drop the participant whose trial is missing"),
    ([1, 2], [3, float("-inf")], "paired data contain NaN or inf; drop the participant whose trial is missing"),
])
def test_each_unusable_input_has_its_own_message(a, b, message):
    with pytest.raises(StatsError) as info:
        paired_comparison(a, b)
    assert str(info.value) == message
