"""The franka_gripper action messages, from franka_ros when installed, else built at run time.

The gripper simulation must speak the same actions as the Franka Hand, and ROS 1 refuses a
connection whose two ends' MD5 sums differ. Without franka_ros (a laptop, CI) genpy generates the
classes from definitions identical to franka_ros' ``.action`` files and ``GraspEpsilon.msg``,
expanded as actionlib's ``genaction.py`` does (hri_teleop.ros.action_msgs): same text, same MD5 sums.
Exports the seven classes of each of Move, Grasp, Homing and Stop (``MoveAction`` ..
``MoveActionFeedback``), ``GraspEpsilon``, and ``SOURCE`` ("franka_gripper" or "generated").
"""

from __future__ import annotations

from typing import Dict

from hri_teleop.ros.action_msgs import ActionMsgsError, MessageClass, expand_action, load_action_messages

PACKAGE = "franka_gripper"

# franka_ros/franka_gripper/msg/GraspEpsilon.msg, verbatim.
GRASP_EPSILON_MSG = "float64 inner # [m]\nfloat64 outer # [m]\n"

# franka_ros/franka_gripper/action/*.action, verbatim (comments included; they do not
# enter the MD5 sum but they do enter the message definition text sent on connection).
ACTION_DEFINITIONS: Dict[str, str] = {
    "Move": (
        "float64 width  # [m]\n"
        "float64 speed  # [m/s]\n"
        "---\n"
        "bool success\n"
        "string error\n"
        "---\n"
    ),
    "Grasp": (
        "float64 width # [m]\n"
        "GraspEpsilon epsilon\n"
        "float64 speed # [m/s]\n"
        "float64 force # [N]\n"
        "---\n"
        "bool success\n"
        "string error\n"
        "---\n"
    ),
    "Homing": (
        "---\n"
        "bool success\n"
        "string error\n"
        "---\n"
    ),
    "Stop": (
        "---\n"
        "bool success\n"
        "string error\n"
        "---\n"
    ),
}

#: The error of this module (kept under its old name; the generation is hri_teleop.ros.action_msgs').
FrankaGripperMsgsError = ActionMsgsError

SOURCE, _CLASSES = load_action_messages(PACKAGE, ACTION_DEFINITIONS, "hri_teleop/ros/franka_gripper_msgs.py",
                                        messages={"GraspEpsilon": GRASP_EPSILON_MSG})

MoveAction: MessageClass = _CLASSES["MoveAction"]
MoveActionGoal: MessageClass = _CLASSES["MoveActionGoal"]
MoveActionResult: MessageClass = _CLASSES["MoveActionResult"]
MoveActionFeedback: MessageClass = _CLASSES["MoveActionFeedback"]
MoveGoal: MessageClass = _CLASSES["MoveGoal"]
MoveResult: MessageClass = _CLASSES["MoveResult"]
MoveFeedback: MessageClass = _CLASSES["MoveFeedback"]

GraspAction: MessageClass = _CLASSES["GraspAction"]
GraspActionGoal: MessageClass = _CLASSES["GraspActionGoal"]
GraspActionResult: MessageClass = _CLASSES["GraspActionResult"]
GraspActionFeedback: MessageClass = _CLASSES["GraspActionFeedback"]
GraspGoal: MessageClass = _CLASSES["GraspGoal"]
GraspResult: MessageClass = _CLASSES["GraspResult"]
GraspFeedback: MessageClass = _CLASSES["GraspFeedback"]
GraspEpsilon: MessageClass = _CLASSES["GraspEpsilon"]

HomingAction: MessageClass = _CLASSES["HomingAction"]
HomingActionGoal: MessageClass = _CLASSES["HomingActionGoal"]
HomingActionResult: MessageClass = _CLASSES["HomingActionResult"]
HomingActionFeedback: MessageClass = _CLASSES["HomingActionFeedback"]
HomingGoal: MessageClass = _CLASSES["HomingGoal"]
HomingResult: MessageClass = _CLASSES["HomingResult"]
HomingFeedback: MessageClass = _CLASSES["HomingFeedback"]

StopAction: MessageClass = _CLASSES["StopAction"]
StopActionGoal: MessageClass = _CLASSES["StopActionGoal"]
StopActionResult: MessageClass = _CLASSES["StopActionResult"]
StopActionFeedback: MessageClass = _CLASSES["StopActionFeedback"]
StopGoal: MessageClass = _CLASSES["StopGoal"]
StopResult: MessageClass = _CLASSES["StopResult"]
StopFeedback: MessageClass = _CLASSES["StopFeedback"]

__all__ = ["SOURCE", "FrankaGripperMsgsError", "expand_action", "ACTION_DEFINITIONS",
           "GRASP_EPSILON_MSG"] + sorted(_CLASSES)
