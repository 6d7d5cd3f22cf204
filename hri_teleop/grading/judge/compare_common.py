"""What every judge shares: the parts tables with their points, message helpers, process output.

What a process' output says: its exit, a crash, a write refused by the sandbox.
"""

from __future__ import annotations

import math
import re
from typing import Any, Dict, List, Optional, Sequence, Tuple

from hri_teleop.core.gripper import GRIPPER_MAX_WIDTH_M
from hri_teleop.grading.results import Part, not_judged
from hri_teleop.grading.run.records import ProcessFacts
from hri_teleop.grading.run.sandbox import OUTPUT_CAP_BYTES, describe_exit

#: Values on /force_mapped must be within this of the reference (Float32 carries ~7 digits).
TOLERANCE = 1e-6
TWIST_TOLERANCE = 1e-9

# Part names and points, per check (names are what students see; tests refer to the keys).
MAPPING: Dict[str, Tuple[str, float]] = {
    "sub": ("subscribes /pub_force with the type the sensor publishes", 3),
    "pub": ("publishes /force_mapped, one message per count", 3),
    "type": ("/force_mapped is std_msgs/Float32", 2),
    "values": ("maps 0../max_sensor_force to 0..1 (public trace, /max_sensor_force = 700)", 4),
    "clip": ("clips counts above /max_sensor_force to 1.0 (public trace)", 3),
    "hidden": ("takes the range from /max_sensor_force (hidden inputs, other values)", 5),
}
TELEOP: Dict[str, Tuple[str, float]] = {
    # 0 points: the template already builds (the constructor is given); it gates the parts below.
    "import": ("imports and builds Teleoperation(rate, k_trans, k_rot, k_gripper, deadzone)", 0),
    "gripper": ("gripper width: k_gripper / rate per tick while cross/circle is held, within "
                f"0..{GRIPPER_MAX_WIDTH_M:g} m", 3),
    "twist": ("sticks -> cartesian_velocity with the dead zone and k_trans / k_rot", 4),
    "toggle": ("triangle toggles translation <-> rotation once per press", 2),
    "rumble": ("rumble from the mapped force, limited to 0..1", 2),
    "node_start": ("node: starts and subscribes /force_mapped (std_msgs/Float32)", 2),
    "node_twist_topic": ("node: publishes geometry_msgs/Twist on /cartesian_velocity_controller/cmd_vel", 2),
    "node_width_topic": ("node: publishes std_msgs/Float32 on /gripper_width", 2),
    "node_twist": ("node: the published twist follows the sticks", 2),
    "node_width": ("node: the published gripper width follows cross", 1),
    "node_rumble": ("node: the rumble follows /force_mapped", 1),
    "node_quit": ("node: square brings the twist to zero and ends the node", 1),
}
SENSOR_LAUNCH: Dict[str, Tuple[str, float]] = {
    "parse": ("parses with roslaunch", 1),
    "nodes": ("starts FSR_sensor.py and mapping_node.py", 3),
    "param": ("sets /max_sensor_force (a count, 0 < value <= 1023)", 2),
    "yaml": ("Ex. 7 (voluntary): loads config/robot_params.yaml", 0),
    "flow": ("launched: /force_mapped flows as std_msgs/Float32 and stays in [0, 1]", 4),
}
TELEOP_LAUNCH: Dict[str, Tuple[str, float]] = {
    "parse": ("parses with roslaunch", 1),
    "nodes": ("starts teleoperation.py, gripper_manager.py and mapping_node.py", 3),
    "serial": ("starts rosserial_python's serial_node.py with ~port /dev/ttyACM0 (a string)", 2),
    "param": ("sets /max_sensor_force (a count, 0 < value <= 1023)", 2),
    "include": ("includes franka_control's franka_control_cartesian_velocity.launch", 2),
    "sim": ("launched in simulation: the pad moves the arm, closes the hand, and the force reaches /force_mapped", 4),
}
GRAPH: Dict[str, Tuple[str, float]] = {
    "format": ("graph.yaml has a list of nodes and a mapping of topics", 1),
    "nodes": ("the pipeline's nodes", 2),
    "types": ("the pipeline's topics and their message types", 3),
    "links": ("who publishes and who subscribes each topic", 3),
}

STUDENT_PACKAGES = ("hri_lab", "ros_intro")  # the handout has Ex. 2-6 done in ros_intro


def judged_part(table: Dict[str, Tuple[str, float]], key: str, passed: bool, message: str = "",
          plots: Sequence[str] = (), note: str = "") -> Part:
    name, points = table[key]
    return Part(name, points, passed, message, tuple(plots), note)


def not_judged_part(table: Dict[str, Tuple[str, float]], key: str, reason: str) -> Part:
    name, points = table[key]
    return not_judged(name, points, reason)


def fmt_value(value: Any) -> str:
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, dict) and "__repr__" in value:
        return str(value["__repr__"])
    if isinstance(value, dict) and "__missing__" in value:
        return f"no attribute {value['__missing__']}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(fmt_value(v) for v in value) + "]"
    return repr(value)


def as_float(value: Any) -> Optional[float]:
    if isinstance(value, bool) or value is None:
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


# -- what a process' output says ------------------------------------------------------------

_WRITE_ERROR = re.compile(r"(Read-only file system|Permission denied)\S*:?\s*'?([^'\n]*)")
#: A file outside the student's folder: not there at all while grading (the box shows the system, not the machine).
_ABSENT = re.compile(r"FileNotFoundError: \[Errno 2\] No such file or directory: '(/[^'\n]*)'")


def process_hints(facts: ProcessFacts) -> List[str]:
    """Student-readable reasons found in a process' exit and output (limits, writes outside...)."""
    tail = facts.output_tail
    hints: List[str] = []
    if facts.output_bytes >= OUTPUT_CAP_BYTES - 1024:
        hints.append(f"it printed more than the output limit of {OUTPUT_CAP_BYTES // (1024 * 1024)} MB and was "
                     "stopped: remove prints inside loops")
    match = _WRITE_ERROR.search(tail)
    if match:
        where = match.group(2).strip() or "a file"
        hints.append(f"it tried to write {where} outside its own folder: while grading (and on the lab PCs) "
                     "write only inside your package folder")
    absent = _ABSENT.search(tail)
    if absent and not match:
        hints.append(f"{absent.group(1)} is not there while grading, as nothing outside its own folder is: read and "
                     "write only inside your package folder (find it with rospkg or relative to __file__)")
    if "Resource temporarily unavailable" in tail or "can't start new thread" in tail:
        hints.append("it tried to start more processes or threads than allowed: do not fork or spawn in a loop")
    if "MemoryError" in tail or "Cannot allocate memory" in tail:
        hints.append("it used more memory than allowed (2 GB)")
    if "NotImplementedError" in tail:
        hints.append("a part marked YOUR CODE HERE still raises NotImplementedError: fill it in")
    return hints


#: The grader's workspace in a process' output: the student's files are named from their package instead.
_WORKSPACE_PATH = re.compile(r"/[^\s\"']*/ws/(?:hri_lab|ros_intro)/")


def _last_lines(text: str, n: int = 6) -> str:
    lines = [line for line in _WORKSPACE_PATH.sub("", str(text)).strip().splitlines() if line.strip()]
    return "\n".join("    " + line[:300] for line in lines[-n:])


def with_box_hints(crash_message: str, facts: ProcessFacts, what: str) -> str:
    """A crash's feedback, and what the box says about it: a write outside its folder, a fork loop at the process
    limit (the crash's own lines alone would not say why the call failed while grading)."""
    hints = [h for h in process_hints(facts) if "NotImplementedError" not in h]
    crowded = facts.problem if "processes and threads" in facts.problem else ""
    return (crash_message + ("\nhint: " + "; ".join(hints) if hints else "")
            + (f"\n{what} {crowded}" if crowded else ""))


def explain_process(facts: ProcessFacts, what: str) -> str:
    """'<what> <problem>. <hints>. Its last output: ...'"""
    problem = facts.problem or describe_exit(facts.exit_code)
    message = f"{what} {problem}"
    hints = process_hints(facts)
    if hints:
        message += "; " + "; ".join(hints)
    tail = _last_lines(facts.output_tail)
    if tail:
        message += "\n  its last output:\n" + tail
    return message
