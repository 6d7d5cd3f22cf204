"""The four actions of franka_gripper on the simulated hand: goal messages in, terminal states out.

lab_sim and the lab twin's /franka_gripper serve the same actions with the same hand
(:class:`hri_teleop.sim.hand.HandSim`): a goal becomes the hand's command here, and a
finished hand goal its actionlib end (succeeded, aborted or canceled) with franka_gripper's
``success`` and ``error`` fields, so both speak exactly as franka_gripper does.
"""

from __future__ import annotations

from typing import Any, Dict, Tuple

from hri_teleop.ros import franka_gripper_msgs as fg
from hri_teleop.sim.gripper_goals import (
    Command,
    GoalRecord,
    GoalStatus,
    GraspCommand,
    HomingCommand,
    MoveCommand,
    StopCommand,
)

__all__ = ["ACTIONS", "command_from_goal", "end_goal"]

#: action name -> (action spec, result class)
ACTIONS: Dict[str, Tuple[type, type]] = {
    "move": (fg.MoveAction, fg.MoveResult),
    "grasp": (fg.GraspAction, fg.GraspResult),
    "homing": (fg.HomingAction, fg.HomingResult),
    "stop": (fg.StopAction, fg.StopResult),
}


def command_from_goal(action: str, goal: Any) -> Command:
    """A franka_gripper goal message as the simulated hand's command (units as the fields': m, m/s, N)."""
    if action == "move":
        return MoveCommand(width_m=goal.width, speed_m_per_s=goal.speed)
    if action == "grasp":
        return GraspCommand(width_m=goal.width, speed_m_per_s=goal.speed, force_n=goal.force,
                            epsilon_inner_m=goal.epsilon.inner, epsilon_outer_m=goal.epsilon.outer)
    if action == "homing":
        return HomingCommand()
    return StopCommand()


def end_goal(action: str, handle: Any, record: GoalRecord) -> str:
    """End an accepted goal as the hand finished it; returns the terminal state's name (for a log line)."""
    _spec, result_cls = ACTIONS[action]
    result = result_cls(success=record.success, error=record.error)
    if record.status == GoalStatus.SUCCEEDED:
        handle.set_succeeded(result, record.detail)
        return "succeeded"
    if record.status == GoalStatus.ABORTED:
        handle.set_aborted(result, record.detail)
        return "aborted"
    handle.set_canceled(result, record.detail)  # PREEMPTED: by a newer goal, or an actionlib cancel
    return "preempted"
