"""Plain-number views of recorded topics: rates, input/output pairing, latency.

Why here and not in the demo or the tests: the demo, the integration tests, the grader
and the benchmarks all ask the same questions of a recording ("how fast did it arrive?",
"does every output match its input?"), so the answers live in one ROS-free place.
A trace is a sequence of (receive time in s, value) pairs in arrival order.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, List, Optional, Sequence, Tuple

import numpy as np

Trace = Sequence[Tuple[float, float]]


class TraceError(ValueError):
    """A trace is too short or malformed for the statistic asked of it."""


@dataclass(frozen=True)
class Pairing:
    """Outputs matched to the inputs that caused them (same order, one to one)."""

    pairs: List[Tuple[float, float, float, float]]  # (t_in_s, value_in, t_out_s, value_out)
    unmatched_outputs: int
    dropped_inputs: int

    @property
    def latencies_s(self) -> np.ndarray:
        return np.array([t_out - t_in for t_in, _, t_out, _ in self.pairs], dtype=float)


def rate_hz(trace: Trace) -> float:
    """Mean arrival rate over the trace (messages per second between first and last)."""
    if len(trace) < 2:
        raise TraceError(f"need at least 2 messages to measure a rate, got {len(trace)}")
    span_s = float(trace[-1][0]) - float(trace[0][0])
    if span_s <= 0:
        raise TraceError("all messages share one timestamp; cannot measure a rate")
    return (len(trace) - 1) / span_s


def pair_outputs(inputs: Trace, outputs: Trace, expected: Callable[[float], float],
                 tolerance: float = 1e-6, clock_slack_s: float = 0.05) -> Pairing:
    """Match each output to the earliest not-yet-matched input whose expected value it equals.

    A node that maps every input to one output produces outputs in input order; inputs
    sent before the node subscribed have no output (``dropped_inputs``), and outputs that
    match no input (``unmatched_outputs``) are wrong values. A recorder receives inputs and
    outputs over separate connections, so an output may be stamped slightly before its
    input: inputs up to ``clock_slack_s`` after an output still count as its cause.
    """
    pairs: List[Tuple[float, float, float, float]] = []
    unmatched = 0
    i = 0
    for t_out, v_out in outputs:
        j = i
        found: Optional[int] = None
        while j < len(inputs) and inputs[j][0] <= t_out + clock_slack_s:
            if abs(expected(inputs[j][1]) - v_out) <= tolerance:
                found = j
                break
            j += 1
        if found is None:
            unmatched += 1
            continue
        pairs.append((inputs[found][0], inputs[found][1], t_out, v_out))
        i = found + 1
    matched_inputs = len(pairs)
    # Inputs after the last output may still be in flight when recording stopped.
    last_t_out = outputs[-1][0] if len(outputs) else float("-inf")
    considered = sum(1 for t, _ in inputs if t <= last_t_out + clock_slack_s)
    return Pairing(pairs=pairs, unmatched_outputs=unmatched,
                   dropped_inputs=max(0, considered - matched_inputs))


def percentile_ms(values_s: np.ndarray, q: float) -> float:
    """The q-th percentile of durations given in seconds, in milliseconds."""
    if len(values_s) == 0:
        raise TraceError("no durations to summarise")
    return float(np.percentile(np.asarray(values_s, dtype=float), q) * 1e3)
