#!/usr/bin/env python3
"""Serial bridge (teleoperation.launch board:=serial): the fsr_serial board -> /pub_force.

The plain-serial sketch (``firmware/fsr_serial``) sends one checked text line per sample at 100 Hz
instead of rosserial's frames. This node reads them with pyserial and publishes each valid count as
std_msgs/Int16 on /pub_force, like the rosserial sketch, so mapping_node and teleoperation cannot
tell the boards apart. The protocol is hri_teleop.core.serial_protocol's; this script only moves
bytes, skips corrupt lines and reopens a port that went away (docs/ros-nodes.md).
"""

from __future__ import annotations

import time
from typing import Optional

import rospy
import serial
from std_msgs.msg import Int16

from hri_teleop.core.serial_protocol import (
    BAUD,
    BoardInfo,
    BoardStream,
    Sample,
    SerialProtocolError,
    open_error_message,
)
from hri_teleop.ros.params import fail, get_param, run_node
from hri_teleop.ros.stop_signals import init_node

PORT_HINT = "port:=... (roslaunch) or _port:=... (rosrun)"


def open_port(port: str, baud: int, read_timeout_s: float) -> serial.Serial:
    """The port opened for reading, with whatever it buffered before thrown away."""
    ser = serial.Serial(port, baud, timeout=read_timeout_s)
    ser.reset_input_buffer()
    return ser


def try_open(port: str, baud: int, read_timeout_s: float):
    """(port, None) when it opened, else (None, one-line message naming cause and fix)."""
    try:
        return open_port(port, baud, read_timeout_s), None
    except (serial.SerialException, OSError) as exc:
        return None, open_error_message(port, getattr(exc, "errno", None), str(exc), PORT_HINT)


class Bridge:
    """Reads the board, publishes samples, reports problems (throttled), reconnects."""

    def __init__(self, port: str, baud: int, reconnect_s: float, read_timeout_s: float,
                 log_every_s: float, silence_s: float) -> None:
        self.port, self.baud = port, baud
        self.reconnect_s, self.read_timeout_s = reconnect_s, read_timeout_s
        self.log_every_s, self.silence_s = log_every_s, silence_s
        self.stream = BoardStream()
        self.pub = rospy.Publisher("pub_force", Int16, queue_size=50)
        self.ser: Optional[serial.Serial] = None
        self._reported_corrupt = 0
        self._reported_lost = 0
        self._last_report = time.monotonic()
        self._last_error: Optional[SerialProtocolError] = None
        self._last_sample = time.monotonic()
        self._last_silence_warning = 0.0

    def start(self) -> None:
        ser, problem = try_open(self.port, self.baud, self.read_timeout_s)
        if ser is None:
            fail(problem or f"cannot open {self.port}")
        self._connected(ser)
        rospy.loginfo("serial bridge: reading %s at %d baud, publishing %s", self.port, self.baud,
                      self.pub.resolved_name)

    def _connected(self, ser: serial.Serial) -> None:
        self.ser = ser
        self.stream.reopened()
        self._last_sample = time.monotonic()

    def _disconnected(self, why: str) -> None:
        if self.ser is not None:
            try:
                self.ser.close()
            except (serial.SerialException, OSError):
                pass
        self.ser = None
        rospy.logwarn("serial bridge: lost %s (%s); reopening it every %.1f s", self.port, why, self.reconnect_s)

    def _reconnect(self) -> None:
        """Retry until the port is back or ROS shuts down."""
        lost_at = time.monotonic()
        last_problem = ""
        while not rospy.is_shutdown():
            ser, problem = try_open(self.port, self.baud, self.read_timeout_s)
            if ser is not None:
                self._connected(ser)
                rospy.loginfo("serial bridge: %s is back after %.1f s", self.port, time.monotonic() - lost_at)
                return
            if problem != last_problem:  # e.g. missing, then briefly not permitted while udev sets it up
                rospy.loginfo("serial bridge: still waiting: %s", problem)
                last_problem = problem or ""
            rospy.sleep(self.reconnect_s)

    def spin(self) -> None:
        while not rospy.is_shutdown():
            if self.ser is None:
                self._reconnect()
                continue
            try:
                data = self.ser.read(max(1, self.ser.in_waiting))
            except (serial.SerialException, OSError) as exc:
                self._disconnected(str(exc))
                continue
            self._handle(data)
            self._report(time.monotonic())

    def _handle(self, data: bytes) -> None:
        for event in self.stream.feed(data):
            if isinstance(event, Sample):
                self._last_sample = time.monotonic()
                self.pub.publish(Int16(data=event.count))
            elif isinstance(event, BoardInfo):
                if event.restarted:
                    rospy.loginfo("serial bridge: board started: %s", event.text.lstrip("# "))
                else:
                    rospy.loginfo("serial bridge: board says: %s", event.text.lstrip("# "))
            else:
                self._last_error = event

    def _report(self, now: float) -> None:
        """Warnings for corrupt and lost lines and for silence, at most every log_every_s."""
        if now - self._last_report < self.log_every_s:
            return
        counters = self.stream.counters
        corrupt = counters.corrupt - self._reported_corrupt
        lost = counters.lost - self._reported_lost
        if corrupt or lost:
            last = f"; last: {self._last_error}" if corrupt and self._last_error is not None else ""
            rospy.logwarn("serial bridge: %d corrupt line(s) skipped, %d line(s) lost in the last %.0f s "
                          "(check the USB cable)%s", corrupt, lost, now - self._last_report, last)
            self._reported_corrupt, self._reported_lost = counters.corrupt, counters.lost
            self._last_report = now
        if self.ser is not None and now - self._last_sample > self.silence_s:
            if now - self._last_silence_warning >= self.log_every_s:
                rospy.logwarn("serial bridge: no valid line from %s for %.0f s (%d corrupt so far): is the "
                              "fsr_serial sketch on the board and ~baud %d its rate? (the rosserial sketch "
                              "needs board:=rosserial)", self.port, now - self._last_sample, counters.corrupt,
                              self.baud)
                self._last_silence_warning = now
                self._last_report = now

    def close(self) -> None:
        if self.ser is not None:
            try:
                self.ser.close()
            except (serial.SerialException, OSError):
                pass
        rospy.loginfo("serial bridge: %s", self.stream.counters.summary())


def main() -> int:
    init_node("serial_bridge")  # SIGINT/SIGTERM handled outside the handler (hri_teleop.ros.stop_signals)
    name = rospy.get_name()
    port = get_param("~port", "/dev/ttyACM0", kind=str, fix="set it to the board's port, e.g. _port:=/dev/ttyACM0")
    baud = get_param("~baud", BAUD, kind=int, fix=f"set it to the sketch's baud rate, e.g. _baud:={BAUD}")
    reconnect_s = get_param("~reconnect_s", 0.5, kind=float, fix="set it to a duration in s, e.g. _reconnect_s:=0.5")
    read_timeout_s = get_param("~read_timeout_s", 0.05, kind=float,
                               fix="set it to a duration in s, e.g. _read_timeout_s:=0.05")
    log_every_s = get_param("~log_every_s", 5.0, kind=float, fix="set it to a duration in s, e.g. _log_every_s:=5")
    silence_s = get_param("~silence_s", 3.0, kind=float, fix="set it to a duration in s, e.g. _silence_s:=3")
    if not port:
        fail(f"parameter {name}/port is empty; set it to the board's port, e.g. port:=/dev/ttyACM0")
    if baud <= 0:
        fail(f"parameter {name}/baud is {baud!r}; set it to the sketch's baud rate, e.g. _baud:={BAUD}")
    for key, value in (("reconnect_s", reconnect_s), ("read_timeout_s", read_timeout_s),
                       ("log_every_s", log_every_s), ("silence_s", silence_s)):
        if not 0.0 < value <= 3600.0:
            fail(f"parameter {name}/{key} is {value!r}; set it to a duration in seconds between 0 and 3600")
    bridge = Bridge(port, baud, reconnect_s, read_timeout_s, log_every_s, silence_s)
    bridge.start()
    try:
        bridge.spin()
    finally:
        bridge.close()
    return 0


if __name__ == "__main__":
    run_node(main)
