"""The lab's calibration value has one place (hri_lab/config/calibration.yaml) and everything reads it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from hri_teleop.core.config import LAB_CALIBRATION, ConfigError, lab_max_sensor_force

ROOT = Path(__file__).resolve().parents[2]


def test_the_lab_value_is_read_from_the_calibration_file():
    text = LAB_CALIBRATION.read_text(encoding="utf-8")
    assert int(re.search(r"^max_sensor_force:\s*(\d+)", text, re.M).group(1)) == lab_max_sensor_force()


@pytest.mark.parametrize("value", ["1", "1023", "690"])
def test_a_whole_count_in_range_is_accepted(tmp_path, value):
    path = tmp_path / "calibration.yaml"
    path.write_text(f"max_sensor_force: {value}\n")
    assert lab_max_sensor_force(path) == int(value)


@pytest.mark.parametrize("value", ["0", "1024", "-5", "700.0", "'700'", "true", "null"])
def test_anything_else_is_one_line_naming_the_file_and_the_fix(tmp_path, value):
    path = tmp_path / "calibration.yaml"
    path.write_text(f"max_sensor_force: {value}\n")
    with pytest.raises(ConfigError, match=r"calibration.yaml: max_sensor_force must be a whole count 1..1023") as err:
        lab_max_sensor_force(path)
    assert "\n" not in str(err.value)


def test_a_missing_file_says_how_to_restore_it(tmp_path):
    with pytest.raises(ConfigError, match="restore hri_lab/config/calibration.yaml"):
        lab_max_sensor_force(tmp_path / "nope.yaml")


def test_the_consumers_take_the_value_from_the_file():
    from benchmarks.nodes import MAX_SENSOR_FORCE
    from hri_teleop.grading.cases.inputs import PUBLIC_MAX_SENSOR_FORCE

    assert PUBLIC_MAX_SENSOR_FORCE == MAX_SENSOR_FORCE == lab_max_sensor_force()
    for launch in ("sensor.launch", "teleoperation.launch"):
        text = (ROOT / "hri_lab" / "launch" / launch).read_text(encoding="utf-8")
        assert '<arg name="max_sensor_force" default=""' in text, launch
        assert 'file="$(find hri_lab)/config/calibration.yaml"' in text, launch
