"""What the lab notebooks start -- the simulated robot, board and pipeline -- mode by mode.

At home (and under grading) these start the simulation on the notebook's master and wait
until it is connected, so a scripted pad never plays to nobody. In the lab
(``HRI_MODE=lab``, :mod:`hri_teleop.core.modes`) or next to real hardware they start nothing
and say so in one line: the real Panda, board and pipeline are already there.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Union

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC, LAB_TELEOP_CONFIG, lab_max_sensor_force
from hri_teleop.core.modes import HARDWARE_NODES, LAB, mode_from_env, pad_params, simulation_refusal
from hri_teleop.course.errors import CourseError
from hri_teleop.course.nodes import STUDENT_PACKAGE, launch, run_provided_node, run_student_node
from hri_teleop.grading.run.workspace import REFERENCE_PACKAGE
from hri_teleop.ros.master_api import master_call, running_nodes

__all__ = ["mode", "start_robot", "start_board", "start_pipeline", "wait_for_subscriber", "hand_z_m",
           "pad_params"]

#: lab_sim's end-effector pose (geometry_msgs/PoseStamped), the simulated robot's answer.
EE_POSE_TOPIC = "/lab_sim/ee_pose"


def mode() -> str:
    """This kernel's mode (``HRI_MODE``; grading under nbgrader; home otherwise)."""
    return mode_from_env(os.environ)


def _refusal(what: str) -> Optional[str]:
    current = mode()
    hardware = [] if current == LAB else running_nodes(among=list(HARDWARE_NODES))
    return simulation_refusal(current, what, hardware)


def _topic_nodes(topic: str, publishers: bool) -> List[List[str]]:
    state = master_call("getSystemState")
    section = state[0] if publishers else state[1]
    return [nodes for name, nodes in section if name == topic][:1] or [[]]


def wait_for_subscriber(topic: str, node: str, process: Any = None, timeout_s: float = 30.0) -> bool:
    """Wait until ``node`` subscribes to ``topic`` (False after ``timeout_s`` or when ``process`` ended)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if node in _topic_nodes(topic, publishers=False)[0]:
            return True
        if process is not None and not process.running:
            return False
        time.sleep(0.05)
    return False


def _wait_until_up(process: Any, topic: str, publishers: bool, node: str, timeout_s: float) -> None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if node in _topic_nodes(topic, publishers)[0]:
            return
        if not process.running:
            raise CourseError(f"{node} ended while starting: {process.output()[-300:]!r}".replace("\\n", " "))
        time.sleep(0.05)
    process.stop()
    raise CourseError(f"{node} did not come up within {timeout_s:.0f} s: run the cell again (a busy machine?)")


def start_robot(timeout_s: float = 60.0, **params: Any) -> Any:
    """The simulated Franka (``lab_sim.py``), up and listening to the velocity command; None in the lab."""
    refusal = _refusal("robot (lab_sim)")
    if refusal:
        print(refusal + "; the real Panda follows your node once franka_control runs")
        return None
    robot = run_provided_node("lab_sim.py", **params)
    _wait_until_up(robot, DEFAULT_TWIST_TOPIC, False, "/lab_sim", timeout_s)
    _wait_until_up(robot, EE_POSE_TOPIC, True, "/lab_sim", timeout_s)
    return robot


def start_board(timeout_s: float = 60.0, **params: Any) -> Any:
    """The simulated FSR board (``FSR_sensor.py`` on ``/pub_force``); None in the lab."""
    refusal = _refusal("board (FSR_sensor.py)")
    if refusal:
        print(refusal + "; the Arduino's serial_node publishes /pub_force")
        return None
    board = run_provided_node("FSR_sensor.py", **params)
    _wait_until_up(board, "/pub_force", True, "/FSR_sensor", timeout_s)
    return board


class NodeGroup:
    """Several started nodes as one: ``running`` while all run, ``output()`` of each, ``stop()`` all."""

    def __init__(self, processes: Dict[str, Any]) -> None:
        self.processes = processes

    @property
    def running(self) -> bool:
        return all(p.running for p in self.processes.values())

    def output(self) -> str:
        return "\n".join(f"[{name}] {p.output()}" for name, p in self.processes.items())

    def stop(self) -> None:
        for process in self.processes.values():
            process.stop()


def _home_pipeline(package: Path) -> NodeGroup:
    """The pipeline without the lab's launch file (the student bundle has none): the provided
    nodes, and the student's own mapping_node.py and teleoperation.py of ``package``."""
    scripts = package / "scripts"
    for script in ("mapping_node.py", "teleoperation.py"):
        if not (scripts / script).is_file():
            raise CourseError(f"{scripts / script}: not found; the pipeline runs your nodes: run this notebook "
                              "next to your hri_lab package")
    master_call("setParam", "/max_sensor_force", lab_max_sensor_force())
    processes: Dict[str, Any] = {}
    try:
        processes["FSR_sensor"] = run_provided_node("FSR_sensor.py", rate_hz=10.0)
        processes["mapping_node"] = run_student_node(scripts / "mapping_node.py", "mapping_node")
        processes["gripper_manager"] = run_provided_node("gripper_manager.py")
        processes["teleoperation"] = run_student_node(scripts / "teleoperation.py", "teleoperation",
                                                      config=str(LAB_TELEOP_CONFIG), pad="virtual",
                                                      pad_script="", script_wait_s=0.0)
    except CourseError:
        for process in processes.values():
            process.stop()
        raise
    return NodeGroup(processes)


def lab_launch_file() -> Path:
    """The lab's own teleoperation.launch (instructors' checkout; the student bundle leaves it out)."""
    return REFERENCE_PACKAGE / "launch" / "teleoperation.launch"


def start_pipeline(timeout_s: float = 60.0, package: Union[str, Path] = STUDENT_PACKAGE, **args: Any) -> Any:
    """The pipeline without hardware; None in the lab, where it runs.

    The lab's ``teleoperation.launch robot:=false arduino:=false pad:=virtual`` where it is
    installed; in the student bundle the same nodes started one by one, with the student's
    own ``mapping_node.py`` and ``teleoperation.py`` from ``package``.
    """
    refusal = _refusal("pipeline (teleoperation.launch without hardware)")
    if refusal:
        print(refusal + "; look at the lab's running pipeline instead")
        return None
    if lab_launch_file().is_file():
        settings = {"robot": "false", "arduino": "false", "pad": "virtual", **args}
        pipeline = launch("hri_lab", "teleoperation.launch", **settings)
    else:
        pipeline = _home_pipeline(Path(package))
    deadline = time.monotonic() + timeout_s
    while not _topic_nodes("/gripper_width", publishers=True)[0]:
        if not pipeline.running:
            raise CourseError(f"the pipeline ended while starting: {pipeline.output()[-300:]!r}")
        if time.monotonic() > deadline:
            pipeline.stop()
            raise CourseError(f"the pipeline did not come up within {timeout_s:.0f} s: run the cell again")
        time.sleep(0.05)
    return pipeline


def hand_z_m(timeout_s: float = 10.0) -> float:
    """The simulated hand's height (m) from ``lab_sim``'s pose; the check of Ex. 10 reads it."""
    if mode() == LAB:
        raise CourseError("lab mode: this check reads the simulated robot; it is judged when your notebook is "
                          "graded, in the lab look at the real hand")
    import rospy  # noqa: PLC0415 - ROS only in the cell that reads the pose
    from geometry_msgs.msg import PoseStamped  # noqa: PLC0415

    try:
        pose = rospy.wait_for_message(EE_POSE_TOPIC, PoseStamped, timeout=timeout_s)
    except rospy.ROSException:
        raise CourseError(f"no pose on {EE_POSE_TOPIC} within {timeout_s:.0f} s: run the start cell "
                          "(the simulated robot) first") from None
    return float(pose.pose.position.z)
