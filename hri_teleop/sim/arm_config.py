"""What the simulated arm (the Panda or the FR3, as its profile says) is told and what it reports: its settings, limit violations and events.

:class:`SimArmConfig` holds every number the arm judges with and where it starts; the records are
what a node logs or a test inspects. The arm itself: :mod:`hri_teleop.sim.arm`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Iterable, Optional, Tuple

from hri_teleop.core.checks import is_finite_number, is_positive_number
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.joints import ROBOT_JOINT_LIMITS, JointLimits
from hri_teleop.core.limits import ROBOT_LIMITS, AxisLimits, CartesianLimits, LimitsError, TwistLimiter, Vec3
from hri_teleop.core.reflex import (
    CARTESIAN_ACCELERATION_DISCONTINUITY as ACCELERATION_DISCONTINUITY,
)
from hri_teleop.core.reflex import (
    CARTESIAN_VELOCITY_DISCONTINUITY as VELOCITY_DISCONTINUITY,
)
from hri_teleop.core.reflex import (
    CARTESIAN_VELOCITY_LIMITS_VIOLATION as VELOCITY_LIMITS_VIOLATION,
)
from hri_teleop.core.reflex import NON_FINITE_COMMAND, ReflexCause
from hri_teleop.core.robot import LAB_ROBOT, RobotProfile

__all__ = [
    "ArmModel", "ROBOT_MODEL", "SimArmError", "SimArmConfig", "LimitViolation", "ArmEvent", "ArmPose", "VELOCITY_LIMITS_VIOLATION",
    "VELOCITY_DISCONTINUITY", "ACCELERATION_DISCONTINUITY", "NON_FINITE_COMMAND", "LIBFRANKA_ERROR_FOR",
    "CONTROLLERS", "GENTLE_STOP_LIMITS", "STATE_IDLE", "STATE_MOVING", "STATE_TIMEOUT", "STATE_REFLEX", "EVENT_REFLEX", "EVENT_TIMEOUT",
    "EVENT_WORKSPACE", "EVENT_RECOVERED", "EVENT_IGNORED", "AXES",
]

@dataclass(frozen=True)
class ArmModel:
    """Which arm description the simulation loads (a robot profile's ``kinematics``): the URDF's path
    inside example-robot-data, the frame the commands move, the joint (0-based) the IK keeps still,
    and the arm's and the fingers' joint names as the URDF names them."""

    urdf: str
    tool_frame: str
    elbow_index: int
    joint_names: Tuple[str, ...]
    finger_joints: Tuple[str, ...]

    @classmethod
    def of(cls, robot: RobotProfile) -> "ArmModel":
        return cls(robot.urdf, robot.tool_frame, robot.elbow_joint - 1, robot.urdf_joint_names, robot.urdf_finger_joints)


#: The lab's robot's (HRI_ROBOT), from its profile.
ROBOT_MODEL = ArmModel.of(LAB_ROBOT)

#: Which libfranka error a violated Cartesian limit raises, keyed by the limit's name in AxisLimits.
LIBFRANKA_ERROR_FOR: Dict[str, str] = {
    "velocity": VELOCITY_LIMITS_VIOLATION,
    "acceleration": VELOCITY_DISCONTINUITY,
    "jerk": ACCELERATION_DISCONTINUITY,
}
#: The controller's ramp to zero after a command timeout: smooth enough for the joints too (the
#: robot's own Cartesian limits would stop in a few ms, a jerk its IK turns into a joint reflex).
GENTLE_STOP_LIMITS = CartesianLimits(AxisLimits(ROBOT_LIMITS.translation.velocity, 1.0, 100.0),
                                     AxisLimits(ROBOT_LIMITS.rotation.velocity, 2.0, 200.0))
#: What the lab's velocity controller does between two commands (see SimArmConfig.controller).
CONTROLLERS = ("interpolate", "hold")

STATE_IDLE = "idle"
STATE_MOVING = "moving"
STATE_TIMEOUT = "timeout"
STATE_REFLEX = "reflex"

EVENT_REFLEX = "reflex"
EVENT_TIMEOUT = "command timeout"
EVENT_WORKSPACE = "workspace limit"
EVENT_RECOVERED = "recovered"
EVENT_IGNORED = "command ignored"

AXES = "xyz"


class SimArmError(HriTeleopError, ValueError):
    """A configuration value, a command or a time the simulated arm cannot take; the message names the fix."""


@dataclass(frozen=True)
class LimitViolation:
    """One broken limit in one 1 ms cycle: ``group`` is "translation", "rotation" (m/s^k, rad/s^k of the
    twist) or "joint 1" .. "joint 7" (rad, rad/s^k of that joint)."""

    time_s: float
    error: str
    group: str
    value: float
    limit: float

    def cause(self) -> ReflexCause:
        """The violation as :mod:`hri_teleop.core.reflex` explains it."""
        return ReflexCause(self.error, self.group, self.value, self.limit)


@dataclass(frozen=True)
class ArmEvent:
    """Something the arm reports once when it happens (kind is one of the ``EVENT_*`` strings)."""

    time_s: float
    kind: str
    message: str


@dataclass(frozen=True)
class ArmPose:
    """End-effector pose in the base frame: position in m, orientation as a unit quaternion (x, y, z, w)."""

    position_m: Vec3
    orientation_xyzw: Tuple[float, float, float, float]


def _vector(name: str, value: object, length: int) -> Tuple[float, ...]:
    try:
        items: Tuple[object, ...] = tuple(value) if isinstance(value, Iterable) else ()
    except TypeError:
        items = ()
    numbers = tuple(float(c) for c in items if is_finite_number(c, numpy=True))
    if len(items) != length or len(numbers) != length:
        raise SimArmError(f"{name} must be {length} finite numbers, got {value!r}")
    return numbers


@dataclass(frozen=True)
class SimArmConfig:
    """What the simulated arm judges against and where it starts; every number has a reason.

    * ``limits``: the robot's Cartesian limits (docs/lab-facts.md), judged every 1 ms.
    * ``timeout_s`` 0.1 s: the teleoperation node publishes at 50 Hz, so this is five
      missed messages -- long enough for a busy laptop, short enough that a dead node
      stops the arm within a tenth of a second.
    * ``workspace_min_m`` / ``workspace_max_m``: a box in the base frame in front of the
      Panda, inside its reach (about 0.855 m) and above the table, with room for a
      gripper at the ready pose.
    * ``start_position_m`` / ``start_orientation_xyzw``: the Panda's "ready" pose
      (joints 0, -pi/4, 0, -3pi/4, 0, pi/2, pi/4), the end effector pointing down:
      a rotation of pi about x, quaternion (1, 0, 0, 0).
    * ``stop_limits``: the ramp to zero after a timeout (:data:`GENTLE_STOP_LIMITS`: from 0.1 m/s
      in about 0.11 s); ``None`` means ``limits``, the fastest stop the Cartesian judge allows.
    * ``rel_tol``: relative tolerance of the judge, as ``limit_violations``'s.
    * ``joint_limits``: the Panda's joint limits, judged every 1 ms after the robot's IK.
    * ``controller``: what the lab's velocity controller does between two commands:
      ``"interpolate"`` moves to the new one over the time since the one before (the robot
      sees no steps; a step still reaches the joints as a jerk), ``"hold"`` keeps the last one
      until the next (each change reaches the robot as a step within 1 ms).
    * ``command_period_s`` 0.02 s: the shortest interpolation (the teleoperation node's 50 Hz),
      and the first after rest; slower commands are interpolated over their interval (up to 0.1 s).
    * ``joints`` True: the seven joints move and are judged; False leaves the hand alone,
      judged on its twist only (tests of the Cartesian judge, scenes far outside the reach).
    * ``model``: the arm description the joints follow (the robot profile's kinematics).
    """

    limits: CartesianLimits = ROBOT_LIMITS
    timeout_s: float = 0.1
    workspace_min_m: Vec3 = (0.2, -0.5, 0.05)
    workspace_max_m: Vec3 = (0.8, 0.5, 0.8)
    start_position_m: Vec3 = (0.3069, 0.0, 0.4867)
    start_orientation_xyzw: Tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    stop_limits: Optional[CartesianLimits] = GENTLE_STOP_LIMITS
    rel_tol: float = 1e-9
    joint_limits: JointLimits = ROBOT_JOINT_LIMITS
    controller: str = "interpolate"
    command_period_s: float = 0.02
    joints: bool = True
    model: ArmModel = ROBOT_MODEL

    def __post_init__(self) -> None:
        if not isinstance(self.joint_limits, JointLimits):
            raise SimArmError(f"joint_limits must be a JointLimits, got {type(self.joint_limits).__name__}; "
                              "use hri_teleop.core.joints.ROBOT_JOINT_LIMITS")
        if not isinstance(self.joints, bool):
            raise SimArmError(f"joints must be true or false, got {self.joints!r}")
        if self.controller not in CONTROLLERS:
            raise SimArmError(f"controller must be one of {', '.join(CONTROLLERS)}, got {self.controller!r}; "
                              "'interpolate' is the lab's velocity controller")
        if not (is_positive_number(self.command_period_s) and self.command_period_s <= 0.1):
            raise SimArmError(f"command_period_s must be in (0, 0.1] s, got {self.command_period_s!r}; "
                              "e.g. 0.02 (the teleoperation node's 50 Hz)")
        if not isinstance(self.limits, CartesianLimits):
            raise SimArmError(f"limits must be a CartesianLimits, got {type(self.limits).__name__}; "
                              "use hri_teleop.core.limits.ROBOT_LIMITS")
        if self.stop_limits is not None and not isinstance(self.stop_limits, CartesianLimits):
            raise SimArmError(f"stop_limits must be a CartesianLimits or None, got {type(self.stop_limits).__name__}")
        if not is_positive_number(self.timeout_s):
            raise SimArmError(f"timeout_s must be a positive number of seconds, got {self.timeout_s!r}; e.g. 0.1")
        if not (is_finite_number(self.rel_tol) and 0.0 <= self.rel_tol < 1e-3):
            raise SimArmError(f"rel_tol must be in [0, 1e-3), got {self.rel_tol!r}; the default 1e-9 absorbs rounding")
        lo = _vector("workspace_min_m", self.workspace_min_m, 3)
        hi = _vector("workspace_max_m", self.workspace_max_m, 3)
        start = _vector("start_position_m", self.start_position_m, 3)
        quat = _vector("start_orientation_xyzw", self.start_orientation_xyzw, 4)
        for i, axis in enumerate(AXES):
            if not lo[i] < hi[i]:
                raise SimArmError(f"workspace {axis}: min {lo[i]:g} m must be below max {hi[i]:g} m; "
                                  "swap or widen them")
            if not lo[i] <= start[i] <= hi[i]:
                raise SimArmError(f"start_position_m {axis} = {start[i]:g} m is outside the workspace "
                                  f"[{lo[i]:g}, {hi[i]:g}] m; move the start pose or widen the box")
        norm = math.sqrt(sum(c * c for c in quat))
        if abs(norm - 1.0) > 1e-6:
            raise SimArmError(f"start_orientation_xyzw must be a unit quaternion (x, y, z, w), got norm {norm:.9g}; "
                              "e.g. (1, 0, 0, 0) for the end effector pointing down")
        object.__setattr__(self, "workspace_min_m", lo)
        object.__setattr__(self, "workspace_max_m", hi)
        object.__setattr__(self, "start_position_m", start)
        object.__setattr__(self, "start_orientation_xyzw", tuple(c / norm for c in quat))
        object.__setattr__(self, "timeout_s", float(self.timeout_s))
        object.__setattr__(self, "command_period_s", float(self.command_period_s))
        object.__setattr__(self, "rel_tol", float(self.rel_tol))
        try:  # the stop ramp must itself pass the judge
            TwistLimiter(self.effective_stop_limits, hard_limits=self.limits)
        except LimitsError as exc:
            raise SimArmError(f"stop_limits: {exc}") from None

    @property
    def effective_stop_limits(self) -> CartesianLimits:
        """The limits of the ramp to zero after a timeout."""
        return self.limits if self.stop_limits is None else self.stop_limits
