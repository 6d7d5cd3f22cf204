"""The lab as a notebook cell drives it: start and stop nodes on the kernel's master.

The lab's own nodes, the student's, a launch of the student's package, and the simulated
robot, board and pipeline (none of which starts on a master this kernel did not start: the lab's),
and after a reflex its explanation and error recovery. Everything started here stops with ``lab.stop()``.
"""

from __future__ import annotations

from hri_teleop.core.config import lab_max_sensor_force as max_sensor_force
from hri_teleop.course.lab_nodes import (
    default_pad,
    hand_z_m,
    pad_params,
    start_board,
    start_pipeline,
    start_robot,
)
from hri_teleop.course.nodes import launch_student, wait_for_publisher
from hri_teleop.course.nodes import rosrun_student as rosrun
from hri_teleop.course.nodes import run_provided_node as run_provided
from hri_teleop.course.nodes import run_student_node as run_student
from hri_teleop.course.nodes import stop_nodes as stop
from hri_teleop.course.pad_route import browser_pad, start_application, wait_for_quit
from hri_teleop.course.recovery import recover, reflex
from hri_teleop.ros.master import PrivateMaster as private_master

__all__ = ["stop", "run_provided", "run_student", "rosrun", "launch_student", "wait_for_publisher", "start_robot",
           "start_board", "start_pipeline", "start_application", "wait_for_quit", "browser_pad", "pad_params", "default_pad", "hand_z_m", "max_sensor_force", "private_master",
           "reflex", "recover"]
