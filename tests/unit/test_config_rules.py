"""Each rule of the teleop config (hri_teleop.core.config) at its edge, with the exact line a mistake gives
(issue 44: changing a rule or the key its message names fails a test): a close and a far unknown key,
limits_by_robot written over limits group by group, the unit of each limit, the robot's limits as the bound,
the file checked before its overrides, the calibration file's shape."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest
import yaml

from hri_teleop.core.config import (
    CONFIG_KEYS,
    ConfigError,
    lab_max_sensor_force,
    load_teleop_config,
    teleop_config_from_dict,
)
from hri_teleop.core.limits import DEFAULT_LIMITS
from hri_teleop.core.robot import LAB_ROBOT
from hri_teleop.core.robot_file import PANDA_FILE

PANDA = LAB_ROBOT.name  # the suite runs with HRI_ROBOT unset (tests/conftest.py): franka_panda


def _refused(d, source: str = "") -> str:
    """The one line ``d`` is refused with, named by ``source`` (none given: the default, ``<dict>``)."""
    with pytest.raises(ConfigError) as caught:
        teleop_config_from_dict(d, source=source) if source else teleop_config_from_dict(d)
    message = str(caught.value)
    assert "\n" not in message, message
    return message


# --- unknown keys -------------------------------------------------------------------------------------------


def test_an_unknown_key_close_to_a_valid_one_is_named_with_it():
    assert _refused({"k_tran": 0.1}) == (f"<dict>: unknown key 'k_tran'; did you mean 'k_trans'? valid keys are "
                                         f"{', '.join(CONFIG_KEYS)}")


def test_an_unknown_key_like_none_lists_the_valid_ones_only():
    assert _refused({"qqqq": 1}) == f"<dict>: unknown key 'qqqq'; valid keys are {', '.join(CONFIG_KEYS)}"


# --- limits and limits_by_robot ---------------------------------------------------------------------------


def test_limits_by_robot_writes_the_robots_numbers_over_limits_group_by_group_and_leaves_the_input_alone():
    d = {"limits": {"translation": {"velocity": 0.2}, "rotation": {"velocity": 0.4}},
         "limits_by_robot": {PANDA: {"translation": {"acceleration": 0.25}}, "other_arm": {"rotation": {"velocity": 0.1}}}}
    given = copy.deepcopy(d)
    limits = teleop_config_from_dict(d).limits
    assert (limits.translation.velocity, limits.translation.acceleration) == (0.2, 0.25)
    assert (limits.rotation.velocity, limits.rotation.acceleration) == (0.4, DEFAULT_LIMITS.rotation.acceleration)
    assert d == given


def test_limits_by_robot_alone_gives_the_robots_numbers_over_the_defaults():
    limits = teleop_config_from_dict({"limits_by_robot": {PANDA: {"translation": {"velocity": 0.2}}}}).limits
    assert limits.translation.velocity == 0.2 and limits.rotation == DEFAULT_LIMITS.rotation


def test_limits_by_robot_for_another_robot_leaves_limits_as_they_are():
    d = {"limits": {"translation": {"velocity": 0.2}}, "limits_by_robot": {"fr3": {"translation": {"velocity": 0.1}}}}
    assert teleop_config_from_dict(d).limits.translation.velocity == 0.2
    assert teleop_config_from_dict({"limits_by_robot": {"fr3": 5}}).limits == DEFAULT_LIMITS


@pytest.mark.parametrize("d, message", [
    ({"limits_by_robot": 5},
     "f.yaml: limits_by_robot must be a mapping, got 5; write e.g. limits_by_robot: {fr3: {translation: "
     "{acceleration: 0.2}}}"),
    ({"limits_by_robot": {PANDA: 0.2}},
     f"f.yaml: limits_by_robot.{PANDA} must be a mapping, got 0.2; write e.g. limits_by_robot: {{{PANDA}: "
     "{translation: {acceleration: 0.2}}}"),
    ({"limits": 5, "limits_by_robot": {PANDA: {"rotation": {"velocity": 0.4}}}},
     "f.yaml: limits must be a mapping, got 5; write e.g. limits: {translation: {velocity: 0.25}}"),
    ({"limits": {"translation": 5}, "limits_by_robot": {PANDA: {"rotation": {"velocity": 0.4}}}},
     "f.yaml: limits.translation must be a mapping, got 5; write e.g. limits: {translation: {velocity: 0.25}}"),
    ({"limits": {"translation": {"velocity": 0.2}}, "limits_by_robot": {PANDA: {"translation": 5}}},
     "f.yaml: limits.translation must be a mapping, got 5; write e.g. limits: {translation: {velocity: 0.25}}"),
    ({"limits": 5},
     "f.yaml: limits must be a mapping, got 5; write e.g. limits: {translation: {velocity: 0.25}}"),
    ({"limits": {"rotation": [1]}},
     "f.yaml: limits.rotation must be a mapping, got [1]; write e.g. limits: {rotation: {velocity: 0.25}}"),
    ({"axes": ["left_y"]},
     "f.yaml: axes must be a mapping, got ['left_y']; write e.g. axes: {translation: [left_y, -left_x, right_y]}"),
])
def test_a_section_that_is_not_a_mapping_is_named_with_its_file_and_an_example(d, message):
    assert _refused(d, "f.yaml") == message


def test_a_number_key_that_is_not_a_number_says_what_the_number_means():
    assert _refused({"rate": "fast"}) == ("<dict>: rate must be a number (control loop rate in Hz), got 'fast' of type "
                                          "str; write a plain number without quotes")


def test_buttons_that_are_not_a_mapping_are_named_with_an_example():
    assert _refused({"buttons": 5}, "f.yaml") == ("f.yaml: buttons must be a mapping, got 5; write e.g. buttons: "
                                                  "{close: south, open: east, toggle: north, quit: west}")


@pytest.mark.parametrize("value", [None, "none", ""])
def test_no_deadman_button_is_written_none_or_left_empty(value):
    assert teleop_config_from_dict({"buttons": {"deadman": value}}).params.deadman_button == ""


@pytest.mark.parametrize("group, name, unit", [
    ("translation", "velocity", "m/s"), ("translation", "acceleration", "m/s^2"), ("translation", "jerk", "m/s^3"),
    ("rotation", "velocity", "rad/s"), ("rotation", "acceleration", "rad/s^2"), ("rotation", "jerk", "rad/s^3"),
])
def test_a_limit_that_is_not_a_number_is_named_with_its_unit(group, name, unit):
    assert _refused({"limits": {group: {name: "0.1"}}}) == (
        f"<dict>: limits.{group}.{name} must be a number ({unit}), got '0.1' of type str; "
        "write a plain number without quotes")


def test_given_limits_stay_inside_the_named_robots_not_the_pandas():
    """9.5 m/s^2 is inside the Panda's 13 and above the FR3's 9."""
    assert teleop_config_from_dict({"limits": {"translation": {"acceleration": 9.5}}}).limits.translation.acceleration == 9.5
    assert "translation.acceleration=9.5 > 9" in _refused({"robot": "fr3",
                                                           "limits": {"translation": {"acceleration": 9.5}}})


# --- the file and its overrides -----------------------------------------------------------------------------


def test_no_file_is_the_defaults_and_the_overrides(tmp_path):
    assert load_teleop_config("").limits == DEFAULT_LIMITS
    assert load_teleop_config("", {"k_trans": 0.05}).params.k_trans == 0.05
    with pytest.raises(ConfigError) as caught:
        load_teleop_config("", {"k_trans": "x"})
    assert str(caught.value).startswith("overrides: k_trans must be a number")


def test_the_file_is_checked_before_its_overrides_and_each_mistake_is_named_where_it_is(tmp_path):
    path = tmp_path / "teleop.yaml"
    path.write_text("k_trans: x\n")
    with pytest.raises(ConfigError) as caught:
        load_teleop_config(path, {"rate": 50})
    assert str(caught.value).startswith(f"{path}: k_trans must be a number")
    path.write_text("k_trans: 0.05\n")
    with pytest.raises(ConfigError) as caught:
        load_teleop_config(path, {"rate": "x"})
    assert str(caught.value).startswith(f"overrides over {path}: rate must be a number")
    with pytest.raises(ConfigError) as caught:
        load_teleop_config(path, {"rate": "x"}, overrides_source="~ params")
    assert str(caught.value).startswith(f"~ params over {path}: rate must be a number")
    assert load_teleop_config(path, {"rate": 25}).params.k_trans == 0.05


# --- the calibration file ---------------------------------------------------------------------------------


def test_a_missing_calibration_file_is_named_as_one(tmp_path):
    with pytest.raises(ConfigError) as caught:
        lab_max_sensor_force(tmp_path / "calibration.yaml")
    assert str(caught.value) == (f"calibration file not found: {tmp_path / 'calibration.yaml'}; restore "
                                 "hri_lab/config/calibration.yaml (max_sensor_force: 700)")


@pytest.mark.parametrize("text", ["[700]\n", "700\n", ""])
def test_a_calibration_file_that_is_not_a_mapping_has_no_value(tmp_path, text):
    path = tmp_path / "calibration.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=r"max_sensor_force must be a whole count 1..1023, got None"):
        lab_max_sensor_force(path)


def test_the_lab_calibration_file_is_a_mapping_with_the_value():
    data = yaml.safe_load((Path(__file__).resolve().parents[2] / "hri_lab" / "config" / "calibration.yaml").read_text())
    assert lab_max_sensor_force() == data["max_sensor_force"]


# --- a robot's own numbers: its limits bound the defaults too, its twist topic is the default one ------------


def _slow_robot(tmp_path: Path, topic: str = "/slow/cmd_vel") -> str:
    """The Panda's file with a translation velocity limit of 0.2 m/s, below the lab's 0.25, and its own topic."""
    data = yaml.safe_load(PANDA_FILE.read_text())
    data["name"] = "slow_arm"
    data["cartesian_limits"]["translation"]["velocity"] = 0.2
    data["topics"]["twist_command"] = topic
    path = tmp_path / "slow_arm.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


def test_the_default_limits_are_checked_against_the_named_robot(tmp_path):
    slow = _slow_robot(tmp_path)
    assert _refused({"robot": slow}, "f.yaml").startswith(
        "f.yaml: limits: limits exceed the robot's (translation.velocity=0.25 > 0.2)")
    config = teleop_config_from_dict({"robot": slow, "limits": {"translation": {"velocity": 0.2}}})
    assert config.limits.translation.velocity == 0.2 and config.robot.name == "slow_arm"


def test_the_twist_topic_is_the_robots_unless_the_config_names_one(tmp_path):
    slow = _slow_robot(tmp_path)
    fit = {"robot": slow, "limits": {"translation": {"velocity": 0.2}}}
    assert teleop_config_from_dict(fit).twist_topic == "/slow/cmd_vel"
    assert teleop_config_from_dict({**fit, "twist_topic": "/mine/cmd_vel"}).twist_topic == "/mine/cmd_vel"


def test_a_missing_config_file_says_where_configs_live(tmp_path):
    with pytest.raises(ConfigError) as caught:
        load_teleop_config(tmp_path / "teleop.yaml")
    assert str(caught.value) == (f"file not found: {tmp_path / 'teleop.yaml'}; check the path (configs live in "
                                 "hri_lab/config/)")


@pytest.mark.parametrize("d, line", [
    ({"rate": -1}, "<dict>: rate must be > 0 Hz, got -1.0; the lab runs at 50"),
    ({"input_timeout": -1}, "<dict>: input_timeout must be > 0 s, got -1.0; e.g. 0.5"),
])
def test_a_value_the_controller_refuses_is_named_by_the_files_key_not_the_fields(d, line):
    assert _refused(d) == line
