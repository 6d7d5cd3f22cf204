"""The robot the lab drives, as one typed profile: limits, joints, kinematics, gripper, topics, error names.

Built from a robot profile YAML (:mod:`hri_teleop.core.robot_file` reads and checks it). The lab's robot
(:data:`LAB_ROBOT`) is chosen once, by ``HRI_ROBOT`` (``fr3``: the Franka Research 3; unset: the Panda), and is
the default everywhere; a sim.yaml or teleop.yaml may still name another with ``robot:``, so a lab with
another arm or hand edits a file, not the code.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Tuple, Union

from hri_teleop.core.joints import JointLimits, JointVector
from hri_teleop.core.limits import AxisLimits, CartesianLimits
from hri_teleop.core.robot_file import (
    ROBOTS_DIR,
    RobotFile,
    RobotFileError,
    lab_robot_file,
    lab_robot_path,
    read_robot_file,
    robot_path,
)

__all__ = ["GripperProfile", "RobotProfile", "LAB_ROBOT", "ROBOTS", "load_robot_profile", "robot_named",
           "RobotFileError"]


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
    urdf_joint_names: Tuple[str, ...]   # the arm's joints as the URDF names them (joint_names on the topics)
    urdf_finger_joints: Tuple[str, ...]
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
            elbow_joint=kin["elbow_joint"], urdf_joint_names=kin["urdf_joint_names"],
            urdf_finger_joints=kin["urdf_finger_joints"],
            gripper=GripperProfile(grip["namespace"], grip["actions"], grip["finger_joints"], grip["max_width_m"],
                                   grip["max_speed_m_per_s"], grip["max_force_n"]),
            topics={k: v for k, v in data["topics"].items() if k != "source"},
            cartesian_errors=dict(errors["cartesian"]), joint_errors=dict(errors["joint"]),
            non_finite_error=errors["non_finite"],
            sources={section: data[section]["source"] for section in
                     ("cartesian_limits", "joints", "kinematics", "gripper", "topics", "errors")},
            path=path)


def load_robot_profile(path: Union[str, Path]) -> RobotProfile:
    """The profile at ``path`` (RobotFileError: one line naming the file, the key and the fix)."""
    return RobotProfile.from_file(read_robot_file(path), str(path))


#: The lab's robot, as ``HRI_ROBOT`` chooses it (unset: the Franka Emika Panda with the Franka Hand).
LAB_ROBOT = RobotProfile.from_file(lab_robot_file(), str(lab_robot_path()))

#: Where a profile given by name (``robot: franka_panda``, ``robot: fr3``) is looked up.
ROBOTS = ROBOTS_DIR


def robot_named(value: object) -> RobotProfile:
    """``value`` as sim.yaml and teleop.yaml write it: None (the lab's robot, :data:`LAB_ROBOT`), a profile's
    name in :data:`ROBOTS` or the path of a profile YAML (RobotFileError otherwise, in one line)."""
    if value is None:
        return LAB_ROBOT
    if not isinstance(value, str) or not value.strip():
        raise RobotFileError(f"robot must be a profile's name (e.g. franka_panda, fr3) or a path to one, got {value!r}")
    path = robot_path(value)
    return LAB_ROBOT if path.resolve() == lab_robot_path().resolve() else load_robot_profile(path)
