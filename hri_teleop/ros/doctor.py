"""``make doctor``: one line per part of a lab station, ok or not with the fix, in a few seconds.

The ROS master, the robot's side (the velocity command's subscriber, franka_gripper, error
recovery; or the simulation), the sensor board and its rate, ``/max_sensor_force``, the gamepad,
and the machine the real robot needs (verdicts: :mod:`hri_teleop.core.doctor`). At home with no
master it starts the simulated lab on a private roscore, checks it, and stops it.

    python -m hri_teleop.apps.doctor [--walk] [--port P] [--no-sim]
"""

from __future__ import annotations

import contextlib
import glob
import os
import time
from pathlib import Path
from typing import Any, Callable, Dict, Iterator, List, NamedTuple, Optional, Sequence, Tuple

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC, lab_max_sensor_force
from hri_teleop.core.doctor import (
    FAIL,
    NOTE,
    OK,
    Finding,
    board_rate_finding,
    calibration_finding,
    expected_board_hz,
    foreign_master_finding,
    governor_finding,
    kernel_finding,
    master_finding,
    measured_rate_hz,
    robot_finding,
    teleop_finding,
)
from hri_teleop.core.modes import HOME, LAB, ModeError, decide_mode, mode_from_env
from hri_teleop.core.robot_file import panda_file
from hri_teleop.hardware.real.board_probe import candidate_ports, probe_port
from hri_teleop.ros.doctor_pad import pad_findings
from hri_teleop.ros.master import MasterError, PrivateMaster, started_here
from hri_teleop.ros.master_api import MasterApiError, master_call, master_reachable, master_uri, running_nodes

__all__ = ["GRIPPER_ACTIONS", "BOARD_NODES", "check_master", "check_robot", "check_teleop", "check_board",
           "check_machine", "home_simulation", "run_checks", "SIM_READY_S"]

GRIPPER_ACTIONS: Tuple[str, ...] = panda_file()["gripper"]["actions"]  # the robot profile's
GRIPPER_NAMESPACE: str = panda_file()["gripper"]["namespace"]
#: Nodes that publish /pub_force, and which sketch (or stand-in) each means.
BOARD_NODES = {"/serial_node": "rosserial", "/serial_bridge": "fsr_serial", "/FSR_sensor": "simulation",
               "/lab_sim": "simulation"}
#: How long the doctor listens to /pub_force (s).
LISTEN_S = 1.5
#: How long the simulated lab may take to come up at home before the doctor gives up (s).
SIM_READY_S = 20.0


def _state() -> Tuple[List[Any], List[Any]]:
    publishers, subscribers, _services = master_call("getSystemState")
    return list(publishers), list(subscribers)


def _nodes(section: Sequence[Any], topic: str) -> List[str]:
    return next((list(nodes) for name, nodes in section if name == topic), [])


def check_master(mode: str) -> Tuple[Finding, bool]:
    uri = master_uri()
    reachable = master_reachable(uri)
    return master_finding(uri, reachable, mode, private=reachable and started_here(uri)), reachable


class _RobotSide(NamedTuple):
    """Who takes the twist (recorders left out), which franka_gripper servers answer, and recovery."""

    listeners: List[str]
    present: List[str]
    recovery: bool

    @classmethod
    def read(cls, publishers: Sequence[Any], subscribers: Sequence[Any]) -> "_RobotSide":
        listeners = [n for n in _nodes(subscribers, DEFAULT_TWIST_TOPIC) if not n.startswith("/record")]
        present = [a for a in GRIPPER_ACTIONS if _nodes(publishers, f"{GRIPPER_NAMESPACE}/{a}/status")]
        return cls(listeners, present, bool(_nodes(publishers, "/franka_control/error_recovery/status")))


def check_robot(mode: str) -> Finding:
    side = _RobotSide.read(*_state())
    missing = [f"franka_gripper/{a}" for a in GRIPPER_ACTIONS if a not in side.present]
    return robot_finding(mode, bool(side.listeners), side.present, missing, "/lab_sim" in side.listeners,
                         side.recovery)


def check_teleop(mode: str) -> Finding:
    running = bool(running_nodes(among=["/teleoperation"]))
    if not running:
        return teleop_finding(mode, False, None)
    return teleop_finding(mode, True, _param("/teleoperation/pad"), _latched_bool("/teleoperation/rumble_ok"))


def _latched_bool(topic: str, timeout_s: float = 1.0) -> Optional[bool]:
    """A latched std_msgs/Bool's value, or None when nobody publishes it (within ``timeout_s``)."""
    import rospy  # noqa: PLC0415 - only with a master: the machine checks run without ROS
    from std_msgs.msg import Bool  # noqa: PLC0415 - with rospy: only with a master

    if not _nodes(_state()[0], topic):
        return None
    _init_node()
    try:
        return bool(rospy.wait_for_message(topic, Bool, timeout=timeout_s).data)
    except rospy.ROSException:
        return None


def _init_node() -> None:
    import rospy  # noqa: PLC0415 - only with a master

    if not rospy.core.is_initialized():
        rospy.init_node("hri_doctor", anonymous=True, disable_signals=True)


def _sim_ready(master: PrivateMaster) -> bool:
    """lab_sim takes the twist and sends /pub_force, and its gripper and recovery servers answer."""
    publishers, subscribers, _services = master.system_state()
    side = _RobotSide.read(publishers, subscribers)
    return ("/lab_sim" in side.listeners and "/lab_sim" in _nodes(publishers, "/pub_force")
            and len(side.present) == len(GRIPPER_ACTIONS) and side.recovery)


@contextlib.contextmanager
def home_simulation(say: Callable[[str], None]) -> Iterator[PrivateMaster]:
    """The simulated station on a private roscore: lab_sim (arm, hand, board) and the lab's calibration,
    none of the student's deliverables; this process points at it while the checks run, then all stops."""
    saved: Dict[str, Optional[str]] = {k: os.environ.get(k) for k in ("ROS_MASTER_URI", "ROS_HOSTNAME", "ROS_IP")}
    started = time.monotonic()
    with PrivateMaster() as master:
        master.set_param("/max_sensor_force", lab_max_sensor_force())
        sim = master.run(["rosrun", "hri_lab", "lab_sim.py"], "lab_sim")
        master.wait_for(lambda: _sim_ready(master) or not sim.running, SIM_READY_S, "the simulated lab")
        if not sim.running:
            raise MasterError(f"lab_sim exited: {sim.output()[-600:]}")
        say(f"note  {'simulation':<17} no master: started the simulated lab on {master.uri} "
            f"({time.monotonic() - started:.1f} s); stopped after the checks")
        os.environ.update({"ROS_MASTER_URI": master.uri, "ROS_HOSTNAME": "127.0.0.1"})
        os.environ.pop("ROS_IP", None)
        try:
            yield master
        finally:
            for key, value in saved.items():
                if value is None:
                    os.environ.pop(key, None)
                else:
                    os.environ[key] = value
            master.stop(quick=True)


def _listen_pub_force(seconds: float) -> Tuple[List[int], List[float]]:
    """Counts on /pub_force and their arrival times, for ``seconds``, through a node of this process."""
    import rospy  # noqa: PLC0415 - only with a master: the machine checks run without ROS
    from std_msgs.msg import Int16  # noqa: PLC0415 - with rospy: only with a master

    _init_node()
    counts: List[int] = []
    times: List[float] = []

    def heard(message: Any) -> None:
        counts.append(int(message.data))
        times.append(time.monotonic())

    subscriber = rospy.Subscriber("/pub_force", Int16, heard)
    deadline = time.monotonic() + seconds + 1.0
    while subscriber.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.02)
    time.sleep(seconds)
    subscriber.unregister()
    return counts, times


def _board_on_master(mode: str, nodes: List[str]) -> Tuple[Finding, List[int]]:
    """The board a node publishes on /pub_force: a simulation (refused in the lab) or a sketch at its rate."""
    kind = next((BOARD_NODES[n] for n in nodes if n in BOARD_NODES), "a node")
    counts, times = _listen_pub_force(LISTEN_S)
    rate = measured_rate_hz(times)
    if kind == "simulation":
        if mode == LAB:
            return Finding("board", FAIL, f"{', '.join(nodes)} simulate the board on the lab's master",
                           "stop them: the Arduino's counts must be alone on /pub_force"), counts
        return Finding("board", OK, f"the simulated board ({nodes[0]}) at {rate or 0:.1f} Hz"), counts
    node = nodes[0]
    expected = expected_board_hz(kind, period_param_ms=_param(f"{node}/publish_period_ms"))
    port = _param(f"{node}/port") or "its port"
    return board_rate_finding(f"{port} ({node})", kind, rate, len(counts), expected), counts


def _board_on_port(port: str) -> Optional[Tuple[Finding, List[int]]]:
    """The sketch on a serial port nobody reads, or None when neither sketch answered."""
    reading = probe_port(port)
    if not reading.sketch:
        return None
    period_us = reading.banner_fields.get("period_us", "")
    expected = expected_board_hz(reading.sketch, banner_period_us=int(period_us) if period_us.isdigit() else None)
    finding = board_rate_finding(port, reading.sketch, reading.rate_hz, len(reading.counts), expected)
    if reading.banner and finding.status == OK:
        finding = Finding(finding.item, OK, f"{finding.detail}; {reading.banner}")
    return finding, reading.counts


def check_board(mode: str, reachable: bool, ports: Optional[Sequence[str]] = None) -> Tuple[Finding, List[int]]:
    """The board on the master (its node's /pub_force), or on a serial port when no node publishes one."""
    if reachable:
        nodes = _nodes(_state()[0], "/pub_force")
        if nodes:
            return _board_on_master(mode, nodes)
    ports = list(ports) if ports is not None else candidate_ports()
    if not ports:
        if mode == LAB:
            return Finding("board", FAIL, "no Arduino on a USB serial port",
                           "plug it in (ls /dev/ttyACM*), then roslaunch the lab's launch file"), []
        return Finding("board", NOTE, "no Arduino here: the simulated board sends /pub_force at home"), []
    for port in ports:
        try:
            found = _board_on_port(port)
        except (OSError, ValueError) as exc:
            return Finding("board", FAIL, f"{port}: cannot read it ({exc})",
                           "add yourself to the dialout group (sudo usermod -aG dialout $USER), log in again"), []
        if found is not None:
            return found
    return Finding("board", FAIL, f"{', '.join(ports)}: neither fsr_serial nor rosserial answers",
                   "upload a sketch (firmware/README.md); close the Arduino IDE's serial monitor"), []


def _nodes_besides_rosout() -> List[str]:
    """Every node registered at the master but roscore's own /rosout."""
    try:
        state = master_call("getSystemState")
    except MasterApiError:
        return []
    nodes = {node for section in state for _name, names in section for node in names}
    return sorted(nodes - {"/rosout"})


def _param(name: str) -> object:
    try:
        return master_call("getParam", name)
    except MasterApiError:
        return None


def check_calibration(counts: List[int], pressed: bool) -> Finding:
    return calibration_finding(_param("/max_sensor_force"), max(counts) if counts else None, pressed)


def _read(path: str) -> Optional[str]:
    try:
        return Path(path).read_text(encoding="utf-8").strip()
    except OSError:
        return None


def check_machine(mode: str) -> List[Finding]:
    governors = [g for g in (_read(p) for p in glob.glob("/sys/devices/system/cpu/cpu*/cpufreq/scaling_governor"))
                 if g]
    return [kernel_finding(mode, os.uname().version, _read("/sys/kernel/realtime")), governor_finding(mode, governors)]


def run_checks(walk: bool = False, ask: Callable[[str], str] = input, say: Callable[[str], None] = print,
               ports: Optional[Sequence[str]] = None, simulate: bool = True,
               skip: Callable[[], bool] = lambda: False) -> List[Finding]:
    """Every check in order, each line said as soon as it is known. At home with no master and
    ``simulate``, the checks run against the simulated lab, started for them and stopped after."""
    try:
        mode = mode_from_env(os.environ)
    except ModeError as exc:
        finding = Finding("mode", FAIL, str(exc), "export HRI_MODE=home (or lab on the lab PCs)")
        say(finding.line())
        return [finding]
    uri = master_uri()
    reachable = master_reachable(uri)
    if reachable:
        own = started_here(uri)
        if not own and mode != LAB and not _nodes_besides_rosout():
            # Lab mode only because somebody else started it (the lab PC's roscore, or one left open at home):
            # one line with both readings, rather than every lab check failing on an empty master.
            finding = foreign_master_finding(uri)
            say(finding.line())
            return [finding]
        mode = decide_mode(os.environ, own)  # a master this process's owner did not start: the lab's
    if simulate and mode == HOME and not reachable:
        try:
            with home_simulation(say):
                return _run_checks(mode, walk, ask, say, ports, skip)
        except MasterError as exc:
            say(Finding("simulation", FAIL, f"the simulated lab did not start: {str(exc).splitlines()[0]}",
                        "make setup, then make demo to see the whole error").line())
    return _run_checks(mode, walk, ask, say, ports, skip)


def _run_checks(mode: str, walk: bool, ask: Callable[[str], str], say: Callable[[str], None],
                ports: Optional[Sequence[str]], skip: Callable[[], bool]) -> List[Finding]:
    findings: List[Finding] = []

    def add(finding: Finding) -> None:
        findings.append(finding)
        say(finding.line())

    master, reachable = check_master(mode)
    add(master)
    if reachable:
        add(check_robot(mode))
        add(check_teleop(mode))
    else:
        add(Finding("robot", NOTE, "not checked: no master"))
    board, counts = check_board(mode, reachable, ports)
    add(board)
    pressed = False
    if walk and board.status == OK and reachable:
        answer = ask("      press the piston fully and hold it, then p and Enter (Enter alone: skip)")
        pressed = answer.strip().lower().startswith("p")
        if pressed:
            counts, _times = _listen_pub_force(LISTEN_S)
    if reachable:
        add(check_calibration(counts, pressed))
    for finding in pad_findings(mode, walk, ask, say, skip):
        add(finding)
    for finding in check_machine(mode):
        add(finding)
    return findings
