"""The teleoperation config (``hri_lab/config/teleop.yaml``): read, check, turn into core objects.

Students edit the file and the launch file loads it, where a typo (``k_tran``) or a quoted number
(``"0.1"``) would be silently ignored or crash a node later; so every problem is one line naming
the file (and line), the key, what was found and the fix. Keys are flat: the node passes its
private namespace to :func:`teleop_config_from_dict`, and missing keys take the defaults of
:class:`~hri_teleop.core.teleop.TeleopParams` and :data:`~hri_teleop.core.limits.DEFAULT_LIMITS`.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, Mapping, Optional, Tuple, Union

from hri_teleop.core.checks import is_finite_number
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.gamepad import AUTO_LAYOUT, DEFAULT_LAYOUT, PAD_KINDS
from hri_teleop.core.limits import DEFAULT_LIMITS, ROBOT_LIMITS, AxisLimits, CartesianLimits, LimitsError, TwistLimiter
from hri_teleop.core.mapping import ADC_MAX_COUNT
from hri_teleop.core.paths import LAB_CONFIG
from hri_teleop.core.robot import LAB_ROBOT, RobotFileError, RobotProfile, robot_named
from hri_teleop.core.robot_file import lab_robot_file
from hri_teleop.core.teleop import (
    HANDOUT_BUTTONS,
    OPTIONAL_BUTTONS,
    RUMBLE_MOTORS,
    AxisAssignment,
    TeleopError,
    TeleopParams,
)
from hri_teleop.core.yamlfile import read_yaml

__all__ = [
    "ConfigError",
    "TeleopConfig",
    "DEFAULT_LAYOUT",
    "AUTO_LAYOUT",
    "DEFAULT_PAD",
    "DEFAULT_TWIST_TOPIC",
    "LAB_TELEOP_CONFIG",
    "LAB_CALIBRATION",
    "lab_max_sensor_force",
    "PAD_KINDS",
    "CONFIG_KEYS",
    "load_yaml",
    "teleop_config_from_dict",
    "load_teleop_config",
]

DEFAULT_PAD = "pygame"  # one of hri_teleop.core.gamepad.PAD_KINDS; DEFAULT_LAYOUT comes from there too
#: The Cartesian velocity controller's command topic (geometry_msgs/Twist).
DEFAULT_TWIST_TOPIC: str = lab_robot_file()["topics"]["twist_command"]
#: The lab's teleoperation config in a checkout (what teleoperation.py reads by default).
LAB_TELEOP_CONFIG = LAB_CONFIG / "teleop.yaml"
#: The lab's calibration value, /max_sensor_force (Ex. 11), in one file (docs/instructors.md).
LAB_CALIBRATION = LAB_TELEOP_CONFIG.with_name("calibration.yaml")

# YAML key -> (TeleopParams field, meaning for messages)
_NUMBER_KEYS: Dict[str, Tuple[str, str]] = {
    "rate": ("rate_hz", "control loop rate in Hz"),
    "k_trans": ("k_trans", "m/s at full stick"),
    "k_rot": ("k_rot", "rad/s at full stick"),
    "k_gripper": ("k_gripper", "gripper speed in m/s while a button is held"),
    "deadzone": ("deadzone", "fraction of stick travel, 0..1"),
    "width_min": ("width_min_m", "smallest gripper width in m"),
    "width_max": ("width_max_m", "largest gripper width in m"),
    "initial_width": ("initial_width_m", "gripper width at start in m"),
    "input_timeout": ("input_timeout_s", "seconds without pad input before stopping"),
    "stale_input_timeout": ("stale_input_timeout_s", "seconds a held stick may read identical before the pad counts as lost, 0: off"),
    "precision_scale": ("precision_scale", "gain factor while the precision button is held, 0..1"),
    "force_timeout": ("force_timeout_s", "seconds after which the mapped force is stale"),
    "rumble_threshold": ("rumble_threshold", "mapped force 0..1 below which the pad does not rumble"),
}
_STRING_KEYS = ("layout", "pad", "twist_topic")
_CHOICE_KEYS = {"rumble_motors": ("rumble_motors", RUMBLE_MOTORS)}
_BOOL_KEYS = {"feedback": ("feedback", "force feedback: true = the pad rumbles, false = it never does")}
# ROS graph resource names: optional ~ or /, then segments that start with a letter.
_ROS_NAME = re.compile(r"^[~/]?[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*$")
# buttons.<role> -> TeleopParams field: close, open, toggle, quit, then the optional deadman, precision.
_BUTTON_ROLES = {field[: -len("_button")]: field for field in HANDOUT_BUTTONS + OPTIONAL_BUTTONS}
_OPTIONAL_ROLES = tuple(role for role, field in _BUTTON_ROLES.items() if field in OPTIONAL_BUTTONS)
_LIMIT_NAMES = ("velocity", "acceleration", "jerk")

#: Every top-level key the teleop config may have.
CONFIG_KEYS = tuple(sorted(list(_NUMBER_KEYS) + list(_STRING_KEYS) + list(_BOOL_KEYS) + list(_CHOICE_KEYS)
                           + ["limits", "limits_by_robot", "axes", "buttons", "robot"]))


class ConfigError(HriTeleopError, ValueError):
    """The config file or dict is unreadable or has a bad key/value (one line with file and fix)."""


@dataclass(frozen=True)
class TeleopConfig:
    """Everything the teleoperation node needs, checked."""

    params: TeleopParams
    limits: CartesianLimits
    layout: str  # "auto" (a real pad identifies itself), a shipped layout's name or a YAML path
    pad: str  # "pygame" | "virtual"
    twist_topic: str
    robot: RobotProfile = LAB_ROBOT  # ``robot:``: whose limits ``limits`` stay inside, and its twist topic


def load_yaml(path: Union[str, Path]) -> Dict[str, Any]:
    """The top-level mapping of a YAML file (``{}`` for an empty file).

    Raises :class:`ConfigError` for a missing file, a syntax error (with the line) or a
    top level that is not a mapping.
    """

    path = Path(path)
    data = read_yaml(path, ConfigError, missing_fix="check the path (configs live in hri_lab/config/)")
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ConfigError(f"{path}: the top level is a {type(data).__name__}, not a mapping; write `key: value` lines")
    return data


def _unknown(key: str, where: str, valid: Tuple[str, ...], source: str) -> ConfigError:
    close = difflib.get_close_matches(key, valid, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return ConfigError(f"{source}: unknown key {where}{key!r}; {hint}valid keys are {', '.join(valid)}")


def _number(value: object, key: str, meaning: str, source: str) -> float:
    if not is_finite_number(value):
        raise ConfigError(
            f"{source}: {key} must be a number ({meaning}), got {value!r} of type {type(value).__name__}; "
            "write a plain number without quotes"
        )
    return float(value)


def _mapping(value: object, key: str, source: str, example: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise ConfigError(f"{source}: {key} must be a mapping, got {value!r}; write e.g. {example}")
    return value


def _limits_for_robot(d: Mapping[str, Any], robot: str, source: str) -> Optional[Mapping[str, Any]]:
    """``limits:`` with what ``limits_by_robot:`` gives the robot named ``robot`` written over it, group by group
    (None: neither says anything). The lab's limits fit the Panda's budget at 50 Hz; a robot whose budget they
    do not fit (the FR3's jerk) gets its own numbers there, and the robot is chosen once (HRI_ROBOT)."""
    given = d.get("limits")
    if "limits_by_robot" not in d:
        return given
    table = _mapping(d["limits_by_robot"], "limits_by_robot", source,
                     "limits_by_robot: {fr3: {translation: {acceleration: 0.2}}}")
    if robot not in table:
        return given
    own = _mapping(table[robot], f"limits_by_robot.{robot}", source,
                   f"limits_by_robot: {{{robot}: {{translation: {{acceleration: 0.2}}}}}}")
    merged: Dict[str, Any] = {str(g): dict(v) if isinstance(v, Mapping) else v
                              for g, v in (_mapping(given, "limits", source, "limits: {translation: {velocity: 0.25}}")
                                           if given is not None else {}).items()}
    for group, entries in own.items():
        if isinstance(entries, Mapping) and isinstance(merged.get(group), dict):
            merged[str(group)].update(entries)
        else:
            merged[str(group)] = entries  # _limits_from judges it, naming limits.<group>
    return merged


def _limits_from(value: object, source: str, hard: CartesianLimits = ROBOT_LIMITS) -> CartesianLimits:
    groups = _mapping(value, "limits", source, "limits: {translation: {velocity: 0.25}}")
    built = {}
    for group in groups:
        if group not in ("translation", "rotation"):
            raise _unknown(str(group), "limits.", ("translation", "rotation"), source)
    for group in ("translation", "rotation"):
        default = getattr(DEFAULT_LIMITS, group)
        entries = _mapping(groups.get(group, {}), f"limits.{group}", source, f"limits: {{{group}: {{velocity: 0.25}}}}")
        for name in entries:
            if name not in _LIMIT_NAMES:
                raise _unknown(str(name), f"limits.{group}.", _LIMIT_NAMES, source)
        unit = "m" if group == "translation" else "rad"
        values = {
            name: _number(entries[name], f"limits.{group}.{name}", f"{unit}/s" + {"velocity": "", "acceleration": "^2", "jerk": "^3"}[name], source)
            if name in entries
            else getattr(default, name)
            for name in _LIMIT_NAMES
        }
        try:
            built[group] = AxisLimits(**values)
        except LimitsError as exc:
            raise ConfigError(f"{source}: limits.{group}: {exc}") from None
    limits = CartesianLimits(**built)
    try:
        TwistLimiter(limits, hard_limits=hard)  # checks them against the robot's
    except LimitsError as exc:
        raise ConfigError(f"{source}: {exc}") from None
    return limits


def _axes_from(value: object, source: str) -> AxisAssignment:
    modes = _mapping(value, "axes", source, "axes: {translation: [left_y, -left_x, right_y]}")
    for mode in modes:
        if mode not in ("translation", "rotation"):
            raise _unknown(str(mode), "axes.", ("translation", "rotation"), source)
    kwargs = {}
    for mode in ("translation", "rotation"):
        if mode in modes:
            entries = modes[mode]
            if not isinstance(entries, (list, tuple)):
                raise ConfigError(f"{source}: axes.{mode} must be a list of 3 axes, got {entries!r}; write e.g. [left_y, -left_x, right_y]")
            kwargs[mode] = tuple(entries)
    try:
        return AxisAssignment(**kwargs)
    except TeleopError as exc:
        raise ConfigError(f"{source}: {exc}") from None


def teleop_config_from_dict(d: Mapping[str, Any], source: str = "<dict>") -> TeleopConfig:
    """Check a config mapping (from YAML or ``rospy.get_param('~')``) and build the core objects.

    Unknown keys, wrong types and out-of-range values raise :class:`ConfigError` naming
    ``source`` (the file), the key and the fix.
    """
    if not isinstance(d, Mapping):
        raise ConfigError(f"{source}: expected a mapping of config keys, got {type(d).__name__}; write `key: value` lines")
    for key in d:
        if key not in CONFIG_KEYS:
            raise _unknown(str(key), "", CONFIG_KEYS, source)

    kwargs: Dict[str, Any] = {}
    for key, (field_name, meaning) in _NUMBER_KEYS.items():
        if key in d:
            kwargs[field_name] = _number(d[key], key, meaning, source)

    for key, (field_name, meaning) in _BOOL_KEYS.items():
        if key in d:
            if not isinstance(d[key], bool):
                raise ConfigError(f"{source}: {key} must be true or false ({meaning}), got {d[key]!r}; "
                                  f"write {key}: true or {key}: false, without quotes")
            kwargs[field_name] = d[key]

    for key, (field_name, choices) in _CHOICE_KEYS.items():
        if key in d:
            if d[key] not in choices:
                raise ConfigError(f"{source}: {key} must be one of {', '.join(choices)}, got {d[key]!r}; "
                                  f"write e.g. {key}: {choices[0]}")
            kwargs[field_name] = d[key]

    strings = {"layout": AUTO_LAYOUT, "pad": DEFAULT_PAD, "twist_topic": DEFAULT_TWIST_TOPIC}
    for key in _STRING_KEYS:
        if key in d:
            value = d[key]
            if not isinstance(value, str) or not value.strip():
                raise ConfigError(f"{source}: {key} must be a non-empty string, got {value!r}; e.g. {key}: {strings[key]}")
            strings[key] = value.strip()
    if not _ROS_NAME.match(strings["twist_topic"]):
        raise ConfigError(f"{source}: twist_topic {strings['twist_topic']!r} is not a valid ROS topic name; "
                          f"use letters, digits, _ and /, e.g. {DEFAULT_TWIST_TOPIC}")
    if strings["pad"] not in PAD_KINDS:
        raise ConfigError(f"{source}: pad must be one of {', '.join(PAD_KINDS)}, got {strings['pad']!r}; use virtual when no gamepad is attached")

    if "buttons" in d:
        roles = _mapping(d["buttons"], "buttons", source, "buttons: {close: south, open: east, toggle: north, quit: west}")
        for role, value in roles.items():
            if role not in _BUTTON_ROLES:
                raise _unknown(str(role), "buttons.", tuple(_BUTTON_ROLES), source)
            if role in _OPTIONAL_ROLES and value in (None, "none"):
                value = ""  # no dead-man switch / precision button (the handout's behaviour), as "" says too
            if not isinstance(value, str):
                raise ConfigError(f"{source}: buttons.{role} must be a button name such as south, got {value!r}; write e.g. {role}: south")
            kwargs[_BUTTON_ROLES[role]] = value

    if "axes" in d:
        kwargs["assignment"] = _axes_from(d["axes"], source)
    try:
        robot = robot_named(d.get("robot"))
    except RobotFileError as exc:
        raise ConfigError(f"{source}: robot: {exc}") from None
    given = _limits_for_robot(d, robot.name, source)
    limits = _limits_from(given, source, robot.cartesian_limits) if given is not None else DEFAULT_LIMITS
    kwargs["gripper_max_width_m"] = robot.gripper.max_width_m
    for key in ("width_max", "initial_width"):  # unset: the robot's hand fully open
        if key not in d:
            kwargs[_NUMBER_KEYS[key][0]] = robot.gripper.max_width_m
    if given is None:  # _limits_from checked given limits against the robot already
        try:
            TwistLimiter(hard_limits=robot.cartesian_limits)  # the defaults (limits is DEFAULT_LIMITS)
        except LimitsError as exc:
            raise ConfigError(f"{source}: limits: {exc}") from None

    try:
        params = TeleopParams(**kwargs)
    except TeleopError as exc:
        message = str(exc)
        for key, (field_name, _) in _NUMBER_KEYS.items():  # speak the file's key names
            if message.startswith(field_name + " "):
                message = key + message[len(field_name):]
        raise ConfigError(f"{source}: {message}") from None
    twist_topic = strings["twist_topic"] if "twist_topic" in d else robot.topics["twist_command"]
    return TeleopConfig(params=params, limits=limits, layout=strings["layout"], pad=strings["pad"], twist_topic=twist_topic,
                        robot=robot)


def load_teleop_config(path: Union[str, Path], overrides: Optional[Mapping[str, Any]] = None,
                       overrides_source: str = "overrides") -> TeleopConfig:
    """:func:`load_yaml` then :func:`teleop_config_from_dict`, with the file named in every error.

    ``overrides`` (e.g. a node's private parameters) replace single keys of the file; the
    file is checked on its own first, so a mistake in it is reported against the file.
    An empty ``path`` means no file: the defaults plus the overrides.
    """
    settings: Dict[str, Any] = {}
    if str(path):
        settings = dict(load_yaml(path))
        if not overrides:
            return teleop_config_from_dict(settings, source=str(path))
        teleop_config_from_dict(settings, source=str(path))
    settings.update(overrides or {})
    where = f"{overrides_source} over {path}" if str(path) else overrides_source
    return teleop_config_from_dict(settings, source=where)


def lab_max_sensor_force(path: Union[str, Path] = LAB_CALIBRATION) -> int:
    """The lab's /max_sensor_force: ``max_sensor_force`` of the calibration file, a whole count 1..1023."""
    data = read_yaml(path, ConfigError, what="calibration file",
                     missing_fix="restore hri_lab/config/calibration.yaml (max_sensor_force: 700)")
    value = data.get("max_sensor_force") if isinstance(data, dict) else None
    if isinstance(value, bool) or not isinstance(value, int) or not 0 < value <= ADC_MAX_COUNT:
        raise ConfigError(f"{path}: max_sensor_force must be a whole count 1..{ADC_MAX_COUNT}, got {value!r}; "
                          "write the count at full piston travel, e.g. max_sensor_force: 700")
    return value
