"""After a reflex, from a notebook cell: what stopped the robot in plain words, and error recovery.

At home lab_sim says why in its ``~arm_status``; in the lab franka_state_controller's ``franka_states``
names the errors. ``recover()`` sends franka_control's error recovery, which lab_sim serves at home.
"""

from __future__ import annotations

import math
from typing import Any, List, Mapping

from hri_teleop.core.modes import LAB
from hri_teleop.core.reflex import ERROR_RECOVERY_ACTION, ReflexCause, explain_reflex
from hri_teleop.core.robot_file import panda_file
from hri_teleop.course.errors import CourseError
from hri_teleop.course.lab_nodes import mode
from hri_teleop.course.notebook_ros import current_session

__all__ = ["ARM_STATUS_TOPIC", "FRANKA_STATES_TOPIC", "ERROR_RECOVERY_ACTION", "reflex", "recover",
           "reflex_from_status", "reflex_from_errors"]

#: lab_sim's arm status (diagnostic_msgs/DiagnosticStatus), with the reflex explained.
ARM_STATUS_TOPIC = "/lab_sim/arm_status"
#: franka_state_controller's robot state (franka_msgs/FrankaState) in the lab.
FRANKA_STATES_TOPIC: str = panda_file()["topics"]["robot_state"]
#: franka_control's error recovery (franka_msgs/ErrorRecoveryAction), served by lab_sim at home.


def _ros() -> Any:
    if current_session() is None:
        raise CourseError("no ROS node in this kernel: run the setup cell (ros = ensure_ros()) first")
    import rospy  # noqa: PLC0415 - ROS only in the cells that talk to the robot

    return rospy


def reflex_from_status(values: Mapping[str, str]) -> List[str]:
    """The lines for lab_sim's ``~arm_status`` values: its explanation during a reflex, else its state."""
    if values.get("state") == "reflex" and values.get("explanation"):
        return str(values["explanation"]).split("\n")
    near = values.get("nearest_joint_limit", "")
    return [f"No reflex: the robot is {values.get('state', 'unknown')} and accepts commands."] + ([near] if near else [])


def reflex_from_errors(last_motion_errors: Any) -> List[str]:
    """The lines for franka_msgs/Errors (the fields set to true), as the real robot reports them."""
    names = [name for name in getattr(last_motion_errors, "__slots__", []) if getattr(last_motion_errors, name, False)]
    # The flags say neither which joint nor which Cartesian group: "The commanded translation or rotation velocity
    # jumped", "A joint's acceleration jumped".
    return explain_reflex([ReflexCause(name, "a joint" if "joint" in name else "translation or rotation", math.nan,
                                       math.nan) for name in names])


def reflex(timeout_s: float = 3.0) -> List[str]:
    """What stopped the robot, in plain words (one line when nothing did), from the robot's own report."""
    rospy = _ros()
    if mode() == LAB:
        try:
            from franka_msgs.msg import FrankaState  # type: ignore[import-not-found]  # noqa: PLC0415 - lab only
        except ImportError:
            return ["In the lab franka_control prints the reflex in its terminal and Desk shows it (franka_msgs is "
                    "not importable in this kernel to read it here); recover with lab.recover()."]
        try:
            state = rospy.wait_for_message(FRANKA_STATES_TOPIC, FrankaState, timeout=timeout_s)
        except rospy.ROSException:
            raise CourseError(f"nothing on {FRANKA_STATES_TOPIC} within {timeout_s:.0f} s: is franka_control "
                              "running (franka_control.launch)?") from None
        return reflex_from_errors(state.last_motion_errors)
    from diagnostic_msgs.msg import DiagnosticStatus  # noqa: PLC0415 - ROS only in the cells that talk to the robot

    try:
        status = rospy.wait_for_message(ARM_STATUS_TOPIC, DiagnosticStatus, timeout=timeout_s)
    except rospy.ROSException:
        raise CourseError(f"nothing on {ARM_STATUS_TOPIC} within {timeout_s:.0f} s: run the start cell (the "
                          "simulated robot) first") from None
    return reflex_from_status({kv.key: kv.value for kv in status.values})


def recover(timeout_s: float = 10.0) -> bool:
    """franka_control's error recovery: the robot accepts commands again (True), or one line why not.

    Let go of the sticks first: a node still commanding a velocity stops the recovered robot again.
    """
    _ros()
    from actionlib_msgs.msg import GoalStatus  # noqa: PLC0415 - ROS only in the cells that talk to the robot

    from hri_teleop.ros.error_recovery import recover_and_wait, status_name  # noqa: PLC0415 - actionlib, ROS only

    found, status, text = recover_and_wait(ERROR_RECOVERY_ACTION, timeout_s / 2, timeout_s)
    if not found:
        print(f"no error recovery on {ERROR_RECOVERY_ACTION}: at home run the start cell (the simulated robot), in "
              "the lab start franka_control")
        return False
    if status != GoalStatus.SUCCEEDED:
        print(f"error recovery did not succeed ({text or status_name(status)}); check the robot "
              "(in the lab: its lights and Desk)")
        return False
    print("recovered: the robot accepts commands again, from rest")
    return True

