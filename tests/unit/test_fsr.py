"""The FSR 402 divider model: datasheet points, round trips, monotonicity, arguments."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core import fsr
from hri_teleop.core.fsr import (
    ADC_BITS,
    FSR402,
    FSR402_POINTS,
    PULLDOWN_OHM,
    SUPPLY_V,
    FsrError,
    PowerLaw,
    count_to_force,
    count_to_voltage,
    fit_power_law,
    force_to_count,
    force_to_resistance,
    resistance_to_force,
    resistance_to_voltage,
    voltage_to_count,
    voltage_to_resistance,
)

SETTINGS = settings(max_examples=150, deadline=None)
forces = st.floats(min_value=1e-3, max_value=1e3, allow_nan=False)

# docs/lab-facts.md: "0.2 N -> 30 kOhm, 1.3 V; 1 N -> 6 kOhm, 3.1 V; 10 N -> 1 kOhm, 4.5 V; 100 N -> 250 Ohm, 4.9 V"
DESIGN_VOLTAGES = ((0.2, 1.3), (1.0, 3.1), (10.0, 4.5), (100.0, 4.9))


def test_lab_constants():
    assert (PULLDOWN_OHM, SUPPLY_V, ADC_BITS) == (10e3, 5.0, 10)
    assert FSR402_POINTS == ((0.2, 30e3), (1.0, 6e3), (10.0, 1e3), (100.0, 250.0))


def test_fit_is_a_falling_power_law_near_the_datasheet_points():
    # The datasheet curve is roughly R ~ F^-0.8 (docs/lab-facts.md).
    assert 0.7 < FSR402.exponent < 0.85
    for force_n, resistance_ohm in FSR402_POINTS:
        assert force_to_resistance(force_n) == pytest.approx(resistance_ohm, rel=0.25)


def test_fit_recovers_an_exact_power_law():
    law = PowerLaw(r_at_1n_ohm=5000.0, exponent=0.9)
    points = [(f, 5000.0 * f ** -0.9) for f in (0.1, 1.0, 7.0, 50.0)]
    fitted = fit_power_law(points)
    assert fitted.r_at_1n_ohm == pytest.approx(law.r_at_1n_ohm, rel=1e-9)
    assert fitted.exponent == pytest.approx(law.exponent, rel=1e-9)


@pytest.mark.parametrize("force_n, volts", DESIGN_VOLTAGES)
def test_design_points_give_the_design_voltages(force_n, volts):
    voltage = resistance_to_voltage(force_to_resistance(force_n))
    assert voltage == pytest.approx(volts, abs=0.2)


def test_divider_formula_at_the_datasheet_resistances():
    # Vout = 5 V * 10 kOhm / (10 kOhm + R): 6 kOhm -> 3.125 V (the handout's "1 N -> 3.1 V").
    assert resistance_to_voltage(6e3) == pytest.approx(3.125)
    assert resistance_to_voltage(30e3) == pytest.approx(1.25)
    assert resistance_to_voltage(np.inf) == 0.0
    assert resistance_to_voltage(0.0) == pytest.approx(5.0)


def test_one_newton_reads_about_3_volts_as_a_count():
    # 3.1 V of 5 V on a 10-bit ADC is about 635; the fitted part reads within 0.2 V of it.
    assert abs(int(force_to_count(1.0)) - 3.1 * 1024 / 5.0) <= 0.2 * 1024 / 5.0


def test_no_force_is_an_open_circuit_and_reads_zero():
    assert force_to_resistance(0.0) == np.inf
    assert force_to_resistance(-1.0) == np.inf
    assert voltage_to_resistance(0.0) == np.inf
    assert resistance_to_force(np.inf) == 0.0
    assert int(force_to_count(0.0)) == 0
    assert int(force_to_count(-3.0)) == 0
    assert count_to_force(0) == 0.0


def test_every_count_round_trips_through_the_force_estimate():
    counts = np.arange(0, 1024)
    estimates = count_to_force(counts)
    assert np.array_equal(force_to_count(estimates), counts)
    assert np.all(np.diff(estimates) > 0)  # strictly increasing estimate


@SETTINGS
@given(force_n=forces)
def test_force_count_force_brackets_the_true_force(force_n):
    count = int(force_to_count(force_n))
    # The estimate is the smallest force of the ADC step: never above the true force...
    assert count_to_force(count) <= force_n * (1 + 1e-12)
    # ...and the next step starts above it.
    if count < 1023:
        assert count_to_force(count + 1) > force_n


@SETTINGS
@given(force_n=forces)
def test_force_resistance_round_trip(force_n):
    assert resistance_to_force(force_to_resistance(force_n)) == pytest.approx(force_n, rel=1e-9)


@SETTINGS
@given(resistance_ohm=st.floats(min_value=1.0, max_value=1e8))
def test_resistance_voltage_round_trip(resistance_ohm):
    assert voltage_to_resistance(resistance_to_voltage(resistance_ohm)) == pytest.approx(resistance_ohm, rel=1e-6)


@SETTINGS
@given(a=forces, b=forces)
def test_model_is_monotonic(a, b):
    low, high = min(a, b), max(a, b)
    assert force_to_resistance(low) >= force_to_resistance(high)
    assert resistance_to_voltage(force_to_resistance(low)) <= resistance_to_voltage(force_to_resistance(high))
    assert force_to_count(low) <= force_to_count(high)


@SETTINGS
@given(a=st.integers(0, 1023), b=st.integers(0, 1023))
def test_count_to_force_is_monotonic(a, b):
    if a < b:
        assert count_to_force(a) < count_to_force(b)


def test_vectorised_shapes_and_scalars():
    grid = np.array([[0.0, 0.5], [5.0, 50.0]])
    counts = force_to_count(grid)
    assert isinstance(counts, np.ndarray) and counts.shape == (2, 2)
    assert np.issubdtype(counts.dtype, np.integer)
    assert counts[0, 0] == 0 and np.all(np.diff(counts.ravel()) > 0)
    assert count_to_force(counts).shape == (2, 2)
    assert np.ndim(force_to_count(1.0)) == 0
    assert np.ndim(count_to_force(500)) == 0
    assert force_to_count([0.0, 1.0]).tolist() == [0, int(force_to_count(1.0))]


def test_adc_floors_and_clips():
    assert voltage_to_count(count_to_voltage(512)) == 512
    assert count_to_voltage(512) == pytest.approx(2.5)
    assert voltage_to_count(2.5 - 1e-6) == 511
    assert voltage_to_count(5.0) == 1023
    assert voltage_to_count(7.0) == 1023
    assert voltage_to_count(-1.0) == 0
    assert voltage_to_count(float("nan")) == 0


def test_arguments_are_respected():
    force_n = np.array([0.5, 2.0, 20.0])
    base = force_to_count(force_n)
    # 12 bits: four times the resolution, the same reading.
    fine = force_to_count(force_n, adc_bits=12)
    assert np.all(fine // 4 == base) and fine.max() <= 4095
    assert int(force_to_count(1e6, adc_bits=12)) == 4095
    # A larger pull-down lifts the divider voltage, hence the count.
    assert np.all(force_to_count(force_n, pulldown_ohm=47e3) > base)
    # The ADC's reference is the supply: the divider is ratiometric, the count does not
    # depend on the supply although the voltage does.
    assert np.array_equal(force_to_count(force_n, supply_v=3.3), base)
    r = force_to_resistance(force_n)
    assert np.allclose(resistance_to_voltage(r, supply_v=3.3), resistance_to_voltage(r) * 3.3 / 5.0)
    # A different sensor law moves the curve.
    stiffer = PowerLaw(r_at_1n_ohm=FSR402.r_at_1n_ohm * 2, exponent=FSR402.exponent)
    assert np.all(force_to_count(force_n, law=stiffer) < base)
    # Every argument round-trips.
    kwargs = dict(law=stiffer, pulldown_ohm=4.7e3, supply_v=3.3, adc_bits=12)
    counts = np.arange(0, 4096, 7)
    assert np.array_equal(force_to_count(count_to_force(counts, **kwargs), **kwargs), counts)


@pytest.mark.parametrize(
    "call",
    [
        lambda: force_to_count(1.0, pulldown_ohm=0.0),
        lambda: force_to_count(1.0, supply_v=-5.0),
        lambda: force_to_count(1.0, supply_v=float("inf")),
        lambda: force_to_count(1.0, adc_bits=0),
        lambda: force_to_count(1.0, adc_bits=10.0),
        lambda: force_to_count(1.0, adc_bits=True),
        lambda: resistance_to_force(-1.0),
        lambda: resistance_to_voltage(-1.0),
        lambda: PowerLaw(-1.0, 0.8),
        lambda: PowerLaw(6e3, 0.0),
        lambda: fit_power_law([(0.0, 1e6), (1.0, 6e3)]),
        lambda: fit_power_law([(1.0, 6e3)]),
        lambda: fit_power_law([(1.0, 6e3), (1.0, 5e3)]),
    ],
)
def test_bad_arguments_raise_one_line_errors(call):
    with pytest.raises(FsrError) as info:
        call()
    assert "\n" not in str(info.value)


def test_module_has_one_error_class():
    assert issubclass(fsr.FsrError, ValueError)


# -- the edges (make mutants) ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("adc_bits, top", [(1, 1), (2, 3), (23, 2 ** 23 - 1), (24, 2 ** 24 - 1), (np.int64(12), 4095)])
def test_an_adc_of_1_to_24_bits_is_accepted_numpy_integers_too(adc_bits, top):
    assert int(voltage_to_count(5.0, adc_bits=adc_bits)) == top
    assert count_to_voltage(top, adc_bits=adc_bits) == 5.0 * top / (top + 1)


@pytest.mark.parametrize("adc_bits", [0, 25, np.int64(25), 12.0, np.float64(12.0)])
def test_an_adc_of_0_or_25_bits_or_a_float_is_refused(adc_bits):
    with pytest.raises(FsrError) as info:
        voltage_to_count(2.5, adc_bits=adc_bits)
    assert str(info.value) == (f"adc_bits must be an integer from 1 to 24, got {adc_bits!r}; "
                               "the Uno's ADC has 10 bits")


def test_numpy_numbers_of_any_kind_are_accepted_as_divider_and_law():
    law = PowerLaw(r_at_1n_ohm=np.float32(6000.0), exponent=np.float32(0.75))
    assert law == PowerLaw(6000.0, 0.75)
    assert PowerLaw(np.int64(6000), np.int32(1)) == PowerLaw(6000.0, 1.0)
    assert resistance_to_voltage(10e3, pulldown_ohm=np.int64(10000), supply_v=np.float32(5.0)) == 2.5
    assert voltage_to_resistance(2.5, pulldown_ohm=np.float32(10000.0), supply_v=np.int64(5)) == 10e3
    assert count_to_voltage(512, supply_v=np.float32(5.0)) == 2.5


@pytest.mark.parametrize("r_at_1n_ohm, ok", [(0.0, False), (-1e-9, False), (1e-9, True), (0.5, True), (1.0, True)])
def test_a_law_needs_a_resistance_at_1_n_above_0_ohm(r_at_1n_ohm, ok):
    if ok:
        assert resistance_to_force(r_at_1n_ohm, PowerLaw(r_at_1n_ohm, 0.8)) == 1.0
    else:
        with pytest.raises(FsrError, match="PowerLaw.r_at_1n_ohm must be a positive finite resistance"):
            PowerLaw(r_at_1n_ohm, 0.8)


def test_two_points_at_two_forces_are_enough_for_a_fit():
    law = fit_power_law([(1.0, 6000.0), (10.0, 600.0)])
    assert law.r_at_1n_ohm == pytest.approx(6000.0, rel=1e-12)
    assert law.exponent == pytest.approx(1.0, rel=1e-12)
    law = fit_power_law([(1.0, 6000.0), (1.0, 5000.0), (10.0, 600.0)])  # two at one force: still two forces
    assert law.exponent > 0.9


@pytest.mark.parametrize("points", [[(1.0, 6e3)], [(1.0, 6e3), (10.0, 1e3, 5.0)], [(1.0,), (10.0, 1e3)]])
def test_a_fit_needs_two_pairs_or_more(points):
    with pytest.raises(FsrError) as info:
        fit_power_law(points)
    assert str(info.value) == (f"fit_power_law needs at least two (force_n, resistance_ohm) pairs, got {points!r}; "
                               "pass more points")


def test_a_fit_of_half_precision_points_is_that_of_the_doubles_they_hold():
    points = [(np.float16(0.2), np.float16(3e4)), (np.float16(1.0), np.float16(6e3)), (np.float16(10.0), np.float16(1e3))]
    as_doubles = [(float(f), float(r)) for f, r in points]
    assert fit_power_law(points) == fit_power_law(as_doubles)


@pytest.mark.parametrize("convert, value", [
    (force_to_resistance, np.float16(2.504)),
    (resistance_to_force, np.float16(2504.0)),
    (resistance_to_voltage, np.float16(2504.0)),
    (voltage_to_resistance, np.float16(2.504)),
    (count_to_voltage, np.float16(513.0)),
    (voltage_to_count, np.float16(2.504)),  # 2.50390625 V: count 512 (computed in half precision: 513)
])
def test_a_half_precision_input_gives_the_double_precision_answer(convert, value):
    got = convert(value)
    assert got == convert(float(value))
    assert got.dtype == (np.int64 if convert is voltage_to_count else np.float64)
    got = convert(np.array([value, value]))
    assert got.dtype == (np.int64 if convert is voltage_to_count else np.float64)


def test_a_nan_force_has_a_nan_resistance():
    assert np.isnan(force_to_resistance(float("nan")))
    assert force_to_resistance(np.array([float("nan"), 1.0])).dtype == np.float64


@pytest.mark.parametrize("resistance_ohm, force_n", [(0.0, np.inf), (float("inf"), 0.0)])
def test_0_ohm_is_an_infinite_force_and_an_open_circuit_none(resistance_ohm, force_n):
    assert resistance_to_force(resistance_ohm) == force_n


def test_a_resistance_below_1_ohm_is_a_force_not_an_error():
    law = PowerLaw(0.5, 1.0)
    assert resistance_to_force(0.25, law) == 2.0
    assert resistance_to_force(np.array([0.5, 0.25]), law).tolist() == [1.0, 2.0]


def test_extreme_values_give_inf_or_0_without_a_numpy_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert force_to_resistance(1e-200, PowerLaw(6e3, 2.0)) == np.inf     # overflows
        assert resistance_to_force(0.0) == np.inf                            # divides by 0
        assert resistance_to_force(1e-300, PowerLaw(6e3, 0.1)) == np.inf    # overflows
        assert voltage_to_resistance(0.0) == np.inf                          # divides by 0
        assert count_to_force(0) == 0.0


@pytest.mark.parametrize("voltage_v, resistance_ohm", [
    (-1.0, np.inf), (-0.0, np.inf), (0.0, np.inf), (1.0, 40e3), (2.5, 10e3), (5.0, 0.0), (6.0, 0.0)])
def test_a_voltage_is_clipped_to_the_supply_before_it_is_read_as_a_resistance(voltage_v, resistance_ohm):
    assert voltage_to_resistance(voltage_v) == resistance_ohm


@pytest.mark.parametrize("count, voltage_v", [(-5, 0.0), (0, 0.0), (1023, 4.9951171875), (1024, 4.9951171875),
                                              (1025, 4.9951171875), (5000, 4.9951171875)])
def test_a_count_is_clipped_to_0_1023_before_it_is_read_as_a_voltage(count, voltage_v):
    assert count_to_voltage(count) == voltage_v


def test_an_open_circuit_reads_0_v_even_where_the_dividers_product_overflows():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert resistance_to_voltage(np.inf, pulldown_ohm=1e300, supply_v=1e300) == 0.0  # was NaN (inf / inf)
        assert resistance_to_voltage(np.inf) == 0.0


def test_0_v_reads_as_an_open_circuit_even_where_the_dividers_product_underflows():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert voltage_to_resistance(0.0, pulldown_ohm=1e-200, supply_v=1e-200) == np.inf  # 0 / 0 inside
        assert voltage_to_resistance(-1.0, pulldown_ohm=1e-200, supply_v=1e-200) == np.inf


@pytest.mark.parametrize("law", ["FSR402", None, (6000.0, 0.8)])
def test_a_law_that_is_not_a_power_law_is_refused_in_one_line_both_ways(law):
    for convert in (lambda: fsr.force_to_resistance(1.0, law), lambda: fsr.resistance_to_force(6000.0, law),
                    lambda: fsr.force_to_count(1.0, law=law), lambda: fsr.count_to_force(500, law=law)):
        with pytest.raises(fsr.FsrError, match=r"^law must be a PowerLaw\(r_at_1n_ohm, exponent\), got .*; pass e\.g\. "
                                               r"fsr\.FSR402 or fsr\.fit_power_law\(points\)$"):
            convert()
