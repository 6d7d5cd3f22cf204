"""What the lab notebooks start -- the simulated robot, board and pipeline -- mode by mode.

At home (and under grading) these start the simulation on the notebook's own master and wait
until it is connected, so a scripted pad never plays to nobody. On any other master (the lab
PC's, :mod:`hri_teleop.course.master_mode`) or next to real hardware they start nothing and
say so in one line: the real Panda, board and pipeline are already there.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Union

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC, LAB_TELEOP_CONFIG, lab_max_sensor_force
from hri_teleop.core.joints import FRANKA_JOINT_STATES_TOPIC, JOINT_NAMES
from hri_teleop.core.modes import LAB, Start
from hri_teleop.core.modes import default_pad as mode_default_pad
from hri_teleop.core.modes import pad_params as mode_pad_params
from hri_teleop.course.errors import CourseError
from hri_teleop.course.master_mode import NotStarted, master_mode, start_refusal
from hri_teleop.course.nodes import STUDENT_PACKAGE, launch, launch_student, run_provided_node, run_student_node
from hri_teleop.course.pipeline_start import (
    STUDENT_GRACE_S,
    explain_ended,
    lab_nodes_settled,
    students_registered,
)
from hri_teleop.grading.run.workspace import REFERENCE_PACKAGE
from hri_teleop.ros.master_api import master_call, running_nodes

__all__ = ["mode", "start_robot", "start_board", "start_pipeline", "wait_for_subscriber", "hand_z_m",
           "pad_params", "default_pad", "start_application", "wait_for_quit"]

#: lab_sim's end-effector pose (geometry_msgs/PoseStamped), the simulated robot's answer.
EE_POSE_TOPIC = "/lab_sim/ee_pose"


def mode() -> str:
    """This kernel's mode, decided from its master: ``lab`` on any master this kernel did not
    start; on its own, ``grading`` under nbgrader, else ``home`` (``HRI_MODE=lab`` for care there too)."""
    return master_mode().mode


def default_pad() -> str:
    """The pad a notebook's node reads unless the student picks one: the real one in the lab."""
    return mode_default_pad(mode())


def pad_params(pad: str, script: Union[str, Path, None] = None) -> Dict[str, Any]:
    """The node's pad parameters in this kernel's mode (under grading the script plays)."""
    return mode_pad_params(pad, script, mode())


def _refusal(what: str) -> Optional[str]:
    return start_refusal([Start(what, simulated=True)])


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


def wait_until_up(process: Any, topic: str, publishers: bool, node: str, timeout_s: float) -> None:
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
    """The simulated Franka (``lab_sim.py``), up and listening to the velocity command; in the lab a NotStarted that says why."""
    refusal = _refusal("the simulated Franka (lab_sim.py)")
    if refusal:
        print(refusal)
        return NotStarted(refusal)
    robot = run_provided_node("lab_sim.py", **params)
    wait_until_up(robot, DEFAULT_TWIST_TOPIC, False, "/lab_sim", timeout_s)
    wait_until_up(robot, EE_POSE_TOPIC, True, "/lab_sim", timeout_s)
    return robot


def start_board(timeout_s: float = 60.0, **params: Any) -> Any:
    """The simulated FSR board (``FSR_sensor.py`` on ``/pub_force``); in the lab a NotStarted that says why."""
    refusal = _refusal("the simulated board (FSR_sensor.py)")
    if refusal:
        print(refusal)
        return NotStarted(refusal)
    board = run_provided_node("FSR_sensor.py", **params)
    wait_until_up(board, "/pub_force", True, "/FSR_sensor", timeout_s)
    return board


class NodeGroup:
    """Several started nodes as one: ``running`` while all run, ``output()`` of each, ``stop()`` all."""

    def __init__(self, processes: Dict[str, Any], scripts: Optional[Dict[str, Path]] = None) -> None:
        self.processes = processes
        #: The student's file each node runs (node name -> path), to explain a node that ended.
        self.scripts = dict(scripts or {})

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
    return NodeGroup(processes, {"mapping_node": scripts / "mapping_node.py",
                                 "teleoperation": scripts / "teleoperation.py"})


def start_application(feedback: bool = True, package: Union[str, Path] = STUDENT_PACKAGE) -> Any:
    """Ex. 14 in the lab: the student's own ``teleoperation.launch`` on the lab's master, the
    condition given to their node as ``/teleoperation/feedback`` (their launch file needs no
    argument for it). At home it starts nothing: the lock-step simulation is Ex. 14's home path."""
    if mode() != LAB:
        reason = ("not started: at home no robot and no board run here, the simulated lab below stands in; in the "
                  "lab this cell starts your teleoperation.launch")
        print(reason)
        return NotStarted(reason)
    master_call("setParam", "/teleoperation/feedback", bool(feedback))
    try:
        return launch_student("teleoperation.launch", package)
    except CourseError as exc:  # a name already running (franka_control from Ex. 10's terminal), a broken file
        print(f"not started: {exc}")
        return NotStarted(f"not started: {exc}")


def wait_for_quit(app: Any, timeout_s: float = 600.0, node: str = "/teleoperation") -> bool:
    """Wait until the teleoperation node ``app`` started has come up and quit (square on the pad).

    True when it quit within ``timeout_s``; at once when ``app`` was not started (at home, a
    refused start); False when the launch ended without the node or the time ran out.
    """
    if not app:
        return True
    deadline = time.monotonic() + timeout_s
    while not running_nodes(among=[node]):  # the launch brings it up first
        if not app.running or time.monotonic() > deadline:
            return False
        time.sleep(0.2)
    while running_nodes(among=[node]):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.2)
    return True


def lab_launch_file() -> Path:
    """The lab's own teleoperation.launch (instructors' checkout; the student bundle leaves it out)."""
    return REFERENCE_PACKAGE / "launch" / "teleoperation.launch"


def start_pipeline(timeout_s: float = 60.0, package: Union[str, Path] = STUDENT_PACKAGE, **args: Any) -> Any:
    """The pipeline without hardware; in the lab, where it runs, a NotStarted that says why.

    The lab's ``teleoperation.launch robot:=false arduino:=false pad:=virtual`` where it is
    installed; in the student bundle the same nodes started one by one, with the student's
    own ``mapping_node.py`` and ``teleoperation.py`` from ``package``.
    """
    refusal = _refusal("the pipeline without hardware (a simulated board and a scripted pad)")
    if refusal:
        print(refusal)
        return NotStarted(refusal)
    student_nodes: List[str] = []
    if lab_launch_file().is_file():
        settings = {"robot": "false", "arduino": "false", "pad": "virtual", **args}
        pipeline = launch("hri_lab", "teleoperation.launch", **settings)
    else:
        pipeline = _home_pipeline(Path(package))
        student_nodes = ["/mapping_node", "/teleoperation"]
    # Up when the graph has settled (every node's registrations at the master, so the graph
    # view draws the whole pipeline), or ended: then one message says which node and why.
    deadline = time.monotonic() + timeout_s
    lab_up_at: Optional[float] = None
    while True:
        if not pipeline.running:
            group = pipeline if isinstance(pipeline, NodeGroup) else NodeGroup({"teleoperation.launch": pipeline})
            message = explain_ended(group.processes, group.scripts)  # before the stop ends the others too
            pipeline.stop()
            raise CourseError(message)
        state = master_call("getSystemState")
        if _has_publisher(state, "/gripper_width") and lab_nodes_settled(state, student_nodes):
            lab_up_at = lab_up_at if lab_up_at is not None else time.monotonic()
            if students_registered(state, student_nodes) or time.monotonic() - lab_up_at > STUDENT_GRACE_S:
                return pipeline
        if time.monotonic() > deadline:
            pipeline.stop()
            raise CourseError(f"the pipeline did not come up within {timeout_s:.0f} s: run the cell again")
        time.sleep(0.05)


def _has_publisher(state: Any, topic: str) -> bool:
    return any(name == topic and nodes for name, nodes in state[0])


def hand_z_m(timeout_s: float = 10.0) -> float:
    """The hand's height (m) above the robot's base, from franka_state_controller's joint states.

    The same topic at home (``lab_sim``) and in the lab (the real Panda), through the arm's
    forward kinematics, so the check of Ex. 10 reads the robot the student drove.
    """
    import rospy  # noqa: PLC0415 - ROS only in the cell that reads the joints
    from sensor_msgs.msg import JointState  # noqa: PLC0415 - as rospy above

    from hri_teleop.sim.kinematics import PandaKinematics  # noqa: PLC0415 - pinocchio loads slowly

    try:
        state = rospy.wait_for_message(FRANKA_JOINT_STATES_TOPIC, JointState, timeout=timeout_s)
    except rospy.ROSException:
        where = "franka_control runs?" if mode() == LAB else "run the start cell (the simulated robot) first"
        raise CourseError(f"no joint states on {FRANKA_JOINT_STATES_TOPIC} within {timeout_s:.0f} s: "
                          f"{where}") from None
    positions = dict(zip(state.name, state.position))
    missing = [name for name in JOINT_NAMES if name not in positions]
    if missing:
        raise CourseError(f"{FRANKA_JOINT_STATES_TOPIC} has no {', '.join(missing)}: is it the Panda's?")
    return float(PandaKinematics().position([positions[name] for name in JOINT_NAMES])[2])
