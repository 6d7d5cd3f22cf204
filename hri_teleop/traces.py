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
    unjudged_outputs: int = 0  # arrived before any input was recorded: their cause is unknown

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
                 tolerance: float = 1e-6, clock_slack_s: float = 0.1,
                 max_latency_s: float = 0.5) -> Pairing:
    """Match each output to the unused input nearest in time whose expected value it equals.

    The candidates for an output received at ``t`` are the inputs received in
    ``[t - max_latency_s, t + clock_slack_s]``: a recorder gets inputs and outputs over
    separate connections and may stamp an output a little before its input (up to about
    20 ms seen on a loaded 2-core machine). Nearest in time, not "next in order", because
    a sensor repeats values (a plateau of equal counts) and the first inputs may have been
    sent before the recording began. An output that matches no candidate is a wrong value
    (``unmatched_outputs``), unless it arrived before any input was recorded
    (``unjudged_outputs``). One output per input: an input already matched is not used
    again, so a node that repeats itself shows up. Inputs that no output matched are ``dropped_inputs``
    (counting only those recorded before the last output).
    """
    pairs: List[Tuple[float, float, float, float]] = []
    unmatched = 0
    unjudged = 0
    used = set()
    t_in = np.array([t for t, _ in inputs], dtype=float)
    first_input_t = float(t_in[0]) if len(t_in) else float("inf")
    for t_out, v_out in outputs:
        lo = int(np.searchsorted(t_in, t_out - max_latency_s, side="left"))
        hi = int(np.searchsorted(t_in, t_out + clock_slack_s, side="right"))
        best: Optional[int] = None
        for j in range(lo, hi):
            if j not in used and abs(expected(inputs[j][1]) - v_out) <= tolerance:
                if best is None or abs(t_out - t_in[j]) < abs(t_out - t_in[best]):
                    best = j
        if best is None:
            if not pairs and t_out < first_input_t + clock_slack_s:
                unjudged += 1
            else:
                unmatched += 1
            continue
        used.add(best)
        pairs.append((inputs[best][0], inputs[best][1], t_out, v_out))
    last_t_out = outputs[-1][0] if len(outputs) else float("-inf")
    considered = sum(1 for t, _ in inputs if t <= last_t_out)
    return Pairing(pairs=pairs, unmatched_outputs=unmatched,
                   dropped_inputs=max(0, considered - len(used)), unjudged_outputs=unjudged)


def percentile_ms(values_s: np.ndarray, q: float) -> float:
    """The q-th percentile of durations given in seconds, in milliseconds."""
    if len(values_s) == 0:
        raise TraceError("no durations to summarise")
    return float(np.percentile(np.asarray(values_s, dtype=float), q) * 1e3)
