"""The board's count rules, in one place (hri_teleop.core.checks): a reading is a whole count 0..1023,
a calibration (/max_sensor_force as a count) 1..1023; bools and floats are neither."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from hri_teleop.core.checks import (
    ADC_MAX_COUNT,
    checked_float,
    is_calibration_count,
    is_count,
    is_finite_number,
    is_int,
    is_number,
    is_positive_number,
)


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


# -- the other checks (make mutants judges hri_teleop.core.checks by this file) ---------------------------------------

@pytest.mark.parametrize("value, number, finite, positive", [
    (1, True, True, True),
    (1.5, True, True, True),
    (0.5, True, True, True),
    (1e-300, True, True, True),
    (0, True, True, False),
    (0.0, True, True, False),
    (-1e-300, True, True, False),
    (-1, True, True, False),
    (float("inf"), True, False, False),
    (float("-inf"), True, False, False),
    (float("nan"), True, False, False),
    (True, False, False, False),
    (False, False, False, False),
    ("1.5", False, False, False),
    (None, False, False, False),
])
def test_a_number_is_an_int_or_a_float_never_a_bool_and_finite_and_positive_as_said(value, number, finite, positive):
    for numpy in (False, True):
        assert is_number(value, numpy=numpy) is number
        assert is_finite_number(value, numpy=numpy) is finite
        assert is_positive_number(value, numpy=numpy) is positive


@pytest.mark.parametrize("value, number, finite, positive, integer", [
    (np.float32(1.5), True, True, True, False),
    (np.float16(-2.0), True, True, False, False),
    (np.float32("nan"), True, False, False, False),
    (np.int16(5), True, True, True, True),
    (np.uint8(0), True, True, False, True),
    (np.bool_(True), False, False, False, False),
])
def test_numpy_scalars_count_only_when_asked(value, number, finite, positive, integer):
    assert (is_number(value), is_finite_number(value), is_positive_number(value), is_int(value)) == (False,) * 4
    assert is_number(value, numpy=True) is number
    assert is_finite_number(value, numpy=True) is finite
    assert bool(is_positive_number(value, numpy=True)) is positive  # a numpy bool for a numpy scalar
    assert is_int(value, numpy=True) is integer


def test_an_integer_is_an_int_never_a_bool_or_a_float():
    assert is_int(3) and is_int(0) and is_int(-2)
    assert not is_int(True) and not is_int(3.0) and not is_int("3") and not is_int(None)
    assert not is_int(np.int64(3)) and is_int(np.int64(3), numpy=True)


def test_a_calibration_count_of_numpy_type_counts_only_when_asked():
    assert not is_calibration_count(np.int16(5))
    assert is_calibration_count(np.int16(5), numpy=True)
    assert not is_calibration_count(np.int16(0), numpy=True)


def test_without_numpy_loaded_numpy_true_looks_for_no_numpy_class(monkeypatch):
    monkeypatch.delitem(sys.modules, "numpy")
    assert is_number(1.5, numpy=True) and not is_number("1.5", numpy=True)
    assert is_int(2, numpy=True) and not is_int(2.0, numpy=True)
    assert not is_number(np.float32(1.5), numpy=True)  # numpy is not loaded as far as the check knows
    assert "numpy" not in sys.modules


class _Refused(ValueError):
    pass


@pytest.mark.parametrize("value, lowest, expected", [
    (1.5, "", 1.5), (-5, "", -5.0), (0, "", 0.0), (np.float32(0.5), "", 0.5), (np.int16(3), "", 3.0),
    (1e-300, ">0", 1e-300), (0.5, ">0", 0.5), (2, ">0", 2.0),
    (0.0, ">=0", 0.0), (1e-300, ">=0", 1e-300), (0.5, ">=0", 0.5),
])
def test_checked_float_gives_the_value_as_a_float(value, lowest, expected):
    got = checked_float(value, "gain", "set it to 1.0", _Refused, lowest=lowest)
    assert got == expected and type(got) is float


@pytest.mark.parametrize("value, lowest, message", [
    (float("nan"), "", "gain must be a finite number, got nan; set it to 1.0"),
    (float("inf"), ">0", "gain must be a finite number, got inf; set it to 1.0"),
    (True, "", "gain must be a finite number, got True; set it to 1.0"),
    ("1.0", "", "gain must be a finite number, got '1.0'; set it to 1.0"),
    (None, ">=0", "gain must be a finite number, got None; set it to 1.0"),
    (0.0, ">0", "gain must be > 0, got 0.0; set it to 1.0"),
    (-1e-300, ">0", "gain must be > 0, got -1e-300; set it to 1.0"),
    (-1e-300, ">=0", "gain must be >= 0, got -1e-300; set it to 1.0"),
    (-2, ">=0", "gain must be >= 0, got -2; set it to 1.0"),
])
def test_checked_float_refuses_with_the_callers_error_naming_the_value_and_the_fix(value, lowest, message):
    with pytest.raises(_Refused) as info:
        checked_float(value, "gain", "set it to 1.0", _Refused, lowest=lowest)
    assert str(info.value) == message
