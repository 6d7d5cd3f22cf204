"""When to send the gripper a new width goal: the rule gripper_manager.py follows.

Teleoperation publishes ``/gripper_width`` at 50 Hz, and forwarding every small change as a
franka_gripper ``move`` goal makes the Franka Hand stutter. :class:`GoalThrottle` decides which
targets become goals; it is pure (the caller may pass the time), so the tests are deterministic.
"""

from __future__ import annotations

import math
import time
from typing import Callable, Optional, Sequence, Tuple

from hri_teleop.core.checks import is_finite_number, is_number
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.robot_file import lab_robot_file

#: The hand's largest opening (the lab's robot's profile: HRI_ROBOT). Here, not in core.teleop: the student API and the
#: provided gripper manager import this module, and a graded student process may not load the teleoperation rule.
GRIPPER_MAX_WIDTH_M: float = lab_robot_file()["gripper"]["max_width_m"]


class GripperError(HriTeleopError, ValueError):
    """A gripper throttle setting or target is not usable."""


class GoalThrottle:
    """Decides which gripper width targets become action goals (the rule: docs/teleoperation.md)."""

    def __init__(
        self,
        min_step_m: float = 0.002,
        max_goal_rate_hz: float = 5.0,
        settle_s: float = 0.2,
        tolerance_m: float = 1e-4,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        for name, value, fix in (
            ("min_step_m", min_step_m, "e.g. 0.002 (2 mm)"),
            ("max_goal_rate_hz", max_goal_rate_hz, "e.g. 5.0"),
            ("settle_s", settle_s, "e.g. 0.2"),
        ):
            if not (is_finite_number(value) and value > 0):
                raise GripperError(
                    f"gripper throttle {name} must be a positive number, got {value!r}; set it to {fix}"
                )
        if not (is_number(tolerance_m) and 0 <= tolerance_m < min_step_m):
            raise GripperError(
                f"gripper throttle tolerance_m must be >= 0 and below min_step_m ({min_step_m}), "
                f"got {tolerance_m!r}; leave it at its default 1e-4"
            )
        self.min_step_m = float(min_step_m)
        self.max_goal_rate_hz = float(max_goal_rate_hz)
        self.settle_s = float(settle_s)
        self.tolerance_m = float(tolerance_m)
        self._clock = clock
        self.last_sent_m: Optional[float] = None
        self._last_sent_s: Optional[float] = None
        self._last_target_m: Optional[float] = None
        self._target_since_s: Optional[float] = None
        self.goals_sent = 0

    def _now(self, now_s: Optional[float]) -> float:
        return float(self._clock() if now_s is None else now_s)

    def _observe(self, target_m: float, now_s: float) -> None:
        """Remember since when the target has not changed (for the settle rule)."""
        if self._last_target_m is None or abs(target_m - self._last_target_m) > self.tolerance_m:
            self._last_target_m = target_m
            self._target_since_s = now_s

    def should_send(self, target_m: float, now_s: Optional[float] = None) -> bool:
        """Whether ``target_m`` (metres) should go out as a goal now.

        Call it with every target that arrives (and, so that the settle rule can fire
        when targets stop arriving, now and then with the latest target).
        """
        if not is_finite_number(target_m):
            raise GripperError(
                f"gripper width target must be a finite number of metres, got {target_m!r}; "
                "check what publishes /gripper_width"
            )
        now = self._now(now_s)
        target = float(target_m)
        self._observe(target, now)
        if self.last_sent_m is None or self._last_sent_s is None:
            return True
        if now - self._last_sent_s < 1.0 / self.max_goal_rate_hz:
            return False
        moved = abs(target - self.last_sent_m)
        if moved >= self.min_step_m:
            return True
        settled = self._target_since_s is not None and now - self._target_since_s >= self.settle_s
        return moved > self.tolerance_m and settled

    def sent(self, target_m: float, now_s: Optional[float] = None) -> None:
        """Record that a goal for ``target_m`` went out at ``now_s``."""
        now = self._now(now_s)
        self.last_sent_m = float(target_m)
        self._last_sent_s = now
        self._observe(float(target_m), now)
        self.goals_sent += 1

    def pending(self) -> bool:
        """Whether the latest target seen differs from the last goal sent."""
        if self._last_target_m is None:
            return False
        if self.last_sent_m is None:
            return True
        return abs(self._last_target_m - self.last_sent_m) > self.tolerance_m

    @property
    def latest_target_m(self) -> Optional[float]:
        """The latest target passed to should_send (None before the first)."""
        return self._last_target_m


def usable_width_m(width_m: float, width_min_m: float = 0.0,
                   width_max_m: float = GRIPPER_MAX_WIDTH_M) -> Tuple[Optional[float], str]:
    """A width target as the gripper may be sent it, and what was wrong with it ("" if nothing).

    Why: /gripper_width is a topic anyone can publish on; a NaN or a width past the hand's
    range must neither reach the Franka Hand nor crash the manager. Non-finite -> None
    (ignore it); out of range -> clamped to ``width_min_m .. width_max_m``.
    """
    try:
        value = float(width_m)
    except (TypeError, ValueError):
        return None, f"gripper width {width_m!r} is not a number: ignored"
    if not math.isfinite(value):
        return None, f"gripper width {value!r} is not finite: ignored"
    if value < width_min_m or value > width_max_m:
        clamped = min(max(value, width_min_m), width_max_m)
        return clamped, (f"gripper width {value:.4f} m outside [{width_min_m:.3f}, {width_max_m:.3f}] m: "
                         f"clamped to {clamped:.4f} m")
    return value, ""


def width_from_joint_positions_m(positions: Sequence[float]) -> Optional[float]:
    """The hand's opening from franka_gripper's ``joint_states`` (two finger joints, each half of it).

    None when fewer than two finite positions arrived (a malformed or foreign message).
    """
    fingers = list(positions[:2])
    if len(fingers) < 2 or not all(is_finite_number(v) for v in fingers):
        return None
    return float(fingers[0]) + float(fingers[1])
