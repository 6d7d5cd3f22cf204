"""The timing arithmetic of make bench: rumble matching, percentiles, periods, tick schedule."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from benchmarks.report import BenchError, BenchRow, format_row
from benchmarks.stats import ForceStep, match_rumbles, period_stats, summarise_ms
from hri_teleop.core.gamepad import GamepadError
from hri_teleop.core.teleop import next_tick_s
from hri_teleop.sim.virtual_pad import RumbleRecord, read_rumble_log, rumble_log_line


def test_each_step_is_answered_by_the_first_agreeing_rumble():
    steps = [ForceStep(1.0, True), ForceStep(2.0, False), ForceStep(3.0, True)]
    rumbles = [(0.5, 0.0), (1.004, 0.7), (1.25, 0.7), (2.011, 0.0), (3.002, 0.7)]
    got = match_rumbles(steps, rumbles)
    assert got == pytest.approx([0.004, 0.011, 0.002])


def test_a_refresh_of_the_old_level_does_not_answer_a_step():
    # force off at 2.0, but only a refresh of the "on" level comes before the next step
    steps = [ForceStep(1.0, True), ForceStep(2.0, False), ForceStep(3.0, True)]
    rumbles = [(1.01, 0.7), (2.1, 0.7), (3.01, 0.7)]
    first, second, third = match_rumbles(steps, rumbles)
    assert second is None
    assert (first, third) == (pytest.approx(0.01), pytest.approx(0.01))


def test_an_answer_after_the_next_step_counts_as_missed():
    steps = [ForceStep(1.0, True), ForceStep(2.0, False)]
    assert match_rumbles(steps, [(2.5, 0.7), (2.6, 0.0)]) == [None, pytest.approx(0.6)]


@given(st.lists(st.floats(0.001, 0.05), min_size=1, max_size=40))
def test_matching_recovers_known_delays(delays):
    steps = [ForceStep(k * 0.1, k % 2 == 0) for k in range(len(delays))]
    rumbles = [(s.time_s + d, 0.5 if s.on else 0.0) for s, d in zip(steps, delays)]
    assert match_rumbles(steps, rumbles) == pytest.approx(delays)


def test_summary_is_in_milliseconds_and_refuses_nothing():
    s = summarise_ms([0.001] * 99 + [0.010])
    assert (s.n, s.p50_ms, s.max_ms) == (100, pytest.approx(1.0), pytest.approx(10.0))
    with pytest.raises(BenchError, match="no rumble"):
        summarise_ms([], "rumble latencies")


def test_period_stats_count_deviation_and_missed_periods():
    arrivals = [0.0, 0.02, 0.04, 0.061, 0.081, 0.141, 0.161]  # one gap of 3 periods: 2 missed
    s = period_stats(arrivals, 0.02)
    assert s.missed == 2
    assert s.max_dev_ms == pytest.approx(40.0)
    assert s.p50_period_ms == pytest.approx(20.0)
    with pytest.raises(BenchError, match="too few"):
        period_stats([0.0, 0.02], 0.02)


@given(st.floats(0, 1e4), st.floats(-1.0, 1.0), st.floats(0.001, 0.1))
def test_next_tick_never_schedules_a_catch_up_burst(previous, offset, period):
    now = previous + period + offset
    due = next_tick_s(previous, now, period)
    assert due >= now - period - 1e-9  # never more than one period in the past
    if now < previous + 2 * period - 1e-6:
        assert due == pytest.approx(previous + period)  # on schedule: exactly one period later


def test_rumble_log_round_trips_and_names_a_bad_line(tmp_path):
    records = [RumbleRecord(12.5, 0.7, 0.5), RumbleRecord(12.75, 0.0, 0.0)]
    path = tmp_path / "rumble.log"
    path.write_text("# header\n" + "\n".join(rumble_log_line(r) for r in records) + "\n")
    assert read_rumble_log(path) == records
    path.write_text("12.5 0.7\n")
    with pytest.raises(GamepadError, match=r"rumble.log:1"):
        read_rumble_log(path)


def test_a_row_shows_figure_reference_and_ratio():
    line = format_row(BenchRow("x", "p50 2 ms", "hop p50 0.5 ms", 4.0, "p50 / hop"))
    assert line == "| x | p50 2 ms | hop p50 0.5 ms | 4× (p50 / hop) | not recorded |"
    assert "n/a" in format_row(BenchRow("x", "a", "b", math.inf, "c"))


def test_a_bar_in_a_cell_does_not_split_the_row():
    line = format_row(BenchRow("a|b", "f", "r", 1.0, "m"))
    assert line == "| a\\|b | f | r | 1× (m) | not recorded |"
