"""Plain-number views of recorded topics: rates, input/output pairing, latency.

Why here and not in the demo or the tests: the demo, the integration tests, the grader
and the benchmarks all ask the same questions of a recording ("how fast did it arrive?",
"does every output match its input?"), so the answers live in one ROS-free place.
A trace is a sequence of (receive time in s, value) pairs in arrival order.
"""

from __future__ import annotations

import bisect
import difflib
from dataclasses import dataclass
from typing import Callable, List, Sequence, Tuple

import numpy as np
import numpy.typing as npt

from hri_teleop.core.errors import HriTeleopError

Trace = Sequence[Tuple[float, float]]


class TraceError(HriTeleopError, ValueError):
    """A trace is too short or malformed for the statistic asked of it."""


@dataclass(frozen=True)
class Pairing:
    """Outputs matched to the inputs that caused them (same order, one to one)."""

    pairs: List[Tuple[float, float, float, float]]  # (t_in_s, value_in, t_out_s, value_out)
    unmatched_outputs: int
    dropped_inputs: int
    unjudged_outputs: int = 0  # their cause is unknown (the edges, and a duplicate or a lost input inside)
    outside_outputs: int = 0  # of the unjudged, those before the first or after the last match (the edges)

    @property
    def latencies_s(self) -> npt.NDArray[np.float64]:
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
                 tolerance: float = 1e-6) -> Pairing:
    """Line the outputs up with the inputs that caused them, in order, like a diff.

    A node that answers every input with one output (mapping_node) keeps their order.
    Order, not receive time, decides: a recorder gets inputs and outputs over separate
    connections and may stamp an output 20 ms before its input on a loaded 2-core
    machine; and a sensor repeats values (plateaus), so value alone is ambiguous. The
    longest in-order matching (difflib) tolerates a message lost on either topic and the
    edges, where the recorder subscribed to or left the two topics at different moments.

    Unpaired outputs inside the matched span whose value is not the mapping of an input
    where they would align are ``unmatched_outputs``: wrong. Unpaired outputs before the
    first or after the last match, or equal to a neighbouring input's mapping, are
    ``unjudged_outputs``: their inputs may not have been recorded (so a duplicated output
    is not caught; a wrong value is). Of those, ``outside_outputs`` lie at the edges: how
    many depends on the latency while the recorder connected, not on the node. Inputs inside
    the matched span with no output are ``dropped_inputs``.
    """
    want = [float(expected(v)) for _, v in inputs]
    levels = sorted(set(want))
    symbols_in = [bisect.bisect_left(levels, w) for w in want]
    symbols_out: List[int] = []
    for k, (_, v) in enumerate(outputs):
        i = bisect.bisect_left(levels, float(v) - tolerance)
        ok = i < len(levels) and abs(levels[i] - float(v)) <= tolerance
        symbols_out.append(i if ok else -1 - k)  # a value no input gives: a symbol of its own
    blocks = [b for b in difflib.SequenceMatcher(None, symbols_in, symbols_out, autojunk=False)
              .get_matching_blocks() if b.size]
    pairs: List[Tuple[float, float, float, float]] = []
    paired_out = set()
    for block in blocks:
        for d in range(block.size):
            j, k = block.a + d, block.b + d
            pairs.append((inputs[j][0], inputs[j][1], outputs[k][0], outputs[k][1]))
            paired_out.add(k)
    pairs.sort(key=lambda p: p[2])
    if not blocks:
        return Pairing(pairs=[], unmatched_outputs=0, dropped_inputs=0, unjudged_outputs=len(outputs),
                       outside_outputs=len(outputs))
    first_k, last_k = blocks[0].b, blocks[-1].b + blocks[-1].size - 1
    first_j, last_j = blocks[0].a, blocks[-1].a + blocks[-1].size - 1
    unmatched = unjudged = outside = 0
    for k in range(len(outputs)):
        if k in paired_out:
            continue
        if not first_k < k < last_k:
            unjudged += 1
            outside += 1
            continue
        # Between two matched runs: an input lost by the recorder looks like this too, so an
        # output equal to the mapping of an input where it would align is not called wrong.
        before = max(b for b in blocks if b.b < k)
        after = min(b for b in blocks if b.b > k)
        lo, hi = before.a + before.size - 2, after.a + 1
        value = float(outputs[k][1])
        if any(abs(want[j] - value) <= tolerance for j in range(max(0, lo), min(len(want), hi + 1))):
            unjudged += 1
        else:
            unmatched += 1
    dropped = (last_j - first_j + 1) - len(pairs)
    return Pairing(pairs=pairs, unmatched_outputs=unmatched, dropped_inputs=max(0, dropped),
                   unjudged_outputs=unjudged, outside_outputs=outside)


def percentile_ms(values_s: npt.NDArray[np.float64], q: float) -> float:
    """The q-th percentile of durations given in seconds, in milliseconds."""
    if len(values_s) == 0:
        raise TraceError("no durations to summarise")
    return float(np.percentile(np.asarray(values_s, dtype=float), q) * 1e3)
