"""MaxRecorder: the calibration's running maximum, bounded in time and memory."""

from __future__ import annotations

import pytest

from hri_teleop.course.widgets._base import WidgetError
from hri_teleop.course.widgets.calibration import MaxRecorder
from hri_teleop.hardware.real.calibrate import CalibrateError


def test_the_largest_count_within_the_duration_is_the_result():
    recorder = MaxRecorder()
    recorder.start(100.0, duration_s=2.0)
    for t, count in [(100.5, 300), (101.0, 688), (101.5, 640)]:
        assert recorder.feed(count, t)
    assert not recorder.feed(1000, 102.5), "a count after the duration was recorded"
    assert not recorder.recording(102.5)
    assert recorder.result() == 688 and recorder.samples == 3


def test_until_stopped_records_everything_then_nothing():
    recorder = MaxRecorder()
    recorder.start(0.0)
    assert recorder.feed(500, 1e6)
    recorder.stop()
    assert not recorder.feed(900, 1e6 + 1)
    assert recorder.result() == 500


def test_out_of_range_counts_are_counted_and_ignored():
    recorder = MaxRecorder()
    recorder.start(0.0)
    for count in (-1, 2000, 3.5, True, 420):
        recorder.feed(count, 0.1)
    assert recorder.rejected == 4 and recorder.result() == 420


def test_nothing_recorded_or_only_zeros_is_refused_with_the_fix():
    recorder = MaxRecorder()
    recorder.start(0.0, 1.0)
    with pytest.raises(CalibrateError, match="no samples"):
        recorder.result()
    recorder.feed(0, 0.5)
    with pytest.raises(CalibrateError, match="press the piston"):
        recorder.result()


def test_starting_again_forgets_the_last_recording():
    recorder = MaxRecorder()
    recorder.start(0.0)
    recorder.feed(700, 0.1)
    recorder.start(1.0, 5.0)
    recorder.feed(300, 1.1)
    assert recorder.result() == 300


def test_elapsed_stops_at_the_duration():
    recorder = MaxRecorder()
    recorder.start(10.0, 2.0)
    assert recorder.elapsed_s(11.0) == 1.0 and recorder.elapsed_s(20.0) == 2.0


@pytest.mark.parametrize("duration", [0.0, -1.0, float("inf")])
def test_a_duration_must_be_positive(duration):
    with pytest.raises(WidgetError, match="duration_s"):
        MaxRecorder().start(0.0, duration)
