"""The arithmetic of the timing benchmarks: percentiles, matching steps to rumbles, periods.

Pure functions over monotonic times in seconds, so the rules are unit-tested without a
master and the numbers in the README come from one place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np

from benchmarks.report import BenchError
from hri_teleop.core.traces import percentile_ms

__all__ = ["Summary", "summarise_ms", "ForceStep", "match_rumbles", "PeriodStats", "period_stats"]


@dataclass(frozen=True)
class Summary:
    """p50, p99 and max of a set of durations, in ms (``n`` samples)."""

    n: int
    p50_ms: float
    p99_ms: float
    max_ms: float

    def text(self) -> str:
        return f"p50 {self.p50_ms:.2f} / p99 {self.p99_ms:.2f} / max {self.max_ms:.2f} ms"


def summarise_ms(durations_s: Sequence[float], what: str = "durations") -> Summary:
    values = np.asarray(list(durations_s), dtype=float)
    if values.size == 0:
        raise BenchError(f"no {what} were measured: nothing to summarise")
    return Summary(int(values.size), percentile_ms(values, 50), percentile_ms(values, 99), percentile_ms(values, 100))


@dataclass(frozen=True)
class ForceStep:
    """The force switched on (``on``) or off at ``time_s`` (monotonic s)."""

    time_s: float
    on: bool


def match_rumbles(steps: Sequence[ForceStep], rumbles: Sequence[Tuple[float, float]]) -> List[Optional[float]]:
    """For each step, the delay (s) until the first rumble request that agrees with it, or None.

    ``rumbles``: (time_s, intensity) of every request, in time order. A step "on" is
    answered by the first request with intensity > 0 after it, a step "off" by the first
    with intensity 0. The answer must come before the next step, else the step gets None:
    a change the operator never felt.
    """
    times = [t for t, _ in rumbles]
    out: List[Optional[float]] = []
    j = 0
    for k, step in enumerate(steps):
        end = steps[k + 1].time_s if k + 1 < len(steps) else math.inf
        while j < len(times) and times[j] < step.time_s:
            j += 1
        answer: Optional[float] = None
        i = j
        while i < len(times) and times[i] < end:
            if (rumbles[i][1] > 0.0) == step.on:
                answer = times[i] - step.time_s
                break
            i += 1
        out.append(answer)
    return out


@dataclass(frozen=True)
class PeriodStats:
    """How steady a periodic stream arrived: |period - nominal| percentiles and missed periods."""

    n_periods: int
    nominal_ms: float
    p50_period_ms: float
    p50_dev_ms: float
    p99_dev_ms: float
    max_dev_ms: float
    missed: int  # nominal periods with no message (a gap of 2.6 periods misses 2)

    def text(self) -> str:
        return (f"period p50 {self.p50_period_ms:.2f} ms, deviation p50 {self.p50_dev_ms:.2f} / p99 {self.p99_dev_ms:.2f} / "
                f"max {self.max_dev_ms:.1f} ms, missed {self.missed}/{self.n_periods + self.missed}")


def period_stats(arrivals_s: Sequence[float], nominal_s: float) -> PeriodStats:
    """Statistics of the gaps between consecutive arrival times against the nominal period."""
    if not nominal_s > 0:
        raise BenchError(f"nominal period must be positive, got {nominal_s!r} s")
    t = np.asarray(list(arrivals_s), dtype=float)
    if t.size < 3:
        raise BenchError(f"only {t.size} messages arrived: too few to judge a period (is the node publishing?)")
    gaps = np.diff(t)
    dev = np.abs(gaps - nominal_s)
    missed = int(np.sum(np.maximum(0, np.floor(gaps / nominal_s + 0.5) - 1)))
    return PeriodStats(int(gaps.size), nominal_s * 1e3, percentile_ms(gaps, 50), percentile_ms(dev, 50),
                       percentile_ms(dev, 99), percentile_ms(dev, 100), missed)
