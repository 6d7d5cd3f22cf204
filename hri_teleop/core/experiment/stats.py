"""The paired comparison for a small study: exact Wilcoxon signed-rank test and its effect size.

Each participant grasps under both conditions, and a lab group is too small for a normal
approximation, so the p-value is exact (up to 25 pairs) and every result states its assumptions
(:attr:`PairedComparison.assumptions`). The test and the rank-biserial effect size: docs/experiment.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Sequence, Tuple

from hri_teleop.core.errors import HriTeleopError

__all__ = ["StatsError", "PairedComparison", "signed_ranks", "wilcoxon_exact", "paired_comparison", "MAX_EXACT_PAIRS"]

#: Up to this many nonzero pairs the p-value is exact (the DP is tiny; beyond, a lab
#: study is not "small" and a normal approximation would be the usual choice).
MAX_EXACT_PAIRS = 25

ASSUMPTIONS = ("pairs independent of each other (one pair per participant); differences at least ordinal; "
               "differences symmetric about their median; zero differences dropped, ties get mean ranks")


class StatsError(HriTeleopError, ValueError):
    """The data cannot be compared this way (the message says why and what to do)."""


@dataclass(frozen=True)
class PairedComparison:
    """Result of :func:`paired_comparison` (``a`` minus ``b``)."""

    n_pairs: int
    n_nonzero: int
    median_difference: float
    w_plus: float
    w_minus: float
    p_value: float
    rank_biserial: float
    test: str = "Wilcoxon signed-rank, exact, two-sided"
    assumptions: str = ASSUMPTIONS

    def describe(self, what: str = "a - b") -> str:
        """One sentence for a report."""
        return (f"{what}: median difference {self.median_difference:.3g} over {self.n_pairs} pairs; "
                f"{self.test}: W+ = {self.w_plus:g}, W- = {self.w_minus:g}, p = {self.p_value:.3f} "
                f"(n = {self.n_nonzero} nonzero); rank-biserial r = {self.rank_biserial:+.2f}")


def signed_ranks(differences: Sequence[float]) -> List[Tuple[float, float]]:
    """(difference, rank of its absolute value) for the nonzero differences; ties share the mean rank."""
    nonzero = [float(d) for d in differences if float(d) != 0.0]
    order = sorted(range(len(nonzero)), key=lambda i: abs(nonzero[i]))
    ranks = [0.0] * len(nonzero)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and abs(nonzero[order[j + 1]]) == abs(nonzero[order[i]]):
            j += 1
        mean_rank = (i + 1 + j + 1) / 2.0
        for k in range(i, j + 1):
            ranks[order[k]] = mean_rank
        i = j + 1
    return list(zip(nonzero, ranks))


def wilcoxon_exact(ranks: Sequence[float], w_plus: float) -> float:
    """Two-sided exact p-value of observing ``w_plus`` given the ranks (mean ranks allowed).

    Under the null each rank is added to W+ with probability 1/2, independently. Ranks
    are doubled to integers (mean ranks are multiples of 1/2) and the number of sign
    assignments per sum is counted by dynamic programming.
    """
    doubled = [int(round(2 * r)) for r in ranks]
    total = sum(doubled)
    counts: Dict[int, int] = {0: 1}
    for r in doubled:
        nxt: Dict[int, int] = dict(counts)
        for s, c in counts.items():
            nxt[s + r] = nxt.get(s + r, 0) + c
        counts = nxt
    n_assign = 2 ** len(doubled)
    w = int(round(2 * w_plus))
    low = sum(c for s, c in counts.items() if s <= w) / n_assign
    high = sum(c for s, c in counts.items() if s >= w) / n_assign
    # symmetric null distribution (about total/2): two-sided = twice the smaller tail
    return min(1.0, 2.0 * min(low, high)) if total else 1.0


def paired_comparison(a: Sequence[float], b: Sequence[float]) -> PairedComparison:
    """Compare paired measurements ``a[i]`` and ``b[i]`` (e.g. peak force without and with feedback)."""
    if len(a) != len(b):
        raise StatsError(f"paired data need as many values in each condition, got {len(a)} and {len(b)}; "
                         "keep one value per participant and condition (e.g. their mean over trials)")
    values = [(float(x), float(y)) for x, y in zip(a, b)]
    if any(not (math.isfinite(x) and math.isfinite(y)) for x, y in values):
        raise StatsError("paired data contain NaN or inf; drop the participant whose trial is missing")
    differences = [x - y for x, y in values]
    if len(differences) < 2:
        raise StatsError(f"{len(differences)} pair(s) cannot be compared; a paired test needs at least 2 participants")
    ranked = signed_ranks(differences)
    if len(ranked) > MAX_EXACT_PAIRS:
        raise StatsError(f"{len(ranked)} nonzero pairs: more than the exact test's {MAX_EXACT_PAIRS}; "
                         "use a normal approximation (scipy.stats.wilcoxon) for a study this large")
    w_plus = sum(r for d, r in ranked if d > 0)
    w_minus = sum(r for d, r in ranked if d < 0)
    p = wilcoxon_exact([r for _, r in ranked], w_plus) if ranked else 1.0
    total = w_plus + w_minus
    ordered = sorted(differences)
    mid = len(ordered) // 2
    median = ordered[mid] if len(ordered) % 2 else 0.5 * (ordered[mid - 1] + ordered[mid])
    return PairedComparison(
        n_pairs=len(differences), n_nonzero=len(ranked), median_difference=median,
        w_plus=w_plus, w_minus=w_minus, p_value=p,
        rank_biserial=(w_plus - w_minus) / total if total else 0.0,
    )
