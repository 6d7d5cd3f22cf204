"""A pad in a person's hands at home: the browser's gamepad for the student's node, and Ex. 14 driven live.

A student without a pad the kernel can open (macOS and Windows in the container, a kernel on a
server) sets ``PAD = "browser"``: the start cell starts their own node reading the browser pad
(``open_gamepad("browser")``: sensor_msgs/Joy on ``/teleoperation/virtual_joy``), and
:func:`browser_pad` shows ``widgets.BrowserPad``, which publishes the page's gamepad there and
plays the node's ``~rumble`` back. Only at home: in the lab the student's node reads the lab's
gamepad (the start is refused, :mod:`hri_teleop.core.modes`), and under grading the script plays.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Dict, Optional, Union

from hri_teleop.core.config import LAB_TELEOP_CONFIG, lab_max_sensor_force
from hri_teleop.core.modes import GRADING, HOME, LAB, Start
from hri_teleop.core.modes import pad_params as mode_pad_params
from hri_teleop.course import lab_nodes
from hri_teleop.course.errors import CourseError
from hri_teleop.course.master_mode import NotStarted, start_refusal
from hri_teleop.course.nodes import STUDENT_PACKAGE, run_provided_node, run_student_node
from hri_teleop.ros.master_api import master_call

__all__ = ["HELD_PADS", "HeldPadApplication", "browser_pad", "start_application", "wait_for_quit"]

#: The pads a person holds (at home the simulated lab is then driven live).
HELD_PADS = ("browser", "pygame")


class HeldPadApplication(lab_nodes.NodeGroup):
    """Ex. 14's simulated lab at home, driven by the student's node from ``pad`` (a pad a person holds)."""

    def __init__(self, processes: Dict[str, Any], pad: str) -> None:
        super().__init__(processes)
        self.pad = pad


def browser_pad(pad: Optional[str] = "browser", node: str = "/teleoperation") -> Any:
    """The browser's gamepad for the student's node when ``pad`` is ``"browser"`` (a cell's last line shows it).

    ``widgets.BrowserPad`` reads the gamepad of this page and publishes it to ``node``, started
    with the same ``pad``; the node's rumble comes back to the page. None for another pad, under
    grading (nobody is at the page) and in the lab, where the student's node reads the lab's gamepad.
    """
    if pad is None:
        return None
    mode_pad_params(pad)  # one line for a pad that is none
    if pad != "browser":
        return None
    now = lab_nodes.mode()
    if now != HOME:
        print("no browser pad: " + ("under grading nobody drives, the script plays" if now == GRADING else
                                    "in the lab your node reads the lab's gamepad (PAD = \"pygame\")"))
        return None
    from hri_teleop.course.widgets.browser_pad import BrowserPad  # noqa: PLC0415 - anywidget only where shown

    return BrowserPad(node)


def _student_nodes(package: Path, pad: str, feedback: bool) -> Dict[str, Any]:
    """The student's mapping_node.py and teleoperation.py (reading ``pad``) and the provided gripper_manager.py."""
    scripts = package / "scripts"
    for script in ("mapping_node.py", "teleoperation.py"):
        if not (scripts / script).is_file():
            raise CourseError(f"{scripts / script}: not found; Ex. 14 at home runs your nodes: run this notebook "
                              "next to your hri_lab package")
    master_call("setParam", "/max_sensor_force", lab_max_sensor_force())
    processes: Dict[str, Any] = {}
    try:
        processes["mapping_node"] = run_student_node(scripts / "mapping_node.py", "mapping_node")
        processes["gripper_manager"] = run_provided_node("gripper_manager.py")
        processes["teleoperation"] = run_student_node(scripts / "teleoperation.py", "teleoperation",
                                                      config=str(LAB_TELEOP_CONFIG), pad=pad, feedback=bool(feedback))
    except CourseError:
        for process in processes.values():
            process.stop()
        raise
    return processes


def start_application(feedback: bool = True, package: Union[str, Path] = STUDENT_PACKAGE,
                      pad: Optional[str] = None) -> Any:
    """Ex. 14: in the lab the student's ``teleoperation.launch`` (:func:`lab_nodes.start_application`).

    At home, with ``pad`` one a person holds (``"browser"``, ``"pygame"``): the simulated Franka with
    an egg between its fingers and its sensor board, and the student's own mapping_node.py and
    teleoperation.py reading that pad with the condition ``feedback``; square on the pad quits.
    Otherwise at home and under grading nothing (the lock-step simulation is Ex. 14's home path).
    In the lab a pad other than the lab's is refused in one line.
    """
    if pad is not None:
        mode_pad_params(pad)
    now = lab_nodes.mode()
    if now == HOME and pad in HELD_PADS:
        robot = lab_nodes.start_robot(object="egg")
        if not robot:
            return robot
        try:
            nodes = _student_nodes(Path(package), pad, feedback)
        except CourseError:
            robot.stop()
            raise
        return HeldPadApplication({"lab_sim": robot, **nodes}, pad)
    if now == LAB and pad not in (None, "pygame"):
        reason = start_refusal([Start("your teleoperation node (Ex. 14)", pad=pad)]) or \
            f"refused: in the lab your node reads the lab's gamepad, not the {pad} pad"
        print(reason)
        return NotStarted(reason)
    return lab_nodes.start_application(feedback, package)


def wait_for_quit(app: Any, timeout_s: float = 600.0, node: str = "/teleoperation") -> Optional[bool]:
    """Wait until the node of ``app`` quit (square on the pad): :func:`lab_nodes.wait_for_quit`.

    Not with the browser pad: a kernel busy with a cell cannot hear the page, so the pad would read
    released while this cell waits. Then it says so and returns None at once (drive, square quits).
    """
    if getattr(app, "pad", None) == "browser" and app.running:
        print("not waiting: with the browser pad the kernel must stay free to hear the page (a cell that waits "
              "would leave your pad released). Drive with the pad above; square quits your node; lab.stop() "
              "stops the rest")
        return None
    return lab_nodes.wait_for_quit(app, timeout_s, node)
