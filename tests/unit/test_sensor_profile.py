"""The simulated piston press: deterministic, bounded, smooth, shaped like the FSR."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core.fsr import count_to_force, force_to_count
from hri_teleop.core.mapping import map_force
from hri_teleop.sim.sensor_profile import SensorProfileError, press_profile_count


def samples(period_s=4.0, max_count=700, n=400, **kwargs):
    return [press_profile_count(k * period_s / n, period_s, max_count, **kwargs) for k in range(n)]


def test_a_press_rises_to_max_count_then_rests_at_zero():
    counts = samples()  # one period, press over the first 60 %
    assert counts[0] == 0
    peak = counts.index(max(counts))
    assert max(counts) == 700 and peak == 120  # the middle of the press
    assert all(b >= a for a, b in zip(counts[:peak], counts[1:peak + 1]))  # rises...
    assert all(b <= a for a, b in zip(counts[peak:240], counts[peak + 1:240]))  # ...falls...
    assert all(c == 0 for c in counts[240:])  # ...and the piston rests


def test_repeats_every_period_and_is_deterministic():
    first = samples(period_s=2.0, n=200)
    again = [press_profile_count(2.0 * 3 + k * 2.0 / 200, 2.0, 700) for k in range(200)]
    assert max(abs(a - b) for a, b in zip(first, again)) <= 1  # float phase rounding at most one count
    assert samples(period_s=2.0, n=200) == first


def test_shaped_through_the_fsr_model():
    # A light touch already gives a large count (the FSR's steep start): at a tenth of
    # the press duration the raised-cosine force is only ~10 % of the peak, the count
    # is far above 10 % of max_count.
    count = press_profile_count(0.1 * 0.6 * 4.0, 4.0, 1000)
    assert count > 300
    shape = 0.5 - 0.5 * math.cos(2 * math.pi * 0.1)
    assert count == int(force_to_count(float(count_to_force(1000)) * shape))


def test_peak_maps_to_one_when_max_count_is_max_sensor_force():
    assert map_force(press_profile_count(1.2, 4.0, 700), 700) == 1.0


def test_zero_max_count_is_always_zero():
    assert set(samples(max_count=0, n=50)) == {0}


def test_press_fraction():
    counts = samples(press_fraction=1.0)
    assert counts[200] == 700 and counts[0] == 0 and counts[399] > 0


@settings(max_examples=200, deadline=None)
@given(
    t_s=st.floats(min_value=-1e6, max_value=1e6),
    period_s=st.floats(min_value=1e-3, max_value=100.0),
    max_count=st.integers(min_value=0, max_value=1023),
)
def test_count_is_an_int_within_zero_and_max_count(t_s, period_s, max_count):
    count = press_profile_count(t_s, period_s, max_count)
    assert isinstance(count, int) and 0 <= count <= max_count


@pytest.mark.parametrize(
    "args, kwargs",
    [
        ((float("nan"), 4.0, 700), {}),
        ((0.0, 0.0, 700), {}),
        ((0.0, -1.0, 700), {}),
        ((0.0, 4.0, 1024), {}),
        ((0.0, 4.0, -1), {}),
        ((0.0, 4.0, 700.0), {}),
        ((0.0, 4.0, True), {}),
        ((0.0, 4.0, 700), {"press_fraction": 0.0}),
        ((0.0, 4.0, 700), {"press_fraction": 1.5}),
    ],
)
def test_bad_arguments(args, kwargs):
    with pytest.raises(SensorProfileError) as info:
        press_profile_count(*args, **kwargs)
    assert "\n" not in str(info.value)
