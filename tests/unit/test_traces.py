from __future__ import annotations

import numpy as np
import pytest

from hri_teleop.core.traces import TraceError, pair_outputs, percentile_ms, rate_hz


def test_rate_of_a_10_hz_trace_is_10_hz():
    trace = [(0.1 * k, 0.0) for k in range(11)]
    assert rate_hz(trace) == pytest.approx(10.0)


def test_rate_needs_two_messages():
    with pytest.raises(TraceError, match="at least 2"):
        rate_hz([(0.0, 1.0)])


def test_pairing_matches_outputs_in_order_and_measures_latency():
    inputs = [(1.0, 10.0), (2.0, 20.0), (3.0, 10.0)]
    outputs = [(1.004, 1.0), (2.002, 2.0), (3.001, 1.0)]
    pairing = pair_outputs(inputs, outputs, expected=lambda v: v / 10.0)
    assert [p[0] for p in pairing.pairs] == [1.0, 2.0, 3.0]
    assert pairing.unmatched_outputs == 0 and pairing.dropped_inputs == 0
    np.testing.assert_allclose(pairing.latencies_s, [0.004, 0.002, 0.001], atol=1e-9)


def test_pairing_counts_wrong_values_and_inputs_before_subscription():
    inputs = [(0.5, 5.0), (1.0, 10.0), (2.0, 20.0), (3.0, 30.0)]
    outputs = [(1.01, 1.0), (2.01, 0.3), (3.01, 3.0)]
    pairing = pair_outputs(inputs, outputs, expected=lambda v: v / 10.0)
    assert pairing.unmatched_outputs == 1  # 0.3 matches nothing
    assert pairing.dropped_inputs == 1  # 2.0 s was answered wrongly; 0.5 s came before the span


def test_percentile_in_milliseconds():
    assert percentile_ms(np.array([0.001, 0.002, 0.003]), 50) == pytest.approx(2.0)


def test_pairing_accepts_an_output_recorded_just_before_its_input():
    pairing = pair_outputs([(1.0002, 7.0)], [(1.0001, 0.7)], expected=lambda v: v / 10.0)
    assert len(pairing.pairs) == 1 and pairing.unmatched_outputs == 0


def test_an_output_before_the_first_recorded_input_is_unjudged_not_wrong():
    inputs = [(1.0, 10.0), (2.0, 20.0)]
    outputs = [(0.99, 0.5), (1.001, 1.0), (2.001, 2.0), (2.5, 0.9)]
    pairing = pair_outputs(inputs, outputs, expected=lambda v: v / 10.0)
    assert pairing.unjudged_outputs == 2  # 0.5 and 0.9 have no recorded input to judge them by
    assert pairing.outside_outputs == 2  # both at the edges
    assert len(pairing.pairs) == 2


def test_a_duplicated_output_is_unjudged_like_a_lost_input():
    inputs = [(1.0, 10.0), (2.0, 20.0), (3.0, 30.0)]
    outputs = [(1.001, 1.0), (2.001, 2.0), (2.002, 2.0), (3.001, 3.0)]  # published twice for 20
    pairing = pair_outputs(inputs, outputs, expected=lambda v: v / 10.0)
    assert len(pairing.pairs) == 3  # the extra one is indistinguishable from a lost input
    assert pairing.unjudged_outputs == 1 and pairing.unmatched_outputs == 0
    assert pairing.outside_outputs == 0  # inside the matched span: a test can bound these


def test_a_message_lost_in_the_middle_does_not_shift_the_rest():
    inputs = [(float(k), float(v)) for k, v in enumerate([0, 0, 5, 9, 9, 9, 4, 0, 0, 7, 7])]
    outputs = [(k + 0.001, v / 10.0) for k, v in inputs]
    del outputs[4]  # the recorder lost one /force_mapped message on a plateau
    del inputs[8]   # ... and one /pub_force message elsewhere
    pairing = pair_outputs(inputs, outputs, expected=lambda v: v / 10.0)
    assert pairing.unmatched_outputs == 0
    assert len(pairing.pairs) >= len(outputs) - 1


def test_a_wrong_value_in_the_middle_is_caught():
    inputs = [(float(k), float(v)) for k, v in enumerate([1, 2, 3, 4, 5])]
    outputs = [(k + 0.001, v / 10.0) for k, v in inputs]
    outputs[2] = (2.001, 0.3 // 1)  # integer division: 0.0
    pairing = pair_outputs(inputs, outputs, expected=lambda v: v / 10.0)
    assert pairing.unmatched_outputs == 1


def test_outputs_whose_inputs_came_before_the_recording_are_outside_however_many():
    """A slow node at the start of a recording: its first outputs answer inputs nobody recorded."""
    inputs = [(1.0 + 0.02 * k, float(k)) for k in range(10)]
    late = [(1.0 + 0.02 * k + 0.001, (k - 4) / 10.0) for k in range(14)]  # 4 outputs of unrecorded inputs -4..-1
    pairing = pair_outputs(inputs, late, expected=lambda v: v / 10.0)
    assert len(pairing.pairs) == 10 and pairing.unmatched_outputs == 0
    assert pairing.unjudged_outputs == 4 and pairing.outside_outputs == 4


def test_no_output_matched_means_every_output_is_outside():
    pairing = pair_outputs([(1.0, 1.0)], [(1.001, 0.5), (1.002, 0.6)], expected=lambda v: v / 10.0)
    assert pairing.pairs == [] and pairing.outside_outputs == 2 and pairing.unjudged_outputs == 2
