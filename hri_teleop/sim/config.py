"""The simulated lab's settings (``hri_lab/config/sim.yaml``): read, check, turn into a WorldConfig.

Students change the object, the board's rate or the start pose there, in a scenario's ``world:``
or with a private parameter of ``lab_sim``; a typo (``rate_hx``), a quoted number or a value out
of range is one line naming the file (or layer), the key, what was found and the fix, as
:mod:`hri_teleop.core.config` does for teleop.yaml. sim.yaml's comments document the keys. Not
settings, on purpose: the Panda's limits and the FSR's wiring. Pure: YAML files, no rospy.
"""

from __future__ import annotations

import builtins
import dataclasses
import difflib
from pathlib import Path
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, TypedDict, Union

from hri_teleop.core.attachment import Attachment, AttachmentError
from hri_teleop.core.checks import is_finite_number, is_int
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.paths import LAB_CONFIG
from hri_teleop.core.robot import RobotFileError, RobotProfile, robot_named
from hri_teleop.core.yamlfile import read_yaml
from hri_teleop.sim.arm import SimArmConfig, SimArmError
from hri_teleop.sim.board import HANDOUT_FIRMWARE_RATE_HZ, BoardConfig, BoardError
from hri_teleop.sim.grasp_objects import OBJECTS, GraspObject
from hri_teleop.sim.hand_params import HandParams, HandSimError
from hri_teleop.sim.joint_motion import start_joints
from hri_teleop.sim.kinematics import KinematicsError
from hri_teleop.sim.world import WorldConfig, WorldError, robot_arm, robot_hand

__all__ = [
    "SimConfigError",
    "TOP_KEYS",
    "SECTION_KEYS",
    "OBJECT_KEYS",
    "NO_OBJECT",
    "PARAM_ALIASES",
    "world_config_from_dict",
    "world_config_from_layers",
    "load_world_config",
    "load_sim_yaml",
    "scenario_world_overrides",
    "world_overrides_from_params",
    "default_sim_yaml",
    "describe",
]

Layer = Tuple[Mapping[str, Any], str]  # (settings, where they come from)

#: The value of ``object`` that means "nothing to grasp" (YAML ``null`` means the same).
NO_OBJECT = "none"

_ARM_KEYS = ("start_position_m", "start_orientation_xyzw", "workspace_min_m", "workspace_max_m", "timeout_s",
             "controller")
_HAND_KEYS = tuple(f.name for f in dataclasses.fields(HandParams))
_AttachmentKey = Literal["piston_travel_m", "spring_n_per_m"]
_ATTACHMENT_KEYS: Tuple[_AttachmentKey, ...] = ("piston_travel_m", "spring_n_per_m")
_BOARD_KEYS = ("rate_hz", "noise_counts", "seed")

#: The sections (mappings) and the keys each one takes.
SECTION_KEYS: Dict[str, Tuple[str, ...]] = {
    "arm": _ARM_KEYS,
    "hand": _HAND_KEYS,
    "attachment": _ATTACHMENT_KEYS,
    "board": _BOARD_KEYS,
}
#: Every top-level key of sim.yaml (and of a scenario's ``world:``).
TOP_KEYS: Tuple[str, ...] = ("robot", "object", "object_xy_m", "table_z_m", "capture_radius_m") + tuple(SECTION_KEYS)
#: The keys of a custom object (the fields of GraspObject).
OBJECT_KEYS: Tuple[str, ...] = tuple(f.name for f in dataclasses.fields(GraspObject))
_OBJECT_REQUIRED = ("width_m", "stiffness_n_per_m", "mass_kg", "friction_coefficient")

#: Flat private parameters of the node that set one key of a section.
PARAM_ALIASES: Dict[str, Tuple[str, str]] = {
    "board_rate_hz": ("board", "rate_hz"),
    "noise_counts": ("board", "noise_counts"),
    "board_seed": ("board", "seed"),
    "arm_timeout_s": ("arm", "timeout_s"),
    "initial_width_m": ("hand", "initial_width_m"),
}

# What a number means, for messages (the unit is in every key's name).
_MEANING: Dict[str, str] = {
    "table_z_m": "height of the table top in m",
    "capture_radius_m": "horizontal capture radius in m",
    "arm.timeout_s": "seconds without a velocity command before the arm stops",
    "board.rate_hz": f"samples per second; 100 recommended, {HANDOUT_FIRMWARE_RATE_HZ:.3f} = the handout's 300 ms",
    "board.noise_counts": "standard deviation of the ADC noise in counts",
    "attachment.piston_travel_m": "how far the relaxed piston sticks out, m",
    "attachment.spring_n_per_m": "piston spring stiffness in N/m",
}
_VECTOR_EXAMPLE: Dict[str, str] = {
    "object_xy_m": "[0.4, 0.0] (or null: below the start pose)",
    "arm.start_position_m": "[0.4, 0.0, 0.4867]",
    "arm.start_orientation_xyzw": "[1.0, 0.0, 0.0, 0.0] (pointing down)",
    "arm.workspace_min_m": "[0.3, -0.25, 0.015]",
    "arm.workspace_max_m": "[0.55, 0.25, 0.55]",
}


class SimConfigError(HriTeleopError, ValueError):
    """The simulation settings are unreadable or have a bad key/value (one line with the file and the fix)."""


class _AttachmentFields(TypedDict, total=False):
    """The :class:`Attachment` fields that sim.yaml may set (``_ATTACHMENT_KEYS``)."""

    piston_travel_m: float
    spring_n_per_m: float


# --------------------------------------------------------------------------- reading files


def load_sim_yaml(path: Union[str, Path]) -> Dict[str, Any]:
    """The top-level mapping of a sim.yaml (``{}`` for an empty file); SimConfigError otherwise."""
    data = read_yaml(path, SimConfigError, missing_fix="check the path (the lab's is hri_lab/config/sim.yaml)")
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise SimConfigError(f"{path}: the top level is a {type(data).__name__}, not a mapping; "
                             "write `key: value` lines (object: egg, board: {rate_hz: 100.0}, ...)")
    return data


def scenario_world_overrides(path: Union[str, Path]) -> Dict[str, Any]:
    """A scenario file's ``world:`` mapping (``{}`` when it has none).

    A scenario is ``{description: ..., world: {...}, expect: {...}, steps: [...]}``; only ``world`` is read
    here (its keys are sim.yaml's and are checked when the layers are built), the steps
    belong to the virtual pad.  A plain pad script (a list of steps) has no world: ``{}``.
    """
    data = read_yaml(path, SimConfigError, what="scenario file",
                     missing_fix="check the path (the lab's scenarios are in hri_lab/scenarios/; "
                                 "roslaunch needs an absolute path)")
    if data is None or isinstance(data, list):
        return {}
    if not isinstance(data, dict):
        raise SimConfigError(f"{path}: the top level is a {type(data).__name__}; a scenario is a mapping "
                             "with description, world and steps")
    world = data.get("world")
    if world is None:
        return {}
    if not isinstance(world, dict):
        raise SimConfigError(f"{path}: world must be a mapping of sim.yaml keys, got {world!r}; "
                             "write e.g. `world: {object: egg}`")
    return world


def default_sim_yaml() -> Optional[Path]:
    """hri_lab/config/sim.yaml beside this package in a source checkout, or None.

    The node looks the package up with rospkg first; this is for scripts and notebooks
    that run from the repository.
    """
    path = LAB_CONFIG / "sim.yaml"
    return path if path.is_file() else None


# --------------------------------------------------------------------------- layers


def _unknown(key: str, where: str, valid: Sequence[str], source: str) -> SimConfigError:
    close = difflib.get_close_matches(key, list(valid), n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return SimConfigError(f"{source}: unknown key '{where}{key}'; {hint}valid keys are {', '.join(valid)}")


def _check_layer(data: Mapping[str, Any], source: str) -> None:
    """Keys and section shapes of one layer (values are checked once the layers are merged)."""
    if not isinstance(data, Mapping):
        raise SimConfigError(f"{source}: expected a mapping of sim.yaml keys, got {type(data).__name__}; "
                             "write `key: value` lines")
    for key in data:
        if key not in TOP_KEYS:
            raise _unknown(str(key), "", TOP_KEYS, source)
    for section, keys in SECTION_KEYS.items():
        if section not in data:
            continue
        value = data[section]
        if value is None:
            continue
        if not isinstance(value, Mapping):
            raise SimConfigError(f"{source}: {section} must be a mapping, got {value!r}; "
                                 f"write e.g. {section}: {{{keys[0]}: ...}}")
        for key in value:
            if key not in keys:
                raise _unknown(str(key), f"{section}.", keys, source)


def _merge(layers: Sequence[Layer]) -> Tuple[Dict[str, Any], Dict[str, str]]:
    """The layers merged (sections key by key, the rest whole) and which source set each key."""
    merged: Dict[str, Any] = {}
    origin: Dict[str, str] = {}
    for data, source in layers:
        for key, value in data.items():
            if key in SECTION_KEYS:
                section = merged.setdefault(key, {})
                for sub, sub_value in (value or {}).items():
                    section[sub] = sub_value
                    origin[f"{key}.{sub}"] = source
            else:
                merged[key] = value
                origin[key] = source
    return merged, origin


class _Builder:
    """Builds a WorldConfig from merged settings; every error names the source of its key."""

    def __init__(self, merged: Mapping[str, Any], origin: Mapping[str, str], sources: Sequence[str]) -> None:
        self.merged = merged
        self.origin = origin
        self.sources = list(sources)
        self._robot: Optional[RobotProfile] = None

    # -- where ------------------------------------------------------------------------

    def source_of(self, *keys: str) -> str:
        """The sources that set ``keys`` (a section name covers its keys), else the first layer."""
        found: List[str] = []
        for key in keys:
            for path, source in self.origin.items():
                # the key itself, a key inside a section, or a whole value (object) holding the key
                related = path == key or path.startswith(key + ".") or key.startswith(path + ".")
                if related and source not in found:
                    found.append(source)
        if not found:
            found = self.sources[:1] or ["<defaults>"]
        ordered = [s for s in self.sources if s in found]  # in layer order
        return " and ".join(ordered or found)

    def error(self, key: str, message: str) -> SimConfigError:
        return SimConfigError(f"{self.source_of(key)}: {message}")

    # -- values -----------------------------------------------------------------------

    def number(self, key: str, value: object) -> float:
        if is_finite_number(value):
            return float(value)
        meaning = _MEANING.get(key, "a finite number")
        hint = "write a plain number without quotes"
        if isinstance(value, str):
            try:
                float(value)
            except ValueError:
                pass
            else:
                hint = ("YAML reads this as text: write the number with a dot and a signed exponent "
                        "(1.0e+6) or in full, without quotes")
        raise self.error(key, f"{key} must be a number ({meaning}), got {value!r} of type "
                              f"{type(value).__name__}; {hint}")

    def vector(self, key: str, value: object, length: int) -> Tuple[float, ...]:
        example = _VECTOR_EXAMPLE.get(key, "[" + ", ".join(["0.0"] * length) + "]")
        if not isinstance(value, (list, tuple)) or len(value) != length \
                or not all(is_finite_number(c) for c in value):
            raise self.error(key, f"{key} must be a list of {length} numbers in m, got {value!r}; "
                                  f"write e.g. {key.split('.')[-1]}: {example}")
        return tuple(float(c) for c in value)

    def section(self, name: str) -> Mapping[str, Any]:
        return self.merged.get(name) or {}

    def wrapped(self, section: str, exc: Exception, prefixes: Sequence[str]) -> SimConfigError:
        """A dataclass's error in the file's words: ``HandParams.x ...`` -> ``hand.x ...``."""
        message = str(exc)
        for prefix in prefixes:
            if message.startswith(prefix):
                message = message[len(prefix):]
                break
        keys = SECTION_KEYS.get(section, OBJECT_KEYS)
        first = message.split(" ", 1)[0]
        named = [k for k in keys if f"{section}.{k}" in self.origin and k in message]
        if first in keys:
            return self.error(f"{section}.{first}", f"{section}.{message}")
        return SimConfigError(f"{self.source_of(*([f'{section}.{k}' for k in named] or [section]))}: "
                              f"{section}: {message}")

    # -- the parts --------------------------------------------------------------------

    def object(self) -> Optional[GraspObject]:
        if "object" not in self.merged:
            return None
        value = self.merged["object"]
        if value is None or (isinstance(value, str) and value.strip().lower() == NO_OBJECT):
            return None
        choices = ", ".join(list(OBJECTS) + [NO_OBJECT])
        if isinstance(value, str):
            name = value.strip()
            if name in OBJECTS:
                return OBJECTS[name]
            close = difflib.get_close_matches(name, list(OBJECTS) + [NO_OBJECT], n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise self.error("object", f"unknown object {name!r}; {hint}choose one of {choices}, "
                                       "or give a mapping of GraspObject fields")
        if not isinstance(value, Mapping):
            raise self.error("object", f"object must be a name ({choices}) or a mapping of "
                                       f"{', '.join(OBJECT_KEYS)}, got {value!r}")
        for key in value:
            if key not in OBJECT_KEYS:
                raise _unknown(str(key), "object.", OBJECT_KEYS, self.source_of("object"))
        missing = [k for k in _OBJECT_REQUIRED if k not in value]
        if missing:
            raise self.error("object", f"a custom object needs {', '.join(missing)}; e.g. object: "
                                       "{name: cup, width_m: 0.06, stiffness_n_per_m: 2.0e+4, mass_kg: 0.1, "
                                       "friction_coefficient: 0.5}")
        kwargs: Dict[str, Any] = {k: self.number(f"object.{k}", value[k]) for k in _OBJECT_REQUIRED}
        kwargs["name"] = self.text("object.name", value.get("name", "custom"))
        if value.get("breaking_force_n") is not None:
            kwargs["breaking_force_n"] = self.number("object.breaking_force_n", value["breaking_force_n"])
        if "note" in value:
            kwargs["note"] = self.text("object.note", value["note"], allow_empty=True)
        try:
            return GraspObject(**kwargs)
        except HandSimError as exc:
            raise self.wrapped("object", exc, ("GraspObject.",)) from None

    def text(self, key: str, value: builtins.object, allow_empty: bool = False) -> str:  # the method object() shadows it
        if not isinstance(value, str) or not (allow_empty or value.strip()):
            raise self.error(key, f"{key} must be a {'' if allow_empty else 'non-empty '}string, got {value!r}; "
                                  "write it in quotes, e.g. name: \"cup\"")
        return value.strip()

    def robot(self) -> RobotProfile:
        """``robot:``: a profile's name in hri_teleop/core/robots/ or a YAML path (absent or null: the lab's robot,
        HRI_ROBOT)."""
        if self._robot is None:
            try:
                self._robot = robot_named(self.merged.get("robot"))
            except RobotFileError as exc:
                raise self.error("robot", f"robot: {exc}") from None
        return self._robot

    def arm(self) -> SimArmConfig:
        values = self.section("arm")
        kwargs: Dict[str, Any] = {}
        for key in ("start_position_m", "workspace_min_m", "workspace_max_m"):
            if key in values:
                kwargs[key] = self.vector(f"arm.{key}", values[key], 3)
        if "start_orientation_xyzw" in values:
            kwargs["start_orientation_xyzw"] = self.vector("arm.start_orientation_xyzw",
                                                           values["start_orientation_xyzw"], 4)
        if "timeout_s" in values:
            kwargs["timeout_s"] = self.number("arm.timeout_s", values["timeout_s"])
        if "controller" in values:
            kwargs["controller"] = values["controller"]
        try:
            arm = dataclasses.replace(robot_arm(self.robot()), **kwargs)
        except SimArmError as exc:
            raise self.wrapped("arm", exc, ()) from None
        if arm.joints:
            try:
                start_joints(arm.start_position_m, arm.start_orientation_xyzw, arm.joint_limits, arm.model)
            except KinematicsError as exc:
                if "robot profile" in str(exc):  # its description, not the start pose
                    raise self.error("robot", f"robot: {exc}") from None
                raise SimConfigError(f"{self.source_of('arm.start_position_m')}: arm.start_position_m: {exc}") from None
        return arm

    def hand(self) -> HandParams:
        values = self.section("hand")
        kwargs = {key: self.number(f"hand.{key}", values[key]) for key in _HAND_KEYS if key in values}
        try:
            return robot_hand(self.robot(), **kwargs)
        except HandSimError as exc:
            raise self.wrapped("hand", exc, ("HandParams.",)) from None

    def attachment(self) -> Attachment:
        values = self.section("attachment")
        kwargs: _AttachmentFields = {}
        for key in _ATTACHMENT_KEYS:
            if key in values:
                kwargs[key] = self.number(f"attachment.{key}", values[key])
        try:
            return Attachment(**kwargs)
        except AttachmentError as exc:
            raise self.wrapped("attachment", exc, ("Attachment.",)) from None

    def board(self) -> BoardConfig:
        values = self.section("board")
        kwargs: Dict[str, Any] = {}
        for key in ("rate_hz", "noise_counts"):
            if key in values:
                kwargs[key] = self.number(f"board.{key}", values[key])
        if "seed" in values:
            seed = values["seed"]
            if seed is not None and not is_int(seed):
                raise self.error("board.seed", f"board.seed must be an integer or null, got {seed!r}; "
                                               "e.g. seed: 0 (repeatable noise) or seed: null (different every run)")
            kwargs["seed"] = None if seed is None else int(seed)
        try:
            return BoardConfig(**kwargs)
        except BoardError as exc:
            raise self.wrapped("board", exc, ("sensor board ",)) from None

    def world(self) -> WorldConfig:
        kwargs: Dict[str, Any] = {
            "arm": self.arm(),
            "hand": self.hand(),
            "attachment": self.attachment(),
            "board": self.board(),
            "object": self.object(),
            "robot": self.robot(),
        }
        merged = self.merged
        if merged.get("object_xy_m") is not None:
            kwargs["object_xy_m"] = self.vector("object_xy_m", merged["object_xy_m"], 2)
        for key in ("table_z_m", "capture_radius_m"):
            if key in merged:
                kwargs[key] = self.number(key, merged[key])
        try:
            return WorldConfig(**kwargs)
        except WorldError as exc:
            message = str(exc)
            named = [k for k in ("capture_radius_m", "table_z_m", "object_xy_m") if message.startswith(k)]
            if named:
                raise self.error(named[0], message) from None
            # the table against the workspace floor: both may be to blame
            raise SimConfigError(f"{self.source_of('table_z_m', 'arm.workspace_min_m')}: {message}") from None


def world_config_from_layers(layers: Sequence[Layer]) -> WorldConfig:
    """Check each layer's keys, merge them, build and check the WorldConfig.

    A later layer replaces single keys of the ones before (``arm``, ``hand``, ``attachment``
    and ``board`` key by key, ``object`` as a whole); an error names the layer that set the key.
    """
    used: List[Layer] = []
    for data, source in layers:
        _check_layer(data, source)
        used.append((data, source))
    merged, origin = _merge(used)
    return _Builder(merged, origin, [source for _, source in used]).world()


def world_config_from_dict(data: Mapping[str, Any], source: str = "<dict>") -> WorldConfig:
    """Check one settings mapping (sim.yaml's keys) and build the WorldConfig; errors name ``source``."""
    return world_config_from_layers([(data, source)])


def load_world_config(path: Union[str, Path], overrides: Optional[Mapping[str, Any]] = None,
                      source: str = "overrides", scenario: Union[str, Path, None] = None) -> WorldConfig:
    """sim.yaml at ``path``, then a scenario's ``world:`` (if ``scenario``), then ``overrides``.

    ``overrides`` has sim.yaml's keys (e.g. from :func:`world_overrides_from_params`) and
    is named ``source`` in errors.  An empty ``path`` means no file: the defaults.
    """
    layers: List[Layer] = []
    if str(path):
        layers.append((load_sim_yaml(path), str(path)))
    if scenario is not None and str(scenario):
        layers.append((scenario_world_overrides(scenario), f"{scenario} (world:)"))
    if overrides:
        layers.append((overrides, source))
    return world_config_from_layers(layers)


def world_overrides_from_params(params: Mapping[str, Any], source: str,
                                node_keys: Sequence[str] = ()) -> Dict[str, Any]:
    """A node's private parameters as sim.yaml overrides.

    ``node_keys`` are the node's own parameters (skipped).  Top-level keys pass as they are
    (``~object: sponge``, ``~arm: {timeout_s: 0.2}``), :data:`PARAM_ALIASES` set one key of
    a section (``~board_rate_hz: 3.333``).  Anything else is a typo: SimConfigError with the
    closest valid name.
    """
    out: Dict[str, Any] = {}
    valid = sorted(set(TOP_KEYS) - set(node_keys)) + sorted(PARAM_ALIASES)
    for key, value in params.items():
        if key in node_keys:
            continue
        if key in PARAM_ALIASES:
            section, sub = PARAM_ALIASES[key]
            existing = out.get(section)
            if existing is not None and not isinstance(existing, dict):
                raise SimConfigError(f"{source}: {section} must be a mapping, got {existing!r}; "
                                     f"set single keys with ~{key} or write {section}: {{{sub}: ...}}")
            out.setdefault(section, {})[sub] = value
        elif key in TOP_KEYS and key not in node_keys:
            if key in SECTION_KEYS and isinstance(value, Mapping):
                section = out.setdefault(key, {})
                for sub, sub_value in value.items():
                    section.setdefault(sub, sub_value)  # an alias given too wins
            else:
                out[key] = value
        else:
            close = difflib.get_close_matches(str(key), list(node_keys) + valid, n=1)
            hint = f"did you mean ~{close[0]}? " if close else ""
            raise SimConfigError(f"{source}: unknown parameter ~{key}; {hint}the simulation's parameters are "
                                 f"{', '.join('~' + k for k in list(node_keys) + valid)}")
    return out


def describe(config: WorldConfig) -> str:
    """One line for a log: the object, where it is, and the board."""
    obj = config.object
    if obj is None:
        what = "no object"
    else:
        breaks = f", breaks above {obj.breaking_force_n:g} N" if obj.breaking_force_n is not None else ""
        where = ("right below the start pose" if config.object_xy_m is None
                 else f"at ({config.object_xy_m[0]:g}, {config.object_xy_m[1]:g}) m")
        what = f"{obj.name} ({obj.width_m * 1000:g} mm, {obj.mass_kg * 1000:g} g{breaks}) {where}"
    board = config.board
    period_ms = 1000.0 / board.rate_hz
    start = config.arm.start_position_m
    robot = f"robot {config.robot.name}; "
    return (f"{robot}{what}; arm starts at ({start[0]:g}, {start[1]:g}, {start[2]:g}) m, command timeout "
            f"{config.arm.timeout_s:g} s; sensor board {board.rate_hz:g} Hz ({period_ms:.4g} ms), noise "
            f"{board.noise_counts:g} counts; piston {config.attachment.piston_travel_m * 1000:g} mm, "
            f"full travel {config.attachment.full_travel_count} counts")

