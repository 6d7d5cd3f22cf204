from __future__ import annotations

import numpy as np
import pytest

from hri_teleop.core.traces import Pairing, TraceError, pair_outputs, percentile_ms, rate_hz


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


# -- the edges (make mutants) ----------------------------------------------------------------------------------------

def test_two_messages_give_a_rate_from_their_time_stamps_not_from_zero_or_their_values():
    assert rate_hz([(10.0, 5.0), (10.5, 7.0)]) == 2.0
    assert rate_hz([(10.0, 5.0), (10.25, 7.0), (10.5, 9.0)]) == 4.0


def test_one_message_has_no_rate():
    with pytest.raises(TraceError) as info:
        rate_hz([(10.0, 5.0)])
    assert str(info.value) == "need at least 2 messages to measure a rate, got 1"


@pytest.mark.parametrize("trace", [[(3.0, 1.0), (3.0, 2.0)], [(3.0, 1.0), (2.5, 2.0)]])
def test_messages_with_one_timestamp_or_going_back_have_no_rate(trace):
    with pytest.raises(TraceError) as info:
        rate_hz(trace)
    assert str(info.value) == "all messages share one timestamp; cannot measure a rate"


def test_one_duration_is_its_own_percentile_and_none_is_refused():
    assert percentile_ms(np.array([0.004]), 50) == 4.0
    with pytest.raises(TraceError) as info:
        percentile_ms(np.array([]), 50)
    assert str(info.value) == "no durations to summarise"


def test_single_precision_durations_are_summarised_in_double_precision():
    values = np.array([0.001, 0.0035], dtype=np.float32)
    assert percentile_ms(values, 100) == float(np.float32(0.0035)) * 1e3  # 3.5000000...; not rounded to float32's 3.5
    assert percentile_ms(values, 100) != 3.5


def _identity(v: float) -> float:
    return v


@pytest.mark.parametrize("value, paired", [(1.74, False), (1.75, True), (2.25, True), (2.26, False)])
def test_an_output_pairs_with_its_input_up_to_the_tolerance_either_way(value, paired):
    inputs = [(1.0, 1.0), (2.0, 2.0), (3.0, 3.0)]
    outputs = [(1.1, 1.0), (2.1, value), (3.1, 3.0)]
    pairing = pair_outputs(inputs, outputs, expected=_identity, tolerance=0.25)
    assert len(pairing.pairs) == (3 if paired else 2)
    assert pairing.unmatched_outputs == (0 if paired else 1)
    assert pairing.dropped_inputs == (0 if paired else 1)


@pytest.mark.parametrize("value, unjudged", [(2.24, 1), (2.25, 1), (2.26, 0)])
def test_a_second_output_up_to_the_tolerance_from_the_same_input_is_unjudged(value, unjudged):
    inputs = [(1.0, 1.0), (2.0, 2.0), (3.0, 3.0)]
    outputs = [(1.1, 1.0), (2.1, 2.0), (2.2, value), (3.1, 3.0)]
    pairing = pair_outputs(inputs, outputs, expected=_identity, tolerance=0.25)
    assert (pairing.unjudged_outputs, pairing.unmatched_outputs) == (unjudged, 1 - unjudged)
    assert len(pairing.pairs) == 3 and pairing.dropped_inputs == 0


@pytest.mark.parametrize("wrong, unjudged", [
    (2.0, False),  # the mapping of the input three before the gap: wrong
    (3.0, True),   # two before it (the last matched input but one): a lost input may explain it
    (4.0, True),
    (7.0, True),   # the mapping of the input just after the first matched one after the gap
    (8.0, False),  # two after it: wrong
])
def test_an_unpaired_output_is_unjudged_only_if_an_input_next_to_the_gap_maps_to_it(wrong, unjudged):
    inputs = [(float(k), float(k)) for k in range(1, 9)]  # 1 .. 8
    outputs = [(k + 0.001, v) for k, v in inputs]
    outputs[4] = (5.001, wrong)  # instead of 5
    pairing = pair_outputs(inputs, outputs, expected=_identity)
    assert len(pairing.pairs) == 7 and pairing.dropped_inputs == 1
    assert (pairing.unjudged_outputs, pairing.unmatched_outputs) == ((1, 0) if unjudged else (0, 1))
    assert pairing.outside_outputs == 0


def test_a_repeated_first_output_is_unjudged_like_any_duplicate():
    inputs = [(1.0, 1.0), (2.0, 2.0), (3.0, 3.0), (4.0, 4.0)]
    outputs = [(1.1, 1.0), (1.2, 1.0), (3.1, 3.0), (4.1, 4.0)]  # input 2 lost, output 1 published twice
    pairing = pair_outputs(inputs, outputs, expected=_identity)
    assert (pairing.unjudged_outputs, pairing.unmatched_outputs, pairing.outside_outputs) == (1, 0, 0)
    assert len(pairing.pairs) == 3 and pairing.dropped_inputs == 1


def test_every_unpaired_output_inside_the_span_is_counted():
    inputs = [(float(k), float(k)) for k in range(1, 9)]
    outputs = [(1.1, 1.0), (2.1, 2.0), (2.2, 2.0), (3.1, 3.0), (3.2, 30.0), (4.1, 4.0), (4.2, 4.0),
               (5.1, 5.0), (5.2, 50.0), (6.1, 6.0), (7.1, 7.0), (8.1, 8.0)]
    pairing = pair_outputs(inputs, outputs, expected=_identity)
    assert (pairing.unjudged_outputs, pairing.unmatched_outputs, pairing.outside_outputs) == (2, 2, 0)
    assert len(pairing.pairs) == 8 and pairing.dropped_inputs == 0


def test_a_long_recording_of_two_plateaus_with_a_lost_message_pairs_every_other_message():
    """300 messages of two values: difflib's 'popular element' heuristic (autojunk) would pair only 149."""
    inputs = [(0.01 * k, 0.0 if k < 150 else 1.0) for k in range(300)]
    outputs = [(t + 0.001, v) for t, v in inputs]
    del outputs[100]  # the recorder lost one output at rest
    pairing = pair_outputs(inputs, outputs, expected=_identity)
    assert len(pairing.pairs) == 299
    assert (pairing.unmatched_outputs, pairing.unjudged_outputs) == (0, 0)  # on a plateau, which one was lost is moot


def test_pairs_are_listed_in_the_order_their_outputs_arrived():
    inputs = [(2.0, 1.0), (1.0, 2.0)]  # stamped out of order
    outputs = [(2.1, 1.0), (2.2, 2.0)]
    pairing = pair_outputs(inputs, outputs, expected=_identity)
    assert pairing.pairs == [(2.0, 1.0, 2.1, 1.0), (1.0, 2.0, 2.2, 2.0)]


def test_with_no_output_matched_nothing_is_called_wrong_or_dropped():
    pairing = pair_outputs([(1.0, 1.0), (2.0, 2.0)], [(1.001, 0.5), (1.002, 0.6)], expected=lambda v: v / 10.0)
    assert pairing == Pairing(pairs=[], unmatched_outputs=0, dropped_inputs=0, unjudged_outputs=2, outside_outputs=2)
