"""The autograder of handout Task 4: student files checked against the lab's reference rules.

Entry points (grading/README.md): ``hri-grade`` (``cli``), ``make grade`` (``batch``), and the
notebooks' ``check_*`` (AssertionError with the student's feedback unless every part passes) and
``grade_*`` (return the result); ``hri-grade traces`` and ``templates`` write the public traces and
the student templates. No lab node imports it; rospy is needed only by the parts that run ROS.
"""

from __future__ import annotations

from hri_teleop.grading.judge.checks import (
    CHECKS,
    check_graph,
    check_mapping_node,
    check_robot_params,
    check_sensor_launch,
    check_teleoperation,
    check_teleoperation_launch,
    grade,
    grade_mapping_node,
    grade_robot_params,
    grade_sensor_launch,
    grade_submission,
    grade_teleoperation,
    grade_teleoperation_launch,
)
from hri_teleop.grading.judge.graph import grade_graph
from hri_teleop.grading.judge.package_check import grade_catkin_package
from hri_teleop.grading.results import CheckResult, GradingError, Part, feedback_text, gradescope_json

__all__ = [
    "CHECKS", "CheckResult", "GradingError", "Part", "feedback_text", "gradescope_json", "grade", "grade_submission",
    "grade_robot_params", "grade_mapping_node", "grade_sensor_launch", "grade_teleoperation",
    "grade_teleoperation_launch", "grade_graph", "grade_catkin_package", "check_robot_params", "check_mapping_node", "check_sensor_launch",
    "check_teleoperation", "check_teleoperation_launch", "check_graph",
]
