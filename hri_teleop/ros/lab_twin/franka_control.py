"""The lab twin's ``/franka_control``: the Panda's Cartesian velocity controller, error recovery and state controller.

As franka_ros's franka_control it takes the velocity command (``cmd_vel``), serves
``/franka_control/error_recovery`` and publishes the seven joints; the project's simulated arm
(:class:`hri_teleop.sim.arm.SimArm`, as lab_sim runs it) moves under the commands. With the
user stop engaged in the twin's folder (whichever franka_control runs reads it) commands are
counted and the arm stays. Counts: twists, non-zero twists, error recoveries.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy: the arm's 7 x 7 solve on one thread

import threading
import time
from pathlib import Path
from typing import Any, Optional

import actionlib
import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import JointState
from std_msgs.msg import Header

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.joints import FRANKA_JOINT_STATES_TOPIC, JOINT_NAMES
from hri_teleop.core.reflex import ERROR_RECOVERY_ACTION
from hri_teleop.ros import franka_msgs as fm
from hri_teleop.ros.lab_twin.counts import TWIN_DIR_ENV, CountsFile, read_activated
from hri_teleop.ros.params import fail, get_param, run_node
from hri_teleop.ros.stop_signals import init_node
from hri_teleop.sim.arm import SimArm
from hri_teleop.sim.world import LAB_ARM_CONFIG

__all__ = ["FrankaControlTwin", "main", "STATE_RATE_HZ", "LOOP_PERIOD_S", "ACTIVATED_POLL_S"]

#: franka_state_controller's publish_rate in franka_control.launch (Hz).
STATE_RATE_HZ = 30.0
#: How often the arm is run up to the present (s); it steps its 1 ms cycles in between.
LOOP_PERIOD_S = 0.002
#: How often the user stop's state is read again (s).
ACTIVATED_POLL_S = 0.1
#: How often the arm's position goes to the counts file while it moves (s).
POSITION_PERIOD_S = 0.1


class FrankaControlTwin:
    """The arm behind franka_control's interfaces, counting what reaches it."""

    def __init__(self, counts: Optional[CountsFile]) -> None:
        self.counts = counts
        self.state_rate_hz = get_param("~state_rate_hz", STATE_RATE_HZ, kind=float)
        if not 0.0 < self.state_rate_hz <= 1000.0:
            fail(f"parameter {rospy.get_name()}/state_rate_hz is {self.state_rate_hz!r}; set a rate in (0, 1000] Hz, "
                 f"e.g. {STATE_RATE_HZ:g}")
        self._lock = threading.Lock()
        self._t0 = time.monotonic()
        self.folder = os.environ.get(TWIN_DIR_ENV, "").strip()
        self.arm = SimArm(LAB_ARM_CONFIG, start_time_s=0.0)
        self.activated = self._read_activated()
        self._record("activated", self.activated)
        self._record("position_m", list(self.arm.position_m))
        self._record("start_position_m", list(self.arm.position_m))
        if self.arm.joint_positions is not None:  # the counts are complete before the first command
            self._record("joint_positions_rad", [round(v, 6) for v in self.arm.joint_positions])
        self.joints_pub = rospy.Publisher(FRANKA_JOINT_STATES_TOPIC, JointState, queue_size=5)
        self.recovery_server = actionlib.ActionServer(ERROR_RECOVERY_ACTION, fm.ErrorRecoveryAction,
                                                      self._on_error_recovery, auto_start=False)
        self.recovery_server.start()
        self.twist_sub = rospy.Subscriber(DEFAULT_TWIST_TOPIC, Twist, self._on_twist, queue_size=100,
                                          tcp_nodelay=True)
        rospy.loginfo("franka_control: Cartesian velocity commands on %s, error recovery on %s, joint states on %s "
                      "(%s)", DEFAULT_TWIST_TOPIC, ERROR_RECOVERY_ACTION, FRANKA_JOINT_STATES_TOPIC,
                      "activated" if self.activated else "user stop engaged: the arm stays")

    def _record(self, key: str, value: Any) -> None:
        if self.counts is not None:
            self.counts.set(key, value)

    def _count(self, key: str) -> None:
        if self.counts is not None:
            self.counts.add(key)

    def _read_activated(self) -> bool:
        """The user stop in the twin's folder (outside a twin: activated)."""
        if not self.folder:
            return True
        try:
            value = read_activated(Path(self.folder))
        except (OSError, ValueError) as exc:  # a file a person broke: keep the arm still
            value = exc
        if not isinstance(value, bool):
            rospy.logwarn_throttle(10.0, "the user stop's state in %s is %r: LabTwin.set_activated (or the twin's "
                                   "activate command) rewrites it; keeping the arm still" % (self.folder, value))
            return False
        return value

    def now(self) -> float:
        return time.monotonic() - self._t0

    def _on_twist(self, msg: Twist) -> None:
        twist = (msg.linear.x, msg.linear.y, msg.linear.z, msg.angular.x, msg.angular.y, msg.angular.z)
        self._count("twists")
        if any(value != 0.0 for value in twist):
            self._count("nonzero_twists")
        if not self.activated:
            self._count("ignored_twists")
            return
        now = self.now()
        with self._lock:
            self.arm.run_until(now)
            self.arm.command(twist, max(now, self.arm.time_s))

    def _on_error_recovery(self, handle: Any) -> None:
        now = self.now()
        with self._lock:
            self.arm.run_until(now)
            recovered = self.arm.recover(now)
            state = self.arm.state
        self._count("error_recoveries")
        message = "recovered from a reflex" if recovered else f"no reflex to recover from (the arm is {state})"
        handle.set_accepted(message)
        handle.set_succeeded(fm.ErrorRecoveryResult(), message)  # franka_control succeeds either way

    def run(self) -> int:
        state_period = 1.0 / self.state_rate_hz
        next_state = next_position = next_poll = 0.0
        wake = time.monotonic()
        while not rospy.is_shutdown():
            now = self.now()
            with self._lock:
                self.arm.run_until(now)
                q, dq = self.arm.joint_positions, self.arm.joint_velocities
                position = self.arm.position_m
            if now >= next_poll:
                next_poll = now + ACTIVATED_POLL_S
                self.activated = self._read_activated()
                self._record("activated", self.activated)
                self._record("arm_state", self.arm.state)
            if now >= next_position:
                next_position = now + POSITION_PERIOD_S
                self._record("position_m", [round(v, 6) for v in position])
                if q is not None:
                    self._record("joint_positions_rad", [round(v, 6) for v in q])
            if now >= next_state and q is not None and dq is not None:
                next_state = max(next_state + state_period, now)
                self.joints_pub.publish(JointState(header=Header(stamp=rospy.Time.now()), name=list(JOINT_NAMES),
                                                   position=list(q), velocity=list(dq), effort=[0.0] * 7))
            wake += LOOP_PERIOD_S
            delay = wake - time.monotonic()
            if delay > 0.0:
                time.sleep(delay)
            else:
                wake = time.monotonic()
        return 0


def main() -> int:
    init_node("franka_control")  # SIGINT/SIGTERM handled outside the handler (hri_teleop.ros.stop_signals)
    counts = CountsFile.from_env(rospy.get_name())
    try:
        return FrankaControlTwin(counts).run()
    finally:
        if counts is not None:
            counts.close(stopped=True)


if __name__ == "__main__":
    run_node(main)
