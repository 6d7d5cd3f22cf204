"""The Panda's seven joints: their limits, libfranka's names for breaking them, the warning before one.

The robot turns a Cartesian velocity into joint motion with its own inverse kinematics and stops
with a reflex when a joint would pass its position, velocity, acceleration or jerk limit. The
simulated arm judges with these numbers, the teleoperation node warns the operator from the joint
states before a position limit, and a notebook explains the reflex (docs/lab-facts.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Iterable, List, Optional, Sequence, Tuple

from hri_teleop.core.checks import is_finite_number
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.robot_file import lab_robot_file

__all__ = [
    "JointsError", "JointLimits", "ROBOT_JOINT_LIMITS", "JOINT_NAMES", "FINGER_JOINT_NAMES", "FRANKA_JOINT_STATES_TOPIC",
    "READY_POSE_RAD", "JointVector",
    "JOINT_POSITION_LIMITS_VIOLATION", "JOINT_VELOCITY_LIMITS_VIOLATION", "JOINT_VELOCITY_DISCONTINUITY",
    "JOINT_ACCELERATION_DISCONTINUITY", "JOINT_ERRORS", "JointViolation", "joint_violations", "LimitDistance",
    "nearest_limit", "WARNING_MARGIN_RAD", "CLEAR_MARGIN_RAD", "WARNING_RUMBLE", "WARNING_PULSE_S",
    "JOINT_STATES_TIMEOUT_S", "JointLimitWatch", "positions_by_name", "JointStateWarning",
]

JointVector = Tuple[float, float, float, float, float, float, float]

# The names, limits and poses of the lab's robot come from its profile (HRI_ROBOT; unset: the Panda's,
# core/robots/franka_panda.yaml).
_ROBOT = lab_robot_file()
#: The arm's joint names, as franka_state_controller publishes them on ``joint_states``.
JOINT_NAMES: Tuple[str, ...] = _ROBOT["joints"]["names"]
#: Where franka_state_controller publishes the arm's joints (lab_sim at home, the same name).
FRANKA_JOINT_STATES_TOPIC: str = _ROBOT["topics"]["arm_joint_states"]
#: The Franka Hand's two finger joints (each moves half the opening), as franka_gripper publishes them.
FINGER_JOINT_NAMES: Tuple[str, str] = _ROBOT["gripper"]["finger_joints"]
#: The robot's "ready" pose (rad); the Panda's and the FR3's: the hand 0.31 m in front of the base, 0.49 m up,
#: pointing down.
READY_POSE_RAD: JointVector = _ROBOT["joints"]["ready_pose_rad"]

# libfranka's franka::Errors flags for the joint-side checks of a Cartesian motion generator
# ("... after IK calculation"): what the robot reports when the joints, not the twist, break a limit.
JOINT_POSITION_LIMITS_VIOLATION: str = _ROBOT["errors"]["joint"]["position"]
JOINT_VELOCITY_LIMITS_VIOLATION: str = _ROBOT["errors"]["joint"]["velocity"]
#: joint acceleration above its limit: "joint velocity ... is discontinuous after IK calculation"
JOINT_VELOCITY_DISCONTINUITY: str = _ROBOT["errors"]["joint"]["acceleration"]
#: joint jerk above its limit: "joint acceleration ... is discontinuous after IK calculation"
JOINT_ACCELERATION_DISCONTINUITY: str = _ROBOT["errors"]["joint"]["jerk"]
#: Which error each judged quantity raises, in the order they are judged.
JOINT_ERRORS = (("position", JOINT_POSITION_LIMITS_VIOLATION), ("velocity", JOINT_VELOCITY_LIMITS_VIOLATION),
                ("acceleration", JOINT_VELOCITY_DISCONTINUITY), ("jerk", JOINT_ACCELERATION_DISCONTINUITY))

#: Warn this close to a position limit (rad): franka_control's ``joint_limit_warning_threshold`` default.
WARNING_MARGIN_RAD = 0.1
#: ... and stop warning once every joint is this far again (a joint hovering at the edge warns once).
CLEAR_MARGIN_RAD = 1.5 * WARNING_MARGIN_RAD
#: The warning's pulse on the pad: its intensity (0..1) and period (s, on for the first half).
WARNING_RUMBLE = 0.6
WARNING_PULSE_S = 0.4
#: Joint states older than this (s) say nothing about the joints any more: the warning ends.
JOINT_STATES_TIMEOUT_S = 0.5


class JointsError(HriTeleopError, ValueError):
    """A joint limit or a joint vector is unusable (the message names the fix)."""


def _seven(name: str, value: object, positive: bool = False) -> JointVector:
    items: Tuple[object, ...] = tuple(value) if isinstance(value, Iterable) else ()
    numbers = tuple(float(v) for v in items if is_finite_number(v, numpy=True))
    if len(items) != 7 or len(numbers) != 7:
        raise JointsError(f"{name} must be 7 finite numbers, one per joint, got {value!r}")
    if positive and not all(v > 0.0 for v in numbers):
        raise JointsError(f"{name} must be positive for every joint, got {value!r}")
    return (numbers[0], numbers[1], numbers[2], numbers[3], numbers[4], numbers[5], numbers[6])


@dataclass(frozen=True)
class JointLimits:
    """Per-joint limits: position (rad), velocity (rad/s), acceleration (rad/s^2), jerk (rad/s^3)."""

    position_min_rad: JointVector
    position_max_rad: JointVector
    velocity_rad_per_s: JointVector
    acceleration_rad_per_s2: JointVector
    jerk_rad_per_s3: JointVector

    def __post_init__(self) -> None:
        for f in fields(self):
            object.__setattr__(self, f.name, _seven(f"JointLimits.{f.name}", getattr(self, f.name),
                                                    positive=not f.name.startswith("position")))
        for j, (low, high) in enumerate(zip(self.position_min_rad, self.position_max_rad), start=1):
            if not low < high:
                raise JointsError(f"joint {j}: position_min_rad {low:g} must be below position_max_rad {high:g}")


#: The lab's robot's joint limits (its profile: Franka's control-parameter documentation, each robot's table).
ROBOT_JOINT_LIMITS = JointLimits(**{key: _ROBOT["joints"][key] for key in (
    "position_min_rad", "position_max_rad", "velocity_rad_per_s", "acceleration_rad_per_s2", "jerk_rad_per_s3")})


@dataclass(frozen=True)
class JointViolation:
    """One broken joint limit in one 1 ms cycle; ``joint`` counts from 1, as the Panda's joints do."""

    time_s: float
    error: str
    joint: int
    value: float
    limit: float


def joint_violations(position_rad: Sequence[float], velocity: Sequence[float], acceleration: Sequence[float],
                     jerk: Sequence[float], time_s: float = 0.0, limits: JointLimits = ROBOT_JOINT_LIMITS,
                     rel_tol: float = 1e-9) -> List[JointViolation]:
    """Every limit the joints break in one cycle: the position the step leads to, and the velocity,
    acceleration and jerk of the step (backward differences at 1 kHz, as the robot takes them).

    A position is judged against its limit exactly; the derivatives against ``limit * (1 + rel_tol)``
    (rounding). NaN breaks every limit.
    """
    found: List[JointViolation] = []
    tol = 1.0 + rel_tol
    bounds = (limits.velocity_rad_per_s, limits.acceleration_rad_per_s2, limits.jerk_rad_per_s3)
    for j in range(7):
        q = float(position_rad[j])
        low, high = limits.position_min_rad[j], limits.position_max_rad[j]
        if not low <= q <= high:
            found.append(JointViolation(time_s, JOINT_POSITION_LIMITS_VIOLATION, j + 1, q,
                                        low if q < low or math.isnan(q) else high))
        for (_what, error), values, bound in zip(JOINT_ERRORS[1:], (velocity, acceleration, jerk), bounds):
            value = float(values[j])
            if not abs(value) <= bound[j] * tol:
                found.append(JointViolation(time_s, error, j + 1, value, bound[j]))
    return found


@dataclass(frozen=True)
class LimitDistance:
    """How close the joint nearest to a position limit is: ``margin_rad`` (negative: past it)."""

    joint: int
    margin_rad: float
    side: str  # "min" or "max"
    position_rad: float
    limit_rad: float

    def describe(self) -> str:
        """One line for a log or the operator: which joint, how far, which way to move."""
        way = "down" if self.side == "max" else "up"
        return (f"joint {self.joint} is {self.margin_rad:.2f} rad from its {self.side} limit "
                f"({self.position_rad:+.2f} of {self.limit_rad:+.2f} rad): turn it back ({way}) before the robot stops")


def nearest_limit(position_rad: Sequence[float], limits: JointLimits = ROBOT_JOINT_LIMITS) -> LimitDistance:
    """The joint closest to one of its position limits (the first of equals)."""
    q = _seven("position_rad", position_rad)
    best: Optional[LimitDistance] = None
    for j in range(7):
        low, high = limits.position_min_rad[j], limits.position_max_rad[j]
        for side, margin, limit in (("min", q[j] - low, low), ("max", high - q[j], high)):
            if best is None or margin < best.margin_rad:
                best = LimitDistance(j + 1, margin, side, q[j], limit)
    assert best is not None
    return best


class JointLimitWatch:
    """When to warn the operator of a joint limit: from the joint states, before the robot stops.

    A warning starts when a joint comes within ``warn_margin_rad`` of a position limit and ends
    once every joint is more than ``clear_margin_rad`` away (hysteresis: one warning per approach,
    not one per tick while it hovers at the edge). While it lasts, :meth:`rumble` pulses.
    """

    def __init__(self, limits: JointLimits = ROBOT_JOINT_LIMITS, warn_margin_rad: float = WARNING_MARGIN_RAD,
                 clear_margin_rad: float = CLEAR_MARGIN_RAD, rumble_level: float = WARNING_RUMBLE,
                 pulse_period_s: float = WARNING_PULSE_S) -> None:
        if not (is_finite_number(warn_margin_rad) and warn_margin_rad > 0.0):
            raise JointsError(f"warn_margin_rad must be a positive angle in rad, got {warn_margin_rad!r}; e.g. 0.1")
        if not (is_finite_number(clear_margin_rad) and clear_margin_rad >= warn_margin_rad):
            raise JointsError(f"clear_margin_rad must be at least warn_margin_rad ({warn_margin_rad:g} rad), "
                              f"got {clear_margin_rad!r}; e.g. {1.5 * warn_margin_rad:g}")
        if not (is_finite_number(rumble_level) and 0.0 <= rumble_level <= 1.0):
            raise JointsError(f"rumble_level must be in [0, 1], got {rumble_level!r}; e.g. 0.6")
        if not (is_finite_number(pulse_period_s) and pulse_period_s > 0.0):
            raise JointsError(f"pulse_period_s must be a positive time in s, got {pulse_period_s!r}; e.g. 0.4")
        self.limits = limits
        self.warn_margin_rad = float(warn_margin_rad)
        self.clear_margin_rad = float(clear_margin_rad)
        self.rumble_level = float(rumble_level)
        self.pulse_period_s = float(pulse_period_s)
        self.warning: Optional[LimitDistance] = None

    def update(self, position_rad: Sequence[float]) -> Optional[LimitDistance]:
        """Take the latest joint positions; returns the nearest limit when a warning starts, else None."""
        nearest = nearest_limit(position_rad, self.limits)
        if self.warning is None:
            if nearest.margin_rad < self.warn_margin_rad:
                self.warning = nearest
                return nearest
            return None
        if nearest.margin_rad > self.clear_margin_rad:
            self.warning = None
        else:
            self.warning = nearest
        return None

    def clear(self) -> None:
        """Forget the warning (the joint states stopped coming: nothing is known any more)."""
        self.warning = None

    def rumble(self, now_s: float) -> float:
        """The warning's rumble at ``now_s``: on for the first half of each pulse period, 0 without a warning."""
        if self.warning is None:
            return 0.0
        phase = math.fmod(float(now_s), self.pulse_period_s)
        return self.rumble_level if phase < 0.5 * self.pulse_period_s else 0.0


def positions_by_name(names: Sequence[str], positions: Sequence[float],
                      joint_names: Sequence[str] = JOINT_NAMES) -> Optional[JointVector]:
    """The arm's seven positions (rad) picked by name from a joint state, in ``joint_names``' order.

    Other joints (``/joint_states`` also carries the fingers) are ignored; None when a joint is
    missing, the lists differ in length or a position is not a finite number.
    """
    if len(names) != len(positions):
        return None
    index = {name: i for i, name in enumerate(names)}
    if any(name not in index for name in joint_names):
        return None
    picked = [positions[index[name]] for name in joint_names]
    if not all(is_finite_number(q, numpy=True) for q in picked):
        return None
    return _seven("position_rad", picked)


class JointStateWarning:
    """The operator's joint-limit warning from a stream of joint states.

    A :class:`JointLimitWatch` fed with each state's positions; its pulse starts on, with the
    warning. When no state came for longer than ``timeout_s`` nothing is known any more about
    the joints, so the warning ends (and :meth:`rumble` is 0) until states come again.
    """

    def __init__(self, watch: JointLimitWatch, timeout_s: float = JOINT_STATES_TIMEOUT_S) -> None:
        if not (is_finite_number(timeout_s) and timeout_s > 0.0):
            raise JointsError(f"timeout_s must be a positive time in s, got {timeout_s!r}; e.g. 0.5")
        self.watch = watch
        self.timeout_s = float(timeout_s)
        self._last_s: Optional[float] = None
        self._started_s = 0.0  # when the current warning started: its pulse's phase

    @property
    def warning(self) -> Optional[LimitDistance]:
        """The limit being warned of (None: no warning)."""
        return self.watch.warning

    def update(self, position_rad: Sequence[float], now_s: float) -> Optional[LimitDistance]:
        """Take the joint state that arrived at ``now_s``; returns the nearest limit when a warning starts."""
        self._last_s = float(now_s)
        started = self.watch.update(position_rad)
        if started is not None:
            self._started_s = self._last_s
        return started

    def expire(self, now_s: float) -> bool:
        """End the warning when the last state is older than ``timeout_s``; True when that ended one."""
        if self._last_s is None or now_s - self._last_s <= self.timeout_s:
            return False
        self._last_s = None
        ended = self.watch.warning is not None
        self.watch.clear()
        return ended

    def rumble(self, now_s: float) -> float:
        """The warning's pulse at ``now_s``, on from the warning's start (0 without one or with stale states)."""
        self.expire(now_s)
        return self.watch.rumble(max(0.0, now_s - self._started_s))
