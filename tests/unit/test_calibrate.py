"""Ex. 11's calibration rule without ROS (hri_teleop.hardware.real.calibrate.calibration_max)."""

from __future__ import annotations

import pytest

from hri_teleop.hardware.real.calibrate import CalibrateError, calibration_max


def test_the_calibration_value_is_the_largest_count_seen():
    assert calibration_max([0, 3, 512, 700, 699, 12]) == 700
    assert calibration_max(iter([1])) == 1


def test_no_samples_is_refused_with_the_fix():
    with pytest.raises(CalibrateError, match="read the board for longer"):
        calibration_max([])


def test_a_piston_never_pressed_is_refused_because_max_sensor_force_must_be_positive():
    with pytest.raises(CalibrateError, match="press the piston"):
        calibration_max([0, 0, 0])


@pytest.mark.parametrize("bad", [1024, -1, 3.5, True, "700"])
def test_values_that_are_no_adc_count_are_refused(bad):
    with pytest.raises(CalibrateError, match="0..1023"):
        calibration_max([5, bad])
