"""The lab twin: a master that looks like the lab PC's and counts what reaches it.

franka_control, franka_gripper, joint_state_publisher and serial_node with a rosserial board on a
pty, under the lab's names, and the lab PC's installed franka_control and rosserial_python packages
(:mod:`.packages`) so a student's teleoperation.launch runs on it; docs/lab-day.md, "Before the
first session: rehearse on the lab twin".
"""

from __future__ import annotations

from hri_teleop.ros.lab_twin.report import NODES, TwinReport
from hri_teleop.ros.lab_twin.twin import LabTwin

__all__ = ["LabTwin", "TwinReport", "NODES"]
