"""The lab twin's ``/serial_node``: the host side of rosserial, as rosserial_python's serial_node.py speaks it.

It opens ``~port`` (the board's pty; run from the twin's installed serial_node.py, the twin's board
whatever ``~port`` says) at ``~baud``, asks the board for its topics (again after ``~timeout`` s of
silence), publishes what it sends, answers time and parameter requests (a missing one unanswered,
as rosserial_python does) and logs its log lines. Counts: frames, messages per topic, time and
parameter answers.
"""

from __future__ import annotations

import os
import select
import termios
import time
import tty
from typing import Any, Dict, Optional

import roslib.message
import rospy

from hri_teleop.core.rosserial_frames import (
    ID_LOG,
    ID_PARAMETER_REQUEST,
    ID_PUBLISHER,
    ID_TIME,
    ID_TX_STOP,
    ROSSERIAL_BAUD,
    TOPIC_REQUEST,
    FrameReader,
    ParamAnswer,
    decode_log,
    decode_param_request,
    decode_topic_info,
    encode_param_answer,
    encode_time,
    frame,
)
from hri_teleop.ros.lab_twin.counts import TWIN_BOARD_PORT_ENV, CountsFile
from hri_teleop.ros.params import fail, get_param, run_node
from hri_teleop.ros.stop_signals import init_node

__all__ = ["RosserialHost", "param_answer", "main", "SYNC_TIMEOUT_S"]

#: rosserial_python's timeout: no frame from the board for this long -> ask for its topics again (s).
SYNC_TIMEOUT_S = 5.0
_BAUDS = {9600: termios.B9600, 19200: termios.B19200, 38400: termios.B38400, 57600: termios.B57600,
          115200: termios.B115200}


def param_answer(value: Any) -> Optional[ParamAnswer]:
    """A parameter's value as rosserial sends it (ints, floats or strings; a list of one kind), None if it cannot."""
    values = value if isinstance(value, list) else [value]
    if values and all(isinstance(v, bool) for v in values):
        return ParamAnswer(ints=tuple(int(v) for v in values))
    if all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return ParamAnswer(ints=tuple(values))
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        return ParamAnswer(floats=tuple(float(v) for v in values))
    if all(isinstance(v, str) for v in values):
        return ParamAnswer(strings=tuple(values))
    return None


class RosserialHost:
    """serial_node's side of the line: frames in, topics, time and parameters out."""

    def __init__(self, fd: int, counts: Optional[CountsFile], timeout_s: float) -> None:
        self.fd = fd
        self.counts = counts
        self.timeout_s = timeout_s
        self.reader = FrameReader()
        self.publishers: Dict[int, Any] = {}  # topic id -> (publisher, message class)
        self._last_frame = time.monotonic()

    def _count(self, key: str, item: Optional[str] = None) -> None:
        if self.counts is None:
            return
        if item is None:
            self.counts.add(key)
        else:
            self.counts.add_to(key, item)

    def send(self, data: bytes) -> None:
        try:
            os.write(self.fd, data)
        except OSError as exc:
            rospy.logwarn_throttle(5.0, "cannot write to the board: %s" % exc)

    def request_topics(self) -> None:
        self.send(TOPIC_REQUEST)
        self._count("topic_requests")

    def spin_once(self, wait_s: float) -> None:
        ready, _w, _x = select.select([self.fd], [], [], wait_s)
        now = time.monotonic()
        if ready:
            try:
                data = os.read(self.fd, 4096)
            except OSError:
                data = b""
            for message in self.reader.feed(data):
                self._last_frame = now
                self._on_frame(message.topic_id, message.payload)
        if now - self._last_frame > self.timeout_s:
            rospy.logwarn("Lost sync with device, restarting...")
            self._last_frame = now
            self.request_topics()

    def _on_frame(self, topic_id: int, payload: bytes) -> None:
        self._count("frames")
        if topic_id == ID_PUBLISHER:
            self._setup_publisher(payload)
        elif topic_id == ID_TIME:
            now = rospy.Time.now()
            self.send(frame(ID_TIME, encode_time(now.secs, now.nsecs)))
            self._count("time_answers")
        elif topic_id == ID_PARAMETER_REQUEST:
            self._answer_param(payload)
        elif topic_id == ID_LOG:
            self._log(payload)
        elif topic_id in self.publishers:
            publisher, cls = self.publishers[topic_id]
            msg = cls()
            try:
                msg.deserialize(payload)
            except Exception as exc:  # noqa: BLE001 - genpy raises its own DeserializationError or struct.error
                rospy.logwarn_throttle(5.0, "a bad %s frame from the board: %s" % (publisher.resolved_name, exc))
                return
            publisher.publish(msg)
            self._count("published", publisher.resolved_name)
            if self.counts is not None and isinstance(getattr(msg, "data", None), (int, float)):
                self.counts.set("last_data", {publisher.resolved_name: msg.data})
        elif topic_id != ID_TX_STOP:
            rospy.logwarn_throttle(5.0, "frame on unknown topic id %d: ask the board for its topics again" % topic_id)

    def _setup_publisher(self, payload: bytes) -> None:
        try:
            info = decode_topic_info(payload)
        except ValueError as exc:
            rospy.logwarn("a bad TopicInfo from the board: %s" % exc)
            return
        cls = roslib.message.get_message_class(info.message_type)
        if cls is None or cls._md5sum != info.md5sum:
            rospy.logerr("Creation of publisher failed: %s (%s, md5 %s) is not a message type here",
                         info.topic_name, info.message_type, info.md5sum)
            return
        current = self.publishers.get(info.topic_id)
        if current is None or current[0].resolved_name != rospy.resolve_name(info.topic_name):
            self.publishers[info.topic_id] = (rospy.Publisher(info.topic_name, cls, queue_size=10), cls)
            rospy.loginfo("Setup publisher on %s [%s]", info.topic_name, info.message_type)
        self._count("topics_announced")

    def _answer_param(self, payload: bytes) -> None:
        try:
            name = decode_param_request(payload)
        except ValueError as exc:
            rospy.logwarn("a bad parameter request from the board: %s" % exc)
            return
        self._count("param_requests", name)
        try:
            value = rospy.get_param(name)
        except KeyError:
            rospy.logerr("Parameter %s does not exist", name)
            return  # unanswered, as rosserial_python: the board's getParam times out
        answer = param_answer(value)
        if answer is None:
            rospy.logerr("Parameter %s has a type rosserial cannot send: %r", name, value)
            return
        self.send(frame(ID_PARAMETER_REQUEST, encode_param_answer(answer)))
        self._count("param_answers", name)

    def _log(self, payload: bytes) -> None:
        try:
            level, text = decode_log(payload)
        except ValueError:
            return
        {"debug": rospy.logdebug, "info": rospy.loginfo, "warn": rospy.logwarn}.get(level, rospy.logerr)(text)
        self._count("board_log_lines")


def open_port(port: str, baud: int) -> int:
    """The board's serial port opened raw at ``baud``; one fatal line naming the port when it cannot be."""
    try:
        fd = os.open(port, os.O_RDWR | os.O_NOCTTY)
    except OSError as exc:
        fail(f"cannot open {port} ({exc.strerror}): plug the Arduino in and set ~port to its device "
             "(ls /dev/ttyACM*), or add yourself to the dialout group")
    tty.setraw(fd)
    attrs = termios.tcgetattr(fd)
    attrs[4] = attrs[5] = _BAUDS[baud]
    termios.tcsetattr(fd, termios.TCSANOW, attrs)
    return fd


def main() -> int:
    init_node("serial_node")  # SIGINT/SIGTERM handled outside the handler (hri_teleop.ros.stop_signals)
    port = get_param("~port", "/dev/ttyUSB0", kind=str)
    baud = get_param("~baud", ROSSERIAL_BAUD, kind=int)
    if baud not in _BAUDS:
        fail(f"parameter {rospy.get_name()}/baud is {baud!r}; use {ROSSERIAL_BAUD} (the sketch's)")
    timeout_s = get_param("~timeout", SYNC_TIMEOUT_S, kind=float)
    board = os.environ.get(TWIN_BOARD_PORT_ENV, "").strip()
    if board:
        rospy.loginfo("lab twin: ~port %s is the twin's board at %s", port, board)
        port = board
    fd = open_port(port, baud)
    counts = CountsFile.from_env(rospy.get_name())
    host = RosserialHost(fd, counts, timeout_s)
    rospy.loginfo("Connecting to %s at %d baud", port, baud)
    try:
        host.request_topics()
        while not rospy.is_shutdown():
            host.spin_once(0.01)
        host.send(frame(ID_TX_STOP, b""))
    finally:
        os.close(fd)
        if counts is not None:
            counts.close(stopped=True)
    return 0


if __name__ == "__main__":
    run_node(main)
