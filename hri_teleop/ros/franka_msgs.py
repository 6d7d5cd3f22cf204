"""The ErrorRecovery messages of franka_msgs, from franka_ros when installed, else built at run time.

franka_control_node serves ``/franka_control/error_recovery`` (``franka_msgs/ErrorRecoveryAction``),
which clears a reflex; lab_sim serves the same action and the teleoperation node sends its goal.
Without franka_ros genpy generates the classes as a catkin build of franka_msgs does
(hri_teleop.ros.action_msgs: same text, same MD5 sums). Exports the seven classes
``ErrorRecoveryAction`` .. ``ErrorRecoveryFeedback`` and ``SOURCE`` ("franka_msgs" or "generated").
"""

from __future__ import annotations

from typing import Dict

from hri_teleop.ros.action_msgs import ActionMsgsError, MessageClass, load_action_messages

PACKAGE = "franka_msgs"

#: franka_ros/franka_msgs/action/ErrorRecovery.action, verbatim: empty goal, result and feedback.
ACTION_DEFINITIONS: Dict[str, str] = {"ErrorRecovery": "---\n---\n"}

SOURCE, _CLASSES = load_action_messages(PACKAGE, ACTION_DEFINITIONS, "hri_teleop/ros/franka_msgs.py")

ErrorRecoveryAction: MessageClass = _CLASSES["ErrorRecoveryAction"]
ErrorRecoveryActionGoal: MessageClass = _CLASSES["ErrorRecoveryActionGoal"]
ErrorRecoveryActionResult: MessageClass = _CLASSES["ErrorRecoveryActionResult"]
ErrorRecoveryActionFeedback: MessageClass = _CLASSES["ErrorRecoveryActionFeedback"]
ErrorRecoveryGoal: MessageClass = _CLASSES["ErrorRecoveryGoal"]
ErrorRecoveryResult: MessageClass = _CLASSES["ErrorRecoveryResult"]
ErrorRecoveryFeedback: MessageClass = _CLASSES["ErrorRecoveryFeedback"]

__all__ = ["SOURCE", "ActionMsgsError", "ACTION_DEFINITIONS"] + sorted(_CLASSES)
