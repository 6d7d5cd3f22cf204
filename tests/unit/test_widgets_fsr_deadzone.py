"""The FSR and dead-zone explorers: their numbers are the core's, and the controls drive them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hri_teleop.core import fsr
from hri_teleop.core.gamepad import normalize_analog_input
from hri_teleop.core.mapping import map_force
from hri_teleop.course.widgets.deadzone import DeadzoneExplorer, deadzone_curve, filter_stick
from hri_teleop.course.widgets.fsr import FsrExplorer, describe_reading, format_ohm, fsr_curve, fsr_reading


def test_a_reading_is_the_core_chain_force_to_count_to_mapped():
    reading = fsr_reading(1.0, pulldown_ohm=10e3, supply_v=5.0, max_sensor_force=700)
    assert reading.count == fsr.force_to_count(1.0)
    assert reading.resistance_ohm == pytest.approx(fsr.force_to_resistance(1.0))
    assert reading.voltage_v == pytest.approx(fsr.resistance_to_voltage(reading.resistance_ohm))
    assert reading.mapped == map_force(reading.count, 700)


def test_no_force_is_an_open_circuit_reading_zero():
    reading = fsr_reading(0.0)
    assert math.isinf(reading.resistance_ohm) and reading.voltage_v == 0.0 and reading.count == 0
    assert reading.mapped == 0.0
    assert "open circuit" in describe_reading(reading)


def test_the_pulldown_and_supply_change_the_count_as_the_divider_says():
    lab = fsr_reading(1.0)
    small = fsr_reading(1.0, pulldown_ohm=3.3e3)
    low_supply = fsr_reading(1.0, supply_v=3.3)
    assert small.count == fsr.force_to_count(1.0, pulldown_ohm=3.3e3) and small.count < lab.count
    # The ADC's reference is the supply: the count of a ratiometric divider does not change.
    assert low_supply.voltage_v == pytest.approx(lab.voltage_v * 3.3 / 5.0)
    assert abs(low_supply.count - lab.count) <= 1


def test_the_curve_is_the_core_model_and_saturates_under_a_firm_press():
    curve = fsr_curve(20.0)
    assert curve.force_n[0] == 0.0 and curve.force_n[-1] == pytest.approx(20.0)
    np.testing.assert_array_equal(curve.count, fsr.force_to_count(curve.force_n))
    assert np.all(np.diff(curve.count) >= 0)
    slope_light = (curve.count[curve.force_n <= 1.0][-1]) / 1.0
    slope_firm = (curve.count[-1] - curve.count[curve.force_n <= 10.0][-1]) / 10.0
    assert slope_light > 20 * slope_firm, "the nonlinearity the handout's Fig. 4 shows is gone"


def test_format_ohm_speaks_kilo_and_open_circuit():
    assert format_ohm(7138.0) == "7.14 kOhm"
    assert format_ohm(250.0) == "250 Ohm"
    assert format_ohm(float("inf")) == "open circuit"


def test_moving_the_explorers_force_slider_updates_the_reading_and_readout():
    explorer = FsrExplorer(figure="image")
    explorer.force.value = 10.0
    explorer.max_sensor_force.value = 500
    assert explorer.reading == fsr_reading(10.0, max_sensor_force=500)
    assert f"count {explorer.reading.count}" in explorer.readout.value
    assert explorer.view.widget.value[:8] == b"\x89PNG\r\n\x1a\n"
    explorer.pulldown.value = 47e3
    assert explorer.reading.count == fsr.force_to_count(10.0, pulldown_ohm=47e3)


def test_the_explorer_defaults_to_ipympls_interactive_canvas():
    explorer = FsrExplorer()
    assert explorer.view.mode == "ipympl"
    assert type(explorer.view.widget).__name__ == "Canvas"


def test_the_deadzone_curve_is_normalize_analog_input_over_the_whole_travel():
    raw, filtered = deadzone_curve(0.2, points=41)
    assert raw[0] == -1.0 and raw[-1] == 1.0
    assert list(filtered) == [normalize_analog_input(float(v), 0.2) for v in raw]
    assert np.all(filtered[np.abs(raw) <= 0.2] == 0.0)


def test_each_stick_axis_is_filtered_on_its_own():
    assert filter_stick(0.05, 0.6, 0.1) == (0.0, normalize_analog_input(0.6, 0.1))


def test_the_deadzone_explorer_follows_its_sliders():
    explorer = DeadzoneExplorer(0.1, figure="image")
    explorer.stick_x.value, explorer.stick_y.value = 0.3, -0.05
    assert explorer.filtered == filter_stick(0.3, -0.05, 0.1)
    explorer.deadzone.value = 0.35
    assert explorer.filtered == (0.0, 0.0)
    assert "dead zone 0.35" in explorer.readout.value


def test_at_a_datasheet_force_the_explorer_shows_the_datasheets_resistance_beside_the_fitted_curves():
    explorer = FsrExplorer(force_n=1.0, figure="image")
    text = explorer.readout.value
    assert "R = 7.14 kOhm" in text  # the fitted curve
    assert "At 1 N the datasheet gives 6 kOhm, the curve 7.14 kOhm" in text
    explorer.force.value = 3.0
    assert "the datasheet gives" not in explorer.readout.value
    assert "fitted through the datasheet's four points" in explorer.readout.value
