"""hri_teleop.core.attachment: the piston, spring and FSR of handout Fig. 5 as force to count. Its table lookup
must give exactly what hri_teleop.core.fsr.force_to_count gives, at every threshold and between them."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from hri_teleop.core import fsr
from hri_teleop.core.attachment import Attachment, AttachmentError

LAB = Attachment()


def _exact(force_n: float, attachment: Attachment = LAB) -> int:
    return int(fsr.force_to_count(force_n, law=attachment.law, pulldown_ohm=attachment.pulldown_ohm,
                                  supply_v=attachment.supply_v, adc_bits=attachment.adc_bits))


def test_the_spring_pushes_with_590_n_per_m_up_to_the_3_mm_travel_and_not_beyond():
    assert LAB.spring_force_n(-0.001) == 0.0
    assert LAB.spring_force_n(0.0) == 0.0
    assert LAB.spring_force_n(0.0015) == pytest.approx(0.885)
    assert LAB.spring_force_n(0.003) == pytest.approx(1.77)
    assert LAB.spring_force_n(0.004) == pytest.approx(1.77)
    assert LAB.full_travel_force_n == pytest.approx(1.77)


def test_full_travel_reads_the_count_students_record_as_max_sensor_force():
    assert LAB.full_travel_count == _exact(1.77) == 700
    assert Attachment(piston_travel_m=0.002).full_travel_count == _exact(590.0 * 0.002)
    assert Attachment(spring_n_per_m=400.0).full_travel_count == _exact(400.0 * 0.003)


def test_no_force_and_nan_read_0_like_an_open_circuit():
    for force in (0.0, -0.5, math.nan):
        assert LAB.count(force) == 0


def test_every_threshold_of_the_10_bit_table_and_its_neighbours_read_what_force_to_count_reads():
    thresholds = fsr.count_to_force(np.arange(1024))
    checked = 0
    for low in (float(f) for f in thresholds):
        if not (math.isfinite(low) and low > 0.0):
            continue
        for force in (float(np.nextafter(low, 0.0)), low, float(np.nextafter(low, math.inf)), low * (1 + 1e-6),
                      low * (1 - 1e-6), low * (1 + 2e-6), low * (1 - 2e-6)):
            assert LAB.count(force) == _exact(force), force
        checked += 1
    assert checked > 1000 // 2


def test_a_force_between_two_thresholds_reads_the_lower_ones_count():
    thresholds = [float(f) for f in fsr.count_to_force(np.arange(1024))]
    for low, high in zip(thresholds, thresholds[1:]):
        if math.isfinite(low) and math.isfinite(high) and high > low > 0.0:
            middle = 0.5 * (low + high)
            assert LAB.count(middle) == _exact(middle)


def test_a_wiring_of_its_own_reads_its_own_counts_at_and_between_its_thresholds():
    """Another FSR, a 4.7 kOhm pull-down and a 3.3 V board: the table is built and read with that wiring."""
    law = fsr.fit_power_law([(0.2, 30e3), (1.0, 8e3), (10.0, 1.2e3)])
    own = Attachment(law=law, pulldown_ohm=4.7e3, supply_v=3.3)
    thresholds = [float(f) for f in fsr.count_to_force(np.arange(1024), law=law, pulldown_ohm=4.7e3, supply_v=3.3)]
    checked = 0
    for low, high in zip(thresholds, thresholds[1:]):
        if math.isfinite(low) and math.isfinite(high) and high > low > 0.0:
            for force in (low, 0.5 * (low + high), float(np.nextafter(high, 0.0))):
                assert own.count(force) == _exact(force, own), force
            checked += 1
    assert checked > 500
    assert own.count(1e9) == _exact(1e9, own)


@given(st.floats(min_value=1e-9, max_value=1e6, allow_nan=False))
@example(1e-9)
@example(1.77)
@example(1e6)
def test_any_force_reads_exactly_what_force_to_count_reads(force):
    assert LAB.count(force) == _exact(force)


def test_an_infinite_force_reads_the_top_count():
    assert LAB.count(math.inf) == _exact(math.inf) == 1023


def test_an_adc_of_more_than_16_bits_is_computed_without_a_table():
    wide = Attachment(adc_bits=18)
    for force in (0.01, 1.0, 1.77, 20.0):
        assert wide.count(force) == _exact(force, wide)
    assert wide.full_travel_count == _exact(1.77, wide) > 700 * 200


def test_an_adc_without_a_table_reads_with_its_own_wiring():
    law = fsr.fit_power_law([(0.2, 30e3), (1.0, 8e3), (10.0, 1.2e3)])
    own = Attachment(adc_bits=18, law=law, pulldown_ohm=4.7e3)
    for force in (0.05, 0.5, 1.77, 20.0):
        assert own.count(force) == _exact(force, own) != _exact(force, Attachment(adc_bits=18)), force
    assert own.count(math.inf) == 2 ** 18 - 1  # whatever the wiring


def test_a_16_bit_adc_is_read_through_its_table_all_the_same():
    fine = Attachment(adc_bits=16)
    for force in (0.01, 1.0, 1.77, 20.0):
        assert fine.count(force) == _exact(force, fine)


@pytest.mark.parametrize("field, value, words", [
    ("piston_travel_m", 0.0, "Attachment.piston_travel_m"),
    ("piston_travel_m", -0.003, "Attachment.piston_travel_m"),
    ("spring_n_per_m", 0.0, "Attachment.spring_n_per_m"),
    ("spring_n_per_m", "stiff", "Attachment.spring_n_per_m"),
])
def test_a_travel_or_spring_that_is_not_a_positive_number_is_refused_by_name(field, value, words):
    with pytest.raises(AttachmentError, match=words):
        Attachment(**{field: value})


def test_a_wiring_the_fsr_model_refuses_is_refused_with_its_own_words():
    with pytest.raises(fsr.FsrError, match="adc_bits must be an integer from 1 to 24"):
        Attachment(adc_bits=25)


def test_a_refused_travel_or_spring_says_what_it_got_and_a_usable_value():
    with pytest.raises(AttachmentError) as travel:
        Attachment(piston_travel_m=0.0)
    assert str(travel.value) == "Attachment.piston_travel_m must be > 0, got 0.0; e.g. 0.003 (3 mm)"
    with pytest.raises(AttachmentError) as spring:
        Attachment(spring_n_per_m=-1)
    assert str(spring.value) == "Attachment.spring_n_per_m must be > 0, got -1; e.g. 590.0"


def test_whole_numbers_from_a_yaml_file_are_kept_as_floats():
    given = Attachment(piston_travel_m=np.float32(0.5), spring_n_per_m=590)
    assert type(given.piston_travel_m) is float and given.piston_travel_m == 0.5
    assert type(given.spring_n_per_m) is float and given.spring_n_per_m == 590.0


@pytest.mark.parametrize("wiring, words", [
    ({"pulldown_ohm": -1.0}, "pulldown_ohm must be a positive finite resistance in ohm, got -1.0"),
    ({"supply_v": 0.0}, "supply_v must be a positive finite voltage in volt, got 0.0"),
])
def test_a_wiring_without_a_table_is_refused_when_the_attachment_is_made_not_at_its_first_count(wiring, words):
    """An 18-bit ADC builds no table, so only the check at construction can refuse the wiring."""
    with pytest.raises(fsr.FsrError, match=words):
        Attachment(adc_bits=18, **wiring)
