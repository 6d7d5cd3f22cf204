"""A robot profile file, read and checked: the robot the lab drives in one YAML (``core/robots/``).

The lab's robot is chosen once, by ``HRI_ROBOT`` (a profile's name in ``core/robots/``, e.g. ``fr3``, or
a path; unset: the Panda), and read here once per process (:func:`lab_robot_file`): the core's limits,
joints, gripper and reflex names take their values from it. This module only turns the file into
checked plain values (numbers, tuples, strings), so that ``limits``, ``joints`` and ``reflex`` can take
their defaults from it without importing each other; :mod:`hri_teleop.core.robot` builds the typed
profile the rest uses.
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path
from typing import Any, Dict, Mapping, Tuple, Union

from hri_teleop.core.checks import is_finite_number, is_int
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.yamlfile import read_yaml

__all__ = ["RobotFileError", "PANDA_FILE", "ROBOTS_DIR", "ROBOT_ENV", "RobotFile", "read_robot_file", "panda_file",
           "robot_path", "lab_robot_path", "lab_robot_file"]

#: Where the shipped profiles are; a profile given by name (``fr3``) is ``<name>.yaml`` here.
ROBOTS_DIR = Path(__file__).resolve().parent / "robots"
#: The default robot: the Franka Emika Panda with its Franka Hand.
PANDA_FILE = ROBOTS_DIR / "franka_panda.yaml"
#: The variable that chooses the lab's robot for every process (a profile's name or a path; unset: the Panda).
ROBOT_ENV = "HRI_ROBOT"

#: What a profile holds: section -> key -> kind ("number", "positive", "name", "numbers:N", "positives:N",
#: "names:N", "names", "int"). Keys named ``source`` (where the numbers come from) are free text.
SHAPE: Dict[str, Dict[str, str]] = {
    "cartesian_limits": {"translation": "axis", "rotation": "axis"},
    "joints": {"names": "names:7", "position_min_rad": "numbers:7", "position_max_rad": "numbers:7",
               "velocity_rad_per_s": "positives:7", "acceleration_rad_per_s2": "positives:7",
               "jerk_rad_per_s3": "positives:7", "ready_pose_rad": "numbers:7"},
    "kinematics": {"urdf": "name", "tool_frame": "name", "elbow_joint": "int", "urdf_joint_names": "names:7",
                   "urdf_finger_joints": "names:2"},
    "gripper": {"namespace": "name", "actions": "names", "finger_joints": "names:2", "max_width_m": "positive",
                "max_speed_m_per_s": "positive", "max_force_n": "positive"},
    "topics": {"twist_command": "name", "arm_joint_states": "name", "robot_state": "name", "error_recovery": "name"},
    "errors": {"cartesian": "errors:velocity,acceleration,jerk", "joint": "errors:position,velocity,acceleration,jerk",
               "non_finite": "name"},
}
AXIS_KEYS = ("velocity", "acceleration", "jerk")
#: Keys a profile may leave out, and whose value stands in for them: the URDF names its joints as the robot's
#: topics do unless it says otherwise (the FR3's profile reuses the Panda's URDF).
OPTIONAL: Dict[str, Dict[str, Tuple[str, str]]] = {
    "kinematics": {"urdf_joint_names": ("joints", "names"), "urdf_finger_joints": ("gripper", "finger_joints")},
}

#: section -> key -> checked value
RobotFile = Dict[str, Any]


class RobotFileError(HriTeleopError, ValueError):
    """A robot profile file is missing, malformed or holds a value of the wrong kind (one line, file and key)."""


def _value(source: str, where: str, kind: str, value: object) -> Any:
    def bad(expected: str) -> RobotFileError:
        return RobotFileError(f"{source}: {where} must be {expected}, got {value!r}; "
                              f"see {PANDA_FILE.name} (the Panda's profile) for the shape")

    if kind in ("number", "positive"):
        if not is_finite_number(value) or (kind == "positive" and not value > 0):
            raise bad("a positive number" if kind == "positive" else "a number")
        return float(value)
    if kind == "int":
        if not is_int(value) or not value >= 1:
            raise bad("a whole number from 1")
        return int(value)
    if kind == "name":
        if not isinstance(value, str) or not value.strip():
            raise bad("a name (text)")
        return value.strip()
    if kind == "axis":
        if not isinstance(value, Mapping) or set(value) != set(AXIS_KEYS):
            raise bad("{velocity: V, acceleration: A, jerk: J}")
        return {k: _value(source, f"{where}.{k}", "positive", value[k]) for k in AXIS_KEYS}
    if kind.startswith("errors:"):
        keys = kind[len("errors:"):].split(",")
        if not isinstance(value, Mapping) or set(value) != set(keys):
            raise bad("{" + ", ".join(f"{k}: NAME" for k in keys) + "}")
        return {k: _value(source, f"{where}.{k}", "name", value[k]) for k in keys}
    item, _, count = kind.partition(":")
    if not isinstance(value, (list, tuple)) or (count and len(value) != int(count)) or not value:
        raise bad(f"a list of {count or 'one or more'} {item}")
    single = {"numbers": "number", "positives": "positive", "names": "name"}[item]
    return tuple(_value(source, f"{where}[{i}]", single, v) for i, v in enumerate(value))


def read_robot_file(path: Union[str, Path]) -> RobotFile:
    """The profile at ``path``, every value checked (RobotFileError names the file and the key)."""
    source = str(path)
    content = read_yaml(path, RobotFileError, what="robot profile",
                        missing_fix=f"give the path of a robot profile YAML, e.g. {PANDA_FILE}")
    if not isinstance(content, Mapping):
        raise RobotFileError(f"{source}: a robot profile is a mapping of sections ({', '.join(SHAPE)}); "
                             f"see {PANDA_FILE.name}")
    known = set(SHAPE) | {"name", "description"}
    unknown = sorted(str(k) for k in content if k not in known)
    if unknown:
        raise RobotFileError(f"{source}: unknown section {unknown[0]!r}; the sections are name, description, "
                             f"{', '.join(SHAPE)}")
    out: RobotFile = {"name": _value(source, "name", "name", content.get("name")),
                      "description": str(content.get("description", ""))}
    for section, keys in SHAPE.items():
        given = content.get(section)
        if not isinstance(given, Mapping):
            raise RobotFileError(f"{source}: section {section!r} is missing or not a mapping; "
                                 f"see {PANDA_FILE.name} for its keys ({', '.join(keys)})")
        extra = sorted(str(k) for k in given if k not in keys and k != "source")
        if extra:
            raise RobotFileError(f"{source}: {section}.{extra[0]} is not a key of {section} "
                                 f"(its keys: {', '.join(keys)})")
        values: Dict[str, Any] = {"source": str(given.get("source", ""))}
        for key, kind in keys.items():
            if key not in given:
                if key in OPTIONAL.get(section, {}):
                    continue
                raise RobotFileError(f"{source}: {section}.{key} is missing; see {PANDA_FILE.name}")
            values[key] = _value(source, f"{section}.{key}", kind, given[key])
        out[section] = values
    for section, defaults in OPTIONAL.items():
        for key, (other, other_key) in defaults.items():
            out[section].setdefault(key, out[other][other_key])
    low, high = out["joints"]["position_min_rad"], out["joints"]["position_max_rad"]
    for j, (a, b) in enumerate(zip(low, high), start=1):
        if not a < b:
            raise RobotFileError(f"{source}: joint {j}: position_min_rad {a:g} must be below position_max_rad {b:g}")
    if not out["kinematics"]["elbow_joint"] <= len(out["joints"]["names"]):
        raise RobotFileError(f"{source}: kinematics.elbow_joint {out['kinematics']['elbow_joint']} is not a joint "
                             f"(1..{len(out['joints']['names'])})")
    return out


@lru_cache(maxsize=1)
def panda_file() -> RobotFile:
    """The Panda's profile, read once (the defaults of the core's limits, joints and reflex names)."""
    return read_robot_file(PANDA_FILE)


def robot_path(value: str) -> Path:
    """The profile ``value`` names: a name (``fr3``: ``core/robots/fr3.yaml``) or the path of a profile YAML."""
    text = value.strip()
    if "/" not in text and not text.endswith((".yaml", ".yml")):
        return ROBOTS_DIR / f"{text}.yaml"
    return Path(text).expanduser()


def lab_robot_path() -> Path:
    """The lab's robot as ``HRI_ROBOT`` chooses it (unset or empty: the Panda's profile)."""
    value = os.environ.get(ROBOT_ENV, "").strip()
    if not value:
        return PANDA_FILE
    path = robot_path(value)
    if not path.is_file():
        shipped = ", ".join(sorted(p.stem for p in ROBOTS_DIR.glob("*.yaml")))
        raise RobotFileError(f"{ROBOT_ENV}={value}: no such robot profile ({path}); name one of {shipped} "
                             "or give the path of a profile YAML")
    return path


@lru_cache(maxsize=1)
def lab_robot_file() -> RobotFile:
    """The lab's robot's profile (``HRI_ROBOT``), read once per process: what the core's constants hold."""
    path = lab_robot_path()
    return panda_file() if path.resolve() == PANDA_FILE.resolve() else read_robot_file(path)
