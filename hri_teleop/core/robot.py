"""The robot the lab drives, as one typed profile: limits, joints, kinematics, gripper, topics, error names.

Built from a robot profile YAML (:mod:`hri_teleop.core.robot_file` reads and checks it). The
Panda's (:data:`PANDA`) is the default everywhere; the simulation takes another with sim.yaml's
``robot:``, so a lab with another arm or hand edits a file, not the code.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Tuple, Union

from hri_teleop.core.joints import JointLimits, JointVector
from hri_teleop.core.limits import AxisLimits, CartesianLimits
from hri_teleop.core.robot_file import PANDA_FILE, RobotFile, RobotFileError, panda_file, read_robot_file

__all__ = ["GripperProfile", "RobotProfile", "PANDA", "ROBOTS", "load_robot_profile", "robot_named", "RobotFileError"]


@dataclass(frozen=True)
class GripperProfile:
    """The hand: its action server's namespace and actions, its finger joints and its range."""

    namespace: str
    actions: Tuple[str, ...]
    finger_joints: Tuple[str, str]
    max_width_m: float
    max_speed_m_per_s: float
    max_force_n: float


@dataclass(frozen=True)
class RobotProfile:
    """One robot profile file, typed; ``sources`` says where each section's numbers come from."""

    name: str
    description: str
    cartesian_limits: CartesianLimits
    joint_names: Tuple[str, ...]
    joint_limits: JointLimits
    ready_pose_rad: JointVector
    urdf: str
    tool_frame: str
    elbow_joint: int
    gripper: GripperProfile
    topics: Dict[str, str]
    cartesian_errors: Dict[str, str]
    joint_errors: Dict[str, str]
    non_finite_error: str
    sources: Dict[str, str]
    path: str = ""

    @classmethod
    def from_file(cls, data: RobotFile, path: str = "") -> "RobotProfile":
        joints, kin, grip, errors = data["joints"], data["kinematics"], data["gripper"], data["errors"]
        limits = data["cartesian_limits"]
        return cls(
            name=data["name"], description=data["description"],
            cartesian_limits=CartesianLimits(AxisLimits(**limits["translation"]), AxisLimits(**limits["rotation"])),
            joint_names=joints["names"],
            joint_limits=JointLimits(**{k: joints[k] for k in ("position_min_rad", "position_max_rad",
                                                                "velocity_rad_per_s", "acceleration_rad_per_s2",
                                                                "jerk_rad_per_s3")}),
            ready_pose_rad=joints["ready_pose_rad"], urdf=kin["urdf"], tool_frame=kin["tool_frame"],
            elbow_joint=kin["elbow_joint"],
            gripper=GripperProfile(grip["namespace"], grip["actions"], grip["finger_joints"], grip["max_width_m"],
                                   grip["max_speed_m_per_s"], grip["max_force_n"]),
            topics={k: v for k, v in data["topics"].items() if k != "source"},
            cartesian_errors=dict(errors["cartesian"]), joint_errors=dict(errors["joint"]),
            non_finite_error=errors["non_finite"],
            sources={section: str(data[section].get("source", "")) for section in
                     ("cartesian_limits", "joints", "kinematics", "gripper", "topics", "errors")},
            path=path)


def load_robot_profile(path: Union[str, Path]) -> RobotProfile:
    """The profile at ``path`` (RobotFileError: one line naming the file, the key and the fix)."""
    return RobotProfile.from_file(read_robot_file(path), str(path))


#: The lab's robot: the Franka Emika Panda with the Franka Hand (core/robots/franka_panda.yaml).
PANDA = RobotProfile.from_file(panda_file(), str(PANDA_FILE))

#: Where a profile given by name (``robot: franka_panda``) is looked up.
ROBOTS = PANDA_FILE.parent


def robot_named(value: object) -> RobotProfile:
    """``value`` as sim.yaml and teleop.yaml write it: None (the Panda), a profile's name in
    :data:`ROBOTS` or the path of a profile YAML (RobotFileError otherwise, in one line)."""
    if value is None:
        return PANDA
    if not isinstance(value, str) or not value.strip():
        raise RobotFileError(f"robot must be a profile's name (e.g. {PANDA.name}) or a path to one, got {value!r}")
    text = value.strip()
    path = ROBOTS / f"{text}.yaml" if "/" not in text and not text.endswith(".yaml") else Path(text).expanduser()
    return PANDA if path.resolve() == PANDA_FILE else load_robot_profile(path)
