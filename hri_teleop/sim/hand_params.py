"""The Franka Hand's numbers (width, speed, force limits) and the simulation's one error class."""

from __future__ import annotations

from dataclasses import dataclass

from hri_teleop.core.checks import checked_float
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.robot_file import panda_file
from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M

__all__ = ["checked_param", "HandSimError", "MAX_SPEED_M_PER_S", "MAX_FORCE_N", "MOVE_WIDTH_TOLERANCE_M", "MOVE_STALL_TIMEOUT_S",
           "DEFAULT_EPSILON_M", "GRAVITY_M_PER_S2", "COMMAND_FAILED", "COMMAND_ABORTED", "HandParams"]

#: Largest speed of the width (m/s): franka_gripper's default_speed, frankx's max_speed (robot profile).
MAX_SPEED_M_PER_S: float = panda_file()["gripper"]["max_speed_m_per_s"]
#: Largest force between the fingers (N): the handout's 70 N, the hand's continuous force (robot profile).
MAX_FORCE_N: float = panda_file()["gripper"]["max_force_n"]
#: A move that stalls this close to its width succeeds (m): franka_gazebo's default.
MOVE_WIDTH_TOLERANCE_M = 0.001
#: A move blocked for this long fails (s): "stalls for about 100 s" (franka_ros #281).
MOVE_STALL_TIMEOUT_S = 100.0
#: libfranka's default grasp epsilon, inner and outer (m); franka_gripper's default too.
DEFAULT_EPSILON_M = 0.005
#: Standard gravity (m/s^2).
GRAVITY_M_PER_S2 = 9.81
#: libfranka's message for a command the gripper could not carry out.
COMMAND_FAILED = "libfranka gripper: Command failed!"
#: libfranka's message for a command ended by stop.
COMMAND_ABORTED = "libfranka gripper: Command aborted!"


class HandSimError(HriTeleopError, ValueError):
    """A hand, object or command setting is unusable, or time ran backwards."""


def checked_param(value: object, name: str, fix: str, *, lowest: str = "") -> float:
    """``value`` as a finite float; ``lowest`` ">0" or ">=0" bounds it (else HandSimError)."""
    return checked_float(value, name, fix, HandSimError, lowest=lowest)


@dataclass(frozen=True)
class HandParams:
    """The Franka Hand's numbers (defaults: the real hand, with their sources in docs/simulation.md).

    ``homing_speed_m_per_s`` and ``homing_force_n`` are not published by Franka; they
    are chosen so that homing takes about 3 s and does not crush an object in the way.
    """

    max_width_m: float = GRIPPER_MAX_WIDTH_M
    max_speed_m_per_s: float = MAX_SPEED_M_PER_S
    max_force_n: float = MAX_FORCE_N
    move_force_n: float = MAX_FORCE_N
    move_width_tolerance_m: float = MOVE_WIDTH_TOLERANCE_M
    move_stall_timeout_s: float = MOVE_STALL_TIMEOUT_S
    homing_speed_m_per_s: float = 0.05
    homing_force_n: float = 10.0
    initial_width_m: float = GRIPPER_MAX_WIDTH_M
    grip_zone_m: float = 0.02

    def __post_init__(self) -> None:
        positive = (
            ("max_width_m", "the Franka Hand opens 0.08 m"),
            ("max_speed_m_per_s", "the Franka Hand's is 0.1"),
            ("max_force_n", "the Franka Hand's is 70.0"),
            ("move_force_n", "the Franka Hand's is 70.0"),
            ("move_stall_timeout_s", "the real hand gives up after about 100.0"),
            ("homing_speed_m_per_s", "e.g. 0.05"),
            ("homing_force_n", "e.g. 10.0"),
        )
        for name, fix in positive:
            object.__setattr__(self, name, checked_param(getattr(self, name), f"HandParams.{name}", fix,
                                                  lowest=">0"))
        for name, fix in (("move_width_tolerance_m", "e.g. 0.001"), ("grip_zone_m", "e.g. 0.02")):
            object.__setattr__(self, name, checked_param(getattr(self, name), f"HandParams.{name}", fix, lowest=">=0"))
        width = checked_param(self.initial_width_m, "HandParams.initial_width_m", "e.g. 0.08 (fully open)")
        if not 0.0 <= width <= self.max_width_m:
            raise HandSimError(
                f"HandParams.initial_width_m must lie in 0 .. {self.max_width_m} m, got {width!r}; e.g. 0.08 (fully open)"
            )
        object.__setattr__(self, "initial_width_m", width)
        if self.move_force_n > self.max_force_n or self.homing_force_n > self.max_force_n:
            raise HandSimError(
                f"HandParams.move_force_n ({self.move_force_n}) and homing_force_n ({self.homing_force_n}) must not "
                f"exceed max_force_n ({self.max_force_n}); lower them"
            )
        if self.homing_speed_m_per_s > self.max_speed_m_per_s:
            raise HandSimError(
                f"HandParams.homing_speed_m_per_s ({self.homing_speed_m_per_s}) exceeds max_speed_m_per_s "
                f"({self.max_speed_m_per_s}); lower it"
            )
