"""``make doctor``'s verdicts: what a finding says about the lab's machine, and the fix, as pure rules.

Each check of a station before a lab session (master, robot, board, calibration, pad, the real-time
kernel) ends in one :class:`Finding`: ok, a failure with the fix, or a note. The probing is
:mod:`hri_teleop.ros.doctor`'s; what counts as ok lives here, tested at each threshold.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

from hri_teleop.core.board_rates import HANDOUT_RATE_HZ, MAX_PERIOD_MS, MIN_PERIOD_MS, RECOMMENDED_RATE_HZ
from hri_teleop.core.checks import is_calibration_count, is_int
from hri_teleop.core.modes import LAB
from hri_teleop.core.traces import TraceError, rate_hz

__all__ = ["OK", "FAIL", "NOTE", "Finding", "exit_code", "master_finding", "foreign_master_finding", "robot_finding",
           "teleop_finding", "board_rate_finding", "expected_board_hz", "FSR_SERIAL", "ROSSERIAL", "calibration_finding",
           "pad_finding", "walk_finding", "rumble_finding", "kernel_finding", "governor_finding",
           "HANDOUT_SKETCH_HZ", "LAB_BOARD_HZ", "RATE_TOLERANCE", "CALIBRATION_TOLERANCE", "MIN_PERIOD_MS",
           "MAX_PERIOD_MS", "measured_rate_hz"]

OK, FAIL, NOTE = "ok", "FAIL", "note"
#: Between a finding's detail and its fix on the printed line.
FIX_MARK = "  -> "
FSR_SERIAL, ROSSERIAL = "fsr_serial", "rosserial"
#: The rosserial sketch sends a count every 300 ms without serial_node's ~publish_period_ms (the
#: handout's delay), at that period (5..10000 ms) with it; fsr_serial every 10 ms.
HANDOUT_SKETCH_HZ = HANDOUT_RATE_HZ
LAB_BOARD_HZ = RECOMMENDED_RATE_HZ
#: A board counts as sending at its rate within this fraction (USB scheduling, a busy host).
RATE_TOLERANCE = 0.1
#: A full press read live may differ this much from /max_sensor_force (parts differ by about 10 %).
CALIBRATION_TOLERANCE = 0.15


@dataclass(frozen=True)
class Finding:
    """One line of the report: ``status`` ok, FAIL or note; ``fix`` says what to do when not ok."""

    item: str
    status: str
    detail: str
    fix: str = ""

    def line(self) -> str:
        return f"{self.status:<5} {self.item:<17} {self.detail}" + (f"{FIX_MARK}{self.fix}" if self.fix else "")

    @classmethod
    def from_line(cls, line: str) -> Optional["Finding"]:
        """The finding a :meth:`line` printed (None for any other line: prompts, the summary)."""
        status = line[:5].strip()
        if status not in (OK, FAIL, NOTE) or len(line) < 24 or line[5] != " " or line[23] != " ":
            return None
        detail, _mark, fix = line[24:].partition(FIX_MARK)
        return cls(line[6:23].strip(), status, detail, fix)


def measured_rate_hz(times_s: Sequence[float]) -> Optional[float]:
    """Counts per second between the first and the last arrival (None: fewer than two, or no time between)."""
    try:
        return rate_hz([(t, 0.0) for t in times_s])
    except TraceError:
        return None


def exit_code(findings: Sequence[Finding]) -> int:
    """0 when nothing failed (notes are fine), 1 otherwise."""
    return 1 if any(f.status == FAIL for f in findings) else 0


def master_finding(uri: str, reachable: bool, mode: str, private: bool) -> Finding:
    """The ROS master: reachable, and whose (a private roscore at home, the lab's in the lab)."""
    if not reachable:
        fix = ("start the lab's roscore or launch file first" if mode == LAB
               else "start one: make demo (or roslaunch hri_lab teleoperation.launch sim:=true), or roscore")
        return Finding("ROS master", FAIL, f"none answers at {uri} ({mode} mode)", fix)
    if mode == LAB and private:
        return Finding("ROS master", FAIL, f"{uri} is a private roscore, not the lab's", "use the lab's ROS_MASTER_URI")
    return Finding("ROS master", OK, f"{uri} ({'a private roscore' if private else 'running'}, {mode} mode)")


def foreign_master_finding(uri: str) -> Finding:
    """A bare master this toolkit did not start, with lab mode only a guess: the cause and both fixes, one line."""
    return Finding("ROS master", FAIL,
                   f"a ROS master at {uri} that the toolkit did not start, with no node on it: it is treated as the "
                   "lab's (it may carry the robot), so nothing is simulated or checked there",
                   "on the lab PC this is right: start the lab's launch file (or HRI_MODE=lab make doctor checks the "
                   "bare station); at home stop that roscore (Ctrl-C in its terminal) and run make doctor again, which "
                   "then checks a simulated lab on a master of its own")


def robot_finding(mode: str, controller_listens: bool, gripper_servers: Sequence[str], missing_servers: Sequence[str],
                  simulated: bool, recovery: bool) -> Finding:
    """The robot's side: something takes the twist, the franka_gripper servers, the error recovery."""
    where = "the simulation (lab_sim)" if simulated else "franka_control"
    missing = list(missing_servers) + ([] if recovery else ["error_recovery"])
    if not controller_listens:
        fix = ("roslaunch franka_control franka_control_cartesian_velocity.launch (or the lab's launch file)"
               if mode == LAB else "roslaunch hri_lab teleoperation.launch sim:=true")
        return Finding("robot", FAIL, "nobody subscribes to the velocity command", fix)
    if missing:
        return Finding("robot", FAIL, f"{where} takes the twist, but {', '.join(missing)} missing",
                       "start franka_gripper (franka_control.launch load_gripper:=true)" if not simulated
                       else "restart lab_sim")
    if mode == LAB and simulated:
        return Finding("robot", FAIL, "lab_sim runs on the lab's master", "stop it: the real robot must be alone")
    return Finding("robot", OK, f"{where}: velocity command, gripper {', '.join(gripper_servers)}, error_recovery")


def teleop_finding(mode: str, running: bool, pad: object, rumble_ok: Optional[bool] = None) -> Finding:
    """The teleoperation node: running, which pad it reads (``pad`` its ``~pad`` parameter, None: unset), and
    its start check's ``~rumble_ok`` (None: not heard, e.g. a node from before the check or a student's own)."""
    if not running:
        return Finding("teleoperation", NOTE, "not running (roslaunch hri_lab teleoperation.launch starts it)")
    kind = pad if isinstance(pad, str) and pad else "the pad teleop.yaml names"
    reads = "the virtual pad" if kind == "virtual" else kind
    if rumble_ok is False:
        return Finding("teleoperation", FAIL, f"running with {reads}, whose pad refused the start check's rumble",
                       "no force feedback this way: a USB cable or another pad, then restart the launch")
    if mode == LAB and kind == "virtual":
        return Finding("teleoperation", NOTE, "running with the virtual pad: a notebook's widget drives the robot")
    return Finding("teleoperation", OK, f"running with {reads}" + ("; rumble accepted" if rumble_ok else ""))


def expected_board_hz(sketch: str, period_param_ms: object = None, banner_period_us: object = None) -> float:
    """The rate a board should send at: fsr_serial's from its banner (100 Hz when unknown); rosserial's from
    serial_node's ``~publish_period_ms`` when it is a count in the sketch's 5..10000 ms, else the handout's 300 ms."""
    if sketch == FSR_SERIAL:
        if is_int(banner_period_us) and int(banner_period_us) > 0:
            return 1e6 / int(banner_period_us)
        return LAB_BOARD_HZ
    if is_int(period_param_ms) and MIN_PERIOD_MS <= int(period_param_ms) <= MAX_PERIOD_MS:
        return 1000.0 / int(period_param_ms)
    return HANDOUT_SKETCH_HZ


def board_rate_finding(port: str, sketch: str, rate_hz: Optional[float], samples: int, expected_hz: float) -> Finding:
    """The sensor board on ``port``: which sketch, and whether it sends at the rate it should."""
    if rate_hz is None or samples < 2:
        return Finding("board", FAIL, f"{port}: {sketch}, no counts arrived",
                       "check the cable and that the sketch is uploaded (firmware/README.md)")
    if abs(rate_hz - expected_hz) > RATE_TOLERANCE * expected_hz:
        return Finding("board", FAIL, f"{port}: {sketch} at {rate_hz:.1f} Hz, expected {expected_hz:.1f} Hz",
                       "re-upload the sketch, or check that nothing else reads the port")
    return Finding("board", OK, f"{port}: {sketch} at {rate_hz:.1f} Hz ({samples} counts)")


def calibration_finding(value: object, live_max: Optional[int], pressed: bool) -> Finding:
    """/max_sensor_force: set, a count in 1..1023, above what the sensor reads at rest, and near a full
    press when one was read (``pressed``); ``live_max`` is the largest count heard (None: none heard)."""
    if value is None:
        return Finding("max_sensor_force", FAIL, "not set", "calibrate (Ex. 11) and set it: hri_lab/config/"
                       "calibration.yaml, or rosparam set /max_sensor_force <count>")
    if not is_calibration_count(value):
        return Finding("max_sensor_force", FAIL, f"{value!r} is not a count in 1..1023",
                       "set the count you read at full piston travel (Ex. 11), e.g. 700")
    if live_max is None:
        return Finding("max_sensor_force", OK, f"{value} (no live reading to compare)")
    if pressed:
        if abs(live_max - value) > CALIBRATION_TOLERANCE * value:
            return Finding("max_sensor_force", FAIL, f"{value}, but a full press reads {live_max} now",
                           "calibrate again (Ex. 11): the FSR or its seat changed")
        return Finding("max_sensor_force", OK, f"{value}; a full press reads {live_max}")
    if live_max > value:
        return Finding("max_sensor_force", FAIL, f"{value}, but the sensor reads {live_max} now, above it",
                       "release the piston and run again; if it reads that at rest, calibrate again (Ex. 11)")
    return Finding("max_sensor_force", OK, f"{value}; the sensor reads up to {live_max} now (--walk: compare a full press)")


def pad_finding(mode: str, found: Optional[str], layout: Optional[str], layout_reason: str) -> Finding:
    """The gamepad SDL sees (``found`` describes it, None: none) and the layout identified for it."""
    if found is None:
        if mode == LAB:
            return Finding("pad", FAIL, "no gamepad", "plug the pad in (USB); `ls /dev/input/js*` should list it")
        return Finding("pad", NOTE, "no gamepad: the virtual pad (or widgets.BrowserPad) stands in at home")
    if layout is None:
        return Finding("pad", NOTE, f"{found}; layout not identified ({layout_reason})",
                       "pick one: layout:=dualshock4 | dualsense | dualsense_hid_generic | xbox, then WALK=1 to check it")
    return Finding("pad", OK, f"{found}; layout {layout} ({layout_reason})")


def walk_finding(wrong: Sequence[str], unseen: Sequence[str]) -> Finding:
    """The walk-through: a control read under another name fails; controls skipped or not pressed are noted."""
    if wrong:
        return Finding("pad buttons", FAIL, "; ".join(wrong),
                       "pick this pad's layout (layout:=..., hri_teleop/core/gamepad/layouts/) or add one")
    if unseen:
        return Finding("pad buttons", NOTE, f"not tried: {', '.join(unseen)}")
    return Finding("pad buttons", OK, "every button and stick the lab uses reads as it should")


def rumble_finding(accepted: bool, felt: Optional[bool]) -> Finding:
    """The rumble probe: refused by the pad, accepted (``felt`` None: nobody asked), felt or not felt."""
    if not accepted:
        return Finding("rumble", FAIL, "the pad refuses to rumble: no force feedback with it",
                       "use a USB cable or another pad (some Bluetooth links carry no rumble); the driver needs "
                       "force feedback and /dev/input/event* writable")
    if felt is None:
        return Finding("rumble", OK, "accepted by the pad (--walk asks whether you felt it)")
    if felt:
        return Finding("rumble", OK, "accepted and felt")
    return Finding("rumble", FAIL, "accepted but not felt", "check the pad's battery and connection; try USB")


def kernel_finding(mode: str, version: str, realtime_flag: Optional[str]) -> Finding:
    """The real-time kernel libfranka asks for (``uname -v`` says PREEMPT_RT, or /sys/kernel/realtime is 1)."""
    realtime = "PREEMPT_RT" in version or (realtime_flag or "").strip() == "1"
    if realtime:
        return Finding("real-time kernel", OK, "PREEMPT_RT")
    if mode == LAB:
        return Finding("real-time kernel", FAIL, "not a PREEMPT_RT kernel",
                       "boot the lab PC's real-time kernel (libfranka refuses to control the robot without it)")
    return Finding("real-time kernel", NOTE, "not PREEMPT_RT: fine at home, the robot's PC needs one")


def governor_finding(mode: str, governors: Sequence[str]) -> Finding:
    """The CPU frequency governor: ``performance`` on every core where the robot is controlled."""
    if not governors:
        return Finding("CPU governor", NOTE, "no cpufreq here (a virtual machine?)")
    slow = sorted(set(g for g in governors if g != "performance"))
    if not slow:
        return Finding("CPU governor", OK, f"performance on {len(governors)} cores")
    if mode == LAB:
        return Finding("CPU governor", FAIL, f"{', '.join(slow)} on some cores",
                       "sudo cpupower frequency-set -g performance (frequency changes cost the 1 kHz loop)")
    return Finding("CPU governor", NOTE, f"{', '.join(slow)}: fine at home, the robot's PC needs performance")
