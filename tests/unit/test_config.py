"""The teleop config: the lab's teleop.yaml loads, and every mistake is one line with the fix."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from hri_teleop.core.config import (
    CONFIG_KEYS,
    DEFAULT_PAD,
    DEFAULT_TWIST_TOPIC,
    ConfigError,
    TeleopConfig,
    load_teleop_config,
    load_yaml,
    teleop_config_from_dict,
)
from hri_teleop.core.gamepad import AUTO_LAYOUT, DEFAULT_LAYOUT, available_layouts
from hri_teleop.core.limits import DEFAULT_LIMITS, AxisLimits
from hri_teleop.core.teleop import AxisAssignment, TeleopParams

REPO = Path(__file__).resolve().parents[2]
TELEOP_YAML = REPO / "hri_lab" / "config" / "teleop.yaml"


def one_line(info) -> str:
    message = str(info.value)
    assert "\n" not in message, message
    return message


# --- the lab's file ----------------------------------------------------------------------


def test_lab_teleop_yaml_loads_and_documents_the_defaults():
    config = load_teleop_config(TELEOP_YAML)
    assert isinstance(config, TeleopConfig)
    # The file states the library defaults, so reading it or not gives the same lab.
    assert config.params == TeleopParams()
    assert config.limits == DEFAULT_LIMITS
    assert config.layout == AUTO_LAYOUT and DEFAULT_LAYOUT in available_layouts()
    assert config.pad == DEFAULT_PAD
    assert config.twist_topic == DEFAULT_TWIST_TOPIC


def test_lab_teleop_yaml_has_every_key_with_a_comment():
    data = load_yaml(TELEOP_YAML)
    assert sorted(data) == sorted(CONFIG_KEYS)
    for line in TELEOP_YAML.read_text().splitlines():
        # every line that sets a value explains it
        if re.match(r"^\s*[a-z_]+:\s*\S", line):
            assert "#" in line, f"teleop.yaml line without a comment: {line!r}"


def test_empty_dict_gives_the_defaults():
    config = teleop_config_from_dict({})
    assert config == TeleopConfig(TeleopParams(), DEFAULT_LIMITS, AUTO_LAYOUT, DEFAULT_PAD, DEFAULT_TWIST_TOPIC)


def test_values_are_taken_over():
    config = teleop_config_from_dict(
        {
            "rate": 100,  # an int is a fine float (rosparam gives ints for "100")
            "k_trans": 0.05,
            "k_rot": 0.2,
            "k_gripper": 0.02,
            "deadzone": 0.15,
            "width_min": 0.01,
            "width_max": 0.07,
            "initial_width": 0.05,
            "input_timeout": 0.3,
            "force_timeout": 1.0,
            "rumble_threshold": 0.05,
            "layout": "xbox",
            "pad": "virtual",
            "twist_topic": "/my_controller/cmd_vel",
            "limits": {"translation": {"velocity": 0.2}, "rotation": {"jerk": 3.0}},
            "axes": {"rotation": ["-left_x", "left_y", "-right_x"]},
            "buttons": {"close": "r1", "open": "l1"},
        },
        source="test.yaml",
    )
    p = config.params
    assert (p.rate_hz, p.k_trans, p.k_rot, p.k_gripper, p.deadzone) == (100.0, 0.05, 0.2, 0.02, 0.15)
    assert (p.width_min_m, p.width_max_m, p.initial_width_m) == (0.01, 0.07, 0.05)
    assert (p.input_timeout_s, p.force_timeout_s, p.rumble_threshold) == (0.3, 1.0, 0.05)
    assert (p.close_button, p.open_button, p.toggle_button, p.quit_button) == ("r1", "l1", "north", "west")
    assert p.assignment == AxisAssignment(rotation=("-left_x", "left_y", "-right_x"))
    assert config.limits.translation == AxisLimits(0.2, DEFAULT_LIMITS.translation.acceleration, DEFAULT_LIMITS.translation.jerk)
    assert config.limits.rotation.jerk == 3.0 and config.limits.rotation.velocity == DEFAULT_LIMITS.rotation.velocity
    assert (config.layout, config.pad, config.twist_topic) == ("xbox", "virtual", "/my_controller/cmd_vel")


# --- load_yaml -----------------------------------------------------------------------------


def test_missing_file(tmp_path):
    path = tmp_path / "nope.yaml"
    with pytest.raises(ConfigError) as info:
        load_yaml(path)
    message = one_line(info)
    assert "file not found" in message and str(path) in message


def test_directory_instead_of_file(tmp_path):
    with pytest.raises(ConfigError) as info:
        load_yaml(tmp_path)
    assert str(tmp_path) in one_line(info)


@pytest.mark.parametrize(
    "text, line",
    [
        ("rate: 50\nk_trans: [0.1\nk_rot: 0.3\n", 3),
        ("rate: 50\nlimits:\n  translation:\n    velocity: 0.2\n   jerk: 2\n", 5),
        ("rate: 50\n\tk_trans: 0.1\n", 2),
        ("rate: 50\nk_trans: 0.1: 2\n", 2),
    ],
)
def test_malformed_yaml_names_file_and_line(tmp_path, text, line):
    path = tmp_path / "teleop.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_teleop_config(path)
    message = one_line(info)
    assert message.startswith(f"{path}:{line}: ")
    assert "fix the YAML syntax" in message


def test_empty_file_is_an_empty_config(tmp_path):
    path = tmp_path / "teleop.yaml"
    path.write_text("# nothing yet\n")
    assert load_yaml(path) == {}
    assert load_teleop_config(path).params == TeleopParams()


def test_top_level_must_be_a_mapping(tmp_path):
    path = tmp_path / "teleop.yaml"
    path.write_text("- rate\n- 50\n")
    with pytest.raises(ConfigError) as info:
        load_yaml(path)
    assert "not a mapping" in one_line(info) and str(path) in str(info.value)


# --- teleop_config_from_dict ------------------------------------------------------------------


def test_unknown_key_lists_the_valid_ones(tmp_path):
    path = tmp_path / "teleop.yaml"
    path.write_text("k_tran: 0.1\n")
    with pytest.raises(ConfigError) as info:
        load_teleop_config(path)
    message = one_line(info)
    assert str(path) in message and "'k_tran'" in message
    for key in CONFIG_KEYS:
        assert key in message


@pytest.mark.parametrize(
    "data, words",
    [
        ({"k_trans": "0.1"}, ["k_trans", "number", "'0.1'"]),
        ({"rate": True}, ["rate", "number"]),
        ({"deadzone": [0.1]}, ["deadzone", "number"]),
        ({"rate": float("nan")}, ["rate", "number"]),
        ({"rate": 0}, ["rate", "> 0"]),
        ({"deadzone": 1.5}, ["deadzone", "[0, 1)"]),
        ({"width_max": 0.1}, ["width", "0.08"]),
        ({"layout": 3}, ["layout", "string"]),
        ({"pad": "joystick"}, ["pad", "pygame", "virtual"]),
        ({"twist_topic": ""}, ["twist_topic", "string"]),
        ({"limits": 0.2}, ["limits", "mapping"]),
        ({"limits": {"translation": {"speed": 0.2}}}, ["limits.translation.", "'speed'", "velocity", "jerk"]),
        ({"limits": {"linear": {}}}, ["limits.", "'linear'", "translation", "rotation"]),
        ({"limits": {"translation": {"velocity": "fast"}}}, ["limits.translation.velocity", "number"]),
        ({"limits": {"translation": {"velocity": -1.0}}}, ["limits.translation", "positive"]),
        ({"limits": {"translation": {"velocity": 2.0}}}, ["translation.velocity=2 > 1.7"]),
        ({"limits": {"rotation": {"jerk": 20000}}}, ["rotation.jerk"]),
        ({"axes": {"translation": "left_y"}}, ["axes.translation", "list"]),
        ({"axes": {"translation": ["left_y", "left_x"]}}, ["axes.translation", "3"]),
        ({"axes": {"rotation": ["left_y", "lefty", "right_y"]}}, ["axes.rotation[1]", "'lefty'", "left_x"]),
        ({"axes": {"pitch": []}}, ["axes.", "'pitch'"]),
        ({"buttons": {"close": "cross"}}, ["close_button", "'cross'", "south"]),
        ({"buttons": {"grab": "south"}}, ["buttons.", "'grab'", "close"]),
        ({"buttons": {"close": 1}}, ["buttons.close", "button name"]),
        ({"buttons": {"quit": "south"}}, ["need different buttons"]),
    ],
)
def test_bad_values_give_one_line_naming_the_key_and_the_source(data, words):
    with pytest.raises(ConfigError) as info:
        teleop_config_from_dict(data, source="lab.yaml")
    message = one_line(info)
    assert message.startswith("lab.yaml: ")
    for word in words:
        assert word in message, (word, message)


def test_not_a_mapping():
    with pytest.raises(ConfigError):
        teleop_config_from_dict(["rate", 50])  # type: ignore[arg-type]


def test_config_error_is_a_value_error():
    assert issubclass(ConfigError, ValueError)


def test_rosparam_style_round_trip(tmp_path):
    # What `rosparam load` puts on the server is what yaml.safe_load gives: the same dict.
    data = yaml.safe_load(TELEOP_YAML.read_text())
    assert teleop_config_from_dict(data, source="~") == load_teleop_config(TELEOP_YAML)


@pytest.mark.parametrize("topic", ["my topic", "/cmd//vel", "/9cmd", "cmd-vel", "/cmd/"])
def test_an_illegal_twist_topic_is_refused_in_one_line(topic):
    with pytest.raises(ConfigError) as info:
        teleop_config_from_dict({"twist_topic": topic}, source="teleop.yaml")
    assert "twist_topic" in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("topic", ["/cartesian_velocity_controller/cmd_vel", "cmd_vel", "~twist", "/a1/b_2"])
def test_legal_twist_topics_are_accepted(topic):
    assert teleop_config_from_dict({"twist_topic": topic}).twist_topic == topic


@pytest.mark.parametrize("value, expected", [("l1", "l1"), ("none", ""), (None, ""), ("", "")])
def test_deadman_button_from_the_config(value, expected):
    cfg = teleop_config_from_dict({"buttons": {"deadman": value}})
    assert cfg.params.deadman_button == expected


def test_overrides_replace_single_keys_of_the_file(tmp_path):
    path = tmp_path / "teleop.yaml"
    path.write_text("k_trans: 0.05\nrate: 50\n")
    cfg = load_teleop_config(path, {"k_trans": 0.07}, "node params")
    assert cfg.params.k_trans == 0.07 and cfg.params.rate_hz == 50.0
    with pytest.raises(ConfigError, match="node params over"):
        load_teleop_config(path, {"k_tran": 0.07}, "node params")


def test_feedback_switch_is_read_from_the_file_and_must_be_a_yaml_bool(tmp_path):
    from hri_teleop.core.config import teleop_config_from_dict

    assert teleop_config_from_dict({}).params.feedback is True
    assert teleop_config_from_dict({"feedback": False}).params.feedback is False
    with pytest.raises(ConfigError) as info:
        teleop_config_from_dict({"feedback": "false"}, "t.yaml")
    assert "t.yaml: feedback must be true or false" in str(info.value) and "without quotes" in str(info.value)
