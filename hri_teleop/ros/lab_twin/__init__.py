"""The lab twin: a master that looks like the lab PC's (franka_control, franka_gripper, joint_state_publisher,
serial_node and a rosserial board on a pty) and counts what reaches it; docs/lab-day.md."""

from __future__ import annotations

from hri_teleop.ros.lab_twin.report import NODES, TwinReport
from hri_teleop.ros.lab_twin.twin import LabTwin

__all__ = ["LabTwin", "TwinReport", "NODES"]
