"""count -> [0, 1] mapping and the validation of /max_sensor_force."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from hri_teleop.core.mapping import ADC_MAX_COUNT, MappingError, map_force, validate_max_sensor_force

SETTINGS = settings(max_examples=200, deadline=None)
valid_max = st.one_of(
    st.integers(min_value=1, max_value=ADC_MAX_COUNT),
    st.floats(min_value=1e-6, max_value=ADC_MAX_COUNT, allow_nan=False),
)


def test_adc_max_count():
    assert ADC_MAX_COUNT == 1023


@pytest.mark.parametrize(
    "count, expected",
    [(0, 0.0), (350, 0.5), (700, 1.0), (1023, 1.0), (-5, 0.0), (70, 0.1), (1, 1 / 700), (-1, 0.0), (699, 699 / 700),
     (701, 1.0)],
)
def test_map_force_values(count, expected):
    result = map_force(count, 700)
    assert isinstance(result, float)
    assert result == pytest.approx(expected)


def test_map_force_arrays():
    result = map_force(np.array([0, 350, 700, 900, -1]), 700.0)
    assert isinstance(result, np.ndarray)
    assert result.tolist() == pytest.approx([0.0, 0.5, 1.0, 1.0, 0.0])
    assert map_force([0, 700], 700).tolist() == [0.0, 1.0]


def test_a_series_with_missing_readings_maps_them_to_no_force_and_the_rest_as_floats():
    """A trace with gaps (None where the board sent nothing) maps like NaN: no usable reading, no feedback."""
    result = map_force(np.array([350, None, 700, 1], dtype=object), 700)
    assert result.dtype == np.float64
    assert result.tolist() == [0.5, 0.0, 1.0, 1 / 700]


def test_nan_count_maps_to_no_force():
    assert map_force(float("nan"), 700) == 0.0
    assert map_force(float("inf"), 700) == 1.0


@SETTINGS
@given(count=st.integers(), maximum=valid_max)
@example(count=0, maximum=700)
@example(count=-1, maximum=700)
@example(count=699, maximum=700)
@example(count=700, maximum=700)
@example(count=701, maximum=700)
@example(count=1023, maximum=1023)
@example(count=1024, maximum=1)
@example(count=700, maximum=699.5)
@example(count=10 ** 400, maximum=700)
@example(count=-(10 ** 400), maximum=700)
def test_any_int_count_maps_into_unit_interval(count, maximum):
    result = map_force(count, maximum)
    assert isinstance(result, float)
    assert 0.0 <= result <= 1.0


@SETTINGS
@given(a=st.integers(-2000, 3000), b=st.integers(-2000, 3000), maximum=valid_max)
@example(a=-1, b=0, maximum=700)
@example(a=0, b=1, maximum=700)
@example(a=699, b=700, maximum=700)
@example(a=700, b=701, maximum=700)
@example(a=1, b=2, maximum=1)
@example(a=699, b=700, maximum=699.5)
def test_map_force_is_monotonic(a, b, maximum):
    if a <= b:
        assert map_force(a, maximum) <= map_force(b, maximum)


def test_huge_python_ints_do_not_overflow():
    assert map_force(10 ** 400, 700) == 1.0
    assert map_force(-(10 ** 400), 700) == 0.0


@pytest.mark.parametrize("value", [700, 700.0, 1, 1023, 0.5, np.int16(700), np.float32(650.0)])
def test_valid_max_sensor_force(value):
    result = validate_max_sensor_force(value)
    assert isinstance(result, float) and result == pytest.approx(float(value))


@pytest.mark.parametrize(
    "value",
    [None, 0, 0.0, -1, -700.0, 1024, 1023.5, float("nan"), float("inf"), True, False, "700", "abc", [700], {}, np.bool_(True)],
)
def test_invalid_max_sensor_force_names_the_parameter_and_the_fix(value):
    with pytest.raises(MappingError) as info:
        validate_max_sensor_force(value)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith("/max_sensor_force")
    assert "rosparam set /max_sensor_force" in message


def test_error_uses_the_given_name():
    with pytest.raises(MappingError, match=r"^/lab/max_force .*rosparam set /lab/max_force 700"):
        validate_max_sensor_force("x", name="/lab/max_force")


def test_map_force_validates_its_maximum():
    with pytest.raises(MappingError):
        map_force(100, 0)
    with pytest.raises(MappingError):
        map_force(100, "700")
    assert issubclass(MappingError, ValueError)
    assert math.isclose(map_force(100, 1023), 100 / 1023)
