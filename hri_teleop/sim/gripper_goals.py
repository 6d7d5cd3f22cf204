"""Franka gripper goals (move, grasp, homing, stop) as the simulated hand takes them, and their records."""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import Optional, Union

from hri_teleop.core.checks import is_number
from hri_teleop.sim.hand_params import DEFAULT_EPSILON_M, MAX_SPEED_M_PER_S, HandSimError

__all__ = ["ACTION_NAMES", "add_note", "MoveCommand", "GraspCommand", "HomingCommand", "StopCommand", "Command", "GoalStatus", "GoalRecord",
           "HandState", "goal_problem"]


def _field(value: object, name: str) -> float:
    """A command field as a float (NaN and inf kept: the hand, not the caller, rejects them)."""
    if not is_number(value, numpy=True):
        raise HandSimError(f"{name} must be a number, got {value!r}; pass metres, m/s or newtons as a float")
    return float(value)


@dataclass(frozen=True)
class MoveCommand:
    """franka_gripper ``move`` goal: drive to ``width_m`` at ``speed_m_per_s``."""

    width_m: float
    speed_m_per_s: float = MAX_SPEED_M_PER_S

    def __post_init__(self) -> None:
        object.__setattr__(self, "width_m", _field(self.width_m, "MoveCommand.width_m"))
        object.__setattr__(self, "speed_m_per_s", _field(self.speed_m_per_s, "MoveCommand.speed_m_per_s"))


@dataclass(frozen=True)
class GraspCommand:
    """franka_gripper ``grasp`` goal: close to contact, press with ``force_n``, check the width."""

    width_m: float
    speed_m_per_s: float = MAX_SPEED_M_PER_S
    force_n: float = 20.0
    epsilon_inner_m: float = DEFAULT_EPSILON_M
    epsilon_outer_m: float = DEFAULT_EPSILON_M

    def __post_init__(self) -> None:
        for name in ("width_m", "speed_m_per_s", "force_n", "epsilon_inner_m", "epsilon_outer_m"):
            object.__setattr__(self, name, _field(getattr(self, name), f"GraspCommand.{name}"))


@dataclass(frozen=True)
class HomingCommand:
    """franka_gripper ``homing`` goal (no fields)."""


@dataclass(frozen=True)
class StopCommand:
    """franka_gripper ``stop`` goal (no fields)."""


Command = Union[MoveCommand, GraspCommand, HomingCommand, StopCommand]

ACTION_NAMES = {MoveCommand: "move", GraspCommand: "grasp", HomingCommand: "homing", StopCommand: "stop"}


class GoalStatus(IntEnum):
    """A goal's state; the numbers are actionlib's ``GoalStatus`` constants."""

    ACTIVE = 1
    PREEMPTED = 2
    SUCCEEDED = 3
    ABORTED = 4


@dataclass
class GoalRecord:
    """One goal's life, as an action server reports it.

    ``success`` and ``error`` are the fields of franka_gripper's results; ``detail`` says
    in plain words why the goal ended as it did (not part of any message).
    ``grasp_width_m`` is the width ``d`` at which a grasp stalled.
    """

    goal_id: int
    command: Command
    accepted_s: float
    status: GoalStatus = GoalStatus.ACTIVE
    success: bool = False
    error: str = ""
    detail: str = ""
    finished_s: Optional[float] = None
    grasp_width_m: Optional[float] = None

    @property
    def action(self) -> str:
        """The action's name: "move", "grasp", "homing" or "stop"."""
        return ACTION_NAMES[type(self.command)]

    @property
    def done(self) -> bool:
        """Whether the goal has reached a terminal state."""
        return self.status != GoalStatus.ACTIVE


def add_note(record: GoalRecord, text: str) -> None:
    """Add ``text`` to the record's plain-words ``detail``."""
    if text:
        record.detail = f"{record.detail}; {text}" if record.detail else text


@dataclass(frozen=True)
class HandState:
    """A snapshot of :class:`HandSim` for logs, plots and tests."""

    time_s: float
    width_m: float
    width_rate_m_per_s: float
    grip_force_n: float
    spring_force_n: float
    piston_compression_m: float
    fsr_count: int
    in_contact: bool
    is_grasped: bool
    active_action: Optional[str]
    object_name: Optional[str]
    object_crushed: bool
    object_height_m: float
    object_moves_with_hand: bool
    finger_offset_m: float


def goal_problem(command: Command, max_width_m: float) -> str:
    """Why the hand cannot execute ``command`` ("" if it can): it then ends ABORTED at once."""
    if isinstance(command, (MoveCommand, GraspCommand)):
        if not (0.0 <= command.width_m <= max_width_m):
            return f"width {command.width_m!r} m outside 0 .. {max_width_m} m"
        if not (command.speed_m_per_s > 0.0):  # also NaN
            return f"speed {command.speed_m_per_s!r} m/s is not positive"
    if isinstance(command, GraspCommand):
        if not (command.force_n >= 0.0):
            return f"force {command.force_n!r} N is negative"
        if not (command.epsilon_inner_m >= 0.0 and command.epsilon_outer_m >= 0.0):
            return f"epsilon {command.epsilon_inner_m!r}/{command.epsilon_outer_m!r} m is negative"
    return ""
