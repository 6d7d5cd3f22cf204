"""The handout's dead-zone filter, made continuous: 0 inside, a ramp from 0 outside, +-1 at +-1."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hri_teleop.core.gamepad import GamepadError, normalize_analog_input

deadzones = st.floats(min_value=0.0, max_value=0.95)
values = st.floats(min_value=-1.0, max_value=1.0)


@pytest.mark.parametrize("value, deadzone, expected", [
    (0.0, 0.1, 0.0),
    (0.05, 0.1, 0.0),
    (-0.1, 0.1, 0.0),      # the edge itself is still inside
    (0.55, 0.1, 0.5),
    (-0.55, 0.1, -0.5),
    (1.0, 0.1, 1.0),
    (-1.0, 0.1, -1.0),
    (0.3, 0.0, 0.3),       # no dead zone: identity
    (1.7, 0.1, 1.0),       # beyond full scale: clipped
    (-3.0, 0.2, -1.0),
])
def test_examples(value, deadzone, expected):
    assert normalize_analog_input(value, deadzone) == pytest.approx(expected)


@given(deadzones, st.floats(min_value=1e-9, max_value=1e-3))
def test_continuous_at_the_dead_zone_edge(dz, eps):
    """Just outside the dead zone the output is tiny: no jump the robot would see as a step."""
    out = normalize_analog_input(dz + eps, dz)
    assert 0.0 <= out <= eps / (1.0 - dz) * (1 + 1e-9) + 1e-15
    assert normalize_analog_input(-(dz + eps), dz) == -out


@given(deadzones, values, values)
def test_monotone(dz, a, b):
    lo, hi = min(a, b), max(a, b)
    assert normalize_analog_input(lo, dz) <= normalize_analog_input(hi, dz)


@given(deadzones, st.floats(allow_nan=False))
def test_range_and_odd_symmetry(dz, v):
    out = normalize_analog_input(v, dz)
    assert -1.0 <= out <= 1.0
    assert normalize_analog_input(-v, dz) == -out
    if abs(v) <= dz:
        assert out == 0.0


@given(deadzones)
def test_full_deflection_is_full_scale(dz):
    assert normalize_analog_input(1.0, dz) == 1.0
    assert normalize_analog_input(-1.0, dz) == -1.0


def test_nan_input_means_no_motion():
    assert normalize_analog_input(float("nan"), 0.1) == 0.0


@pytest.mark.parametrize("deadzone", [-0.1, 1.0, 1.5, float("nan"), "0.1", None, True])
def test_bad_dead_zone_is_one_line_with_the_fix(deadzone):
    with pytest.raises(GamepadError) as info:
        normalize_analog_input(0.5, deadzone)
    message = str(info.value)
    assert "\n" not in message
    assert "[0, 1)" in message and "deadzone" in message


def test_returns_plain_float():
    out = normalize_analog_input(0.5, 0.1)
    assert type(out) is float and math.isfinite(out)


def test_a_numpy_dead_zone_is_a_number_like_any_other():
    import numpy as np

    from hri_teleop.core.gamepad.deadzone import check_deadzone

    assert check_deadzone(np.float32(0.25)) == 0.25
    assert normalize_analog_input(0.625, np.float32(0.25)) == 0.5
