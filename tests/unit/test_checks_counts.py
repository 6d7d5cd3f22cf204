"""The board's count rules, in one place (hri_teleop.core.checks): a reading is a whole count 0..1023,
a calibration (/max_sensor_force as a count) 1..1023; bools and floats are neither."""

from __future__ import annotations

import numpy as np
import pytest

from hri_teleop.core.checks import ADC_MAX_COUNT, is_calibration_count, is_count


@pytest.mark.parametrize("value, reading, calibration", [
    (-1, False, False),
    (0, True, False),
    (1, True, True),
    (1023, True, True),
    (1024, False, False),
    (True, False, False),
    (700.0, False, False),
    ("700", False, False),
    (None, False, False),
])
def test_a_count_at_each_threshold(value, reading, calibration):
    assert is_count(value) is reading
    assert is_calibration_count(value) is calibration


def test_numpy_counts_only_when_asked():
    assert not is_count(np.int16(5))
    assert is_count(np.int16(5), numpy=True)
    assert not is_count(np.bool_(True), numpy=True)


def test_the_top_count_is_the_10_bit_adcs():
    assert ADC_MAX_COUNT == 2 ** 10 - 1
