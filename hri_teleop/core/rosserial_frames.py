"""The frames of rosserial's serial protocol and the few messages a force board and its host exchange, without I/O.

The handout's sketch speaks rosserial (57600 baud). ``make doctor`` asks such a board for its topics
and counts its ``/pub_force`` frames; the lab twin's serial_node and board speak both sides of it.
Frame: 0xff 0xfe, length (2 bytes LE), length checksum, topic id (2 bytes LE), payload, checksum
over topic id and payload. Messages are ROS 1 serialized (little-endian, strings length-prefixed).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import List, Tuple

from hri_teleop.core.errors import HriTeleopError

__all__ = ["ROSSERIAL_BAUD", "TOPIC_REQUEST", "ID_PUBLISHER", "ID_SUBSCRIBER", "ID_TIME", "ID_PARAMETER_REQUEST",
           "ID_LOG", "ID_TX_STOP", "NO_PARAMETER", "INT16_MD5", "Frame", "TopicInfo", "ParamAnswer", "FrameReader",
           "frame", "decode_topic_info", "encode_topic_info", "encode_time", "decode_time", "encode_param_request",
           "decode_param_request", "encode_param_answer", "decode_param_answer", "encode_int16", "decode_int16",
           "decode_log", "encode_log", "LOG_LEVELS", "FrameError"]

#: rosserial_arduino's default baud rate.
ROSSERIAL_BAUD = 57600
#: Topic id of a TopicInfo for a publisher (also of the host's request for the board's topics).
ID_PUBLISHER = 0
#: Topic id of time: the board's request (empty) and the host's answer (sec, nsec as uint32).
ID_TIME = 10
#: Topic id of a TopicInfo for a subscriber.
ID_SUBSCRIBER = 1
#: Topic id of a log line from the board (rosserial_msgs/Log: level, text).
ID_LOG = 7
#: Topic id the host sends when it stops (the board then waits for a new topic request).
ID_TX_STOP = 11
#: rosserial_msgs/Log's levels by number, as rospy names them.
LOG_LEVELS = {0: "debug", 1: "info", 2: "warn", 3: "error", 4: "fatal"}
#: std_msgs/Int16's MD5 sum: the TopicInfo a board announces /pub_force with.
INT16_MD5 = "8524586e34fbd7cb1c08c5f5f1ca0e57"
#: Topic id of a parameter request (the board's getParam) and of the host's answer.
ID_PARAMETER_REQUEST = 6
#: An answer with no value (rosserial_msgs/RequestParamResponse: no ints, floats or strings):
#: the board's getParam fails at once and the sketch keeps its default, instead of waiting.
NO_PARAMETER = bytes(12)
_SYNC = b"\xff\xfe"
#: The fix a malformed message names: its frame's checksum held, so the two ends disagree on its fields.
_VERSIONS = ("the board and its host speak different rosserial versions: build the sketch's ros_lib with "
             "this ROS (rosrun rosserial_arduino make_libraries.py)")


class FrameError(HriTeleopError, ValueError):
    """A message whose frame arrived whole but whose fields do not: too short, or empty."""


def _checksum(data: bytes) -> int:
    return 255 - (sum(data) % 256)


def frame(topic_id: int, payload: bytes) -> bytes:
    """The bytes of one frame, as rosserial writes it."""
    length = struct.pack("<H", len(payload))
    body = struct.pack("<H", topic_id) + payload
    return _SYNC + length + bytes([_checksum(length)]) + body + bytes([_checksum(body)])


#: What serial_node sends to ask the board for its topics: an empty frame on topic 0.
TOPIC_REQUEST = frame(ID_PUBLISHER, b"")


@dataclass(frozen=True)
class Frame:
    topic_id: int
    payload: bytes


@dataclass(frozen=True)
class TopicInfo:
    """rosserial_msgs/TopicInfo: how the board announces one of its topics."""

    topic_id: int
    topic_name: str
    message_type: str
    md5sum: str
    buffer_size: int


class FrameReader:
    """Feed it bytes as they come; it returns whole frames with good checksums and skips the rest."""

    def __init__(self) -> None:
        self._buffer = b""
        self.bad = 0  # frames with a wrong checksum

    def feed(self, data: bytes) -> List[Frame]:
        self._buffer += data
        frames: List[Frame] = []
        while True:
            start = self._buffer.find(_SYNC)
            if start < 0:
                self._buffer = self._buffer[-1:]  # a 0xff may be the first half of the next sync
                return frames
            buffer = self._buffer = self._buffer[start:]
            if len(buffer) < 5:
                return frames
            length = buffer[2:4]
            if _checksum(length) != buffer[4]:
                self.bad += 1
                self._buffer = buffer[1:]
                continue
            size = struct.unpack("<H", length)[0]
            end = 5 + 2 + size + 1
            if len(buffer) < end:
                return frames
            body = buffer[5:end - 1]
            if _checksum(body) == buffer[end - 1]:
                frames.append(Frame(struct.unpack("<H", body[:2])[0], body[2:]))
            else:
                self.bad += 1
            self._buffer = buffer[end:]


def _string(payload: bytes, at: int) -> Tuple[str, int]:
    size = struct.unpack_from("<I", payload, at)[0]
    start = at + 4
    if start + size > len(payload):  # cut short, like a number cut short: the callers' FrameError
        raise struct.error(f"a string of {size} bytes at offset {start}, {len(payload) - start} left")
    return payload[start:start + size].decode("utf-8", "replace"), start + size


def decode_topic_info(payload: bytes) -> TopicInfo:
    """A TopicInfo's fields from its serialized bytes (FrameError when they are cut short)."""
    try:
        topic_id = struct.unpack_from("<H", payload, 0)[0]
        name, at = _string(payload, 2)
        kind, at = _string(payload, at)
        md5, at = _string(payload, at)
        buffer_size = struct.unpack_from("<i", payload, at)[0]
    except struct.error as exc:
        raise FrameError(f"a TopicInfo cut short ({len(payload)} bytes: {exc}); {_VERSIONS}") from None
    return TopicInfo(topic_id, name, kind, md5, buffer_size)


def _text(value: str) -> bytes:
    data = value.encode("utf-8")
    return struct.pack("<I", len(data)) + data


def encode_topic_info(info: TopicInfo) -> bytes:
    """A TopicInfo's bytes, as the board's negotiateTopics sends them (the inverse of decode_topic_info)."""
    return (struct.pack("<H", info.topic_id) + _text(info.topic_name) + _text(info.message_type)
            + _text(info.md5sum) + struct.pack("<i", info.buffer_size))


def encode_time(sec: int, nsec: int) -> bytes:
    """std_msgs/Time: the host's answer to the board's time request."""
    return struct.pack("<II", sec, nsec)


def decode_time(payload: bytes) -> Tuple[int, int]:
    """(sec, nsec) of a time answer (FrameError when cut short)."""
    try:
        sec, nsec = struct.unpack_from("<II", payload, 0)
    except struct.error as exc:
        raise FrameError(f"a time cut short ({len(payload)} bytes: {exc}); {_VERSIONS}") from None
    return int(sec), int(nsec)


def encode_param_request(name: str) -> bytes:
    """rosserial_msgs/RequestParamRequest: the board's getParam of ``name``."""
    return _text(name)


def decode_param_request(payload: bytes) -> str:
    """The parameter name a board asks for (FrameError when cut short)."""
    try:
        name, _at = _string(payload, 0)
    except struct.error as exc:
        raise FrameError(f"a parameter request cut short ({len(payload)} bytes: {exc}); {_VERSIONS}") from None
    return name


@dataclass(frozen=True)
class ParamAnswer:
    """rosserial_msgs/RequestParamResponse: a parameter's value as ints, floats or strings (all empty: none)."""

    ints: Tuple[int, ...] = ()
    floats: Tuple[float, ...] = ()
    strings: Tuple[str, ...] = ()


def encode_param_answer(answer: ParamAnswer) -> bytes:
    """The host's answer to a parameter request; ``ParamAnswer()`` is :data:`NO_PARAMETER`."""
    out = struct.pack("<I", len(answer.ints)) + b"".join(struct.pack("<i", v) for v in answer.ints)
    out += struct.pack("<I", len(answer.floats)) + b"".join(struct.pack("<f", v) for v in answer.floats)
    return out + struct.pack("<I", len(answer.strings)) + b"".join(_text(v) for v in answer.strings)


def decode_param_answer(payload: bytes) -> ParamAnswer:
    """A parameter answer's values (FrameError when cut short)."""
    try:
        count = struct.unpack_from("<I", payload, 0)[0]
        ints = struct.unpack_from(f"<{count}i", payload, 4)
        at = 4 + 4 * count
        count = struct.unpack_from("<I", payload, at)[0]
        floats = struct.unpack_from(f"<{count}f", payload, at + 4)
        at += 4 + 4 * count
        count = struct.unpack_from("<I", payload, at)[0]
        at += 4
        strings = []
        for _ in range(count):
            text, at = _string(payload, at)
            strings.append(text)
    except struct.error as exc:
        raise FrameError(f"a parameter answer cut short ({len(payload)} bytes: {exc}); {_VERSIONS}") from None
    return ParamAnswer(tuple(int(v) for v in ints), tuple(float(v) for v in floats), tuple(strings))


def encode_int16(value: int) -> bytes:
    """std_msgs/Int16: the board's count on /pub_force."""
    return struct.pack("<h", value)


def decode_int16(payload: bytes) -> int:
    """A count from an Int16 frame (FrameError unless exactly 2 bytes)."""
    if len(payload) != 2:
        raise FrameError(f"an Int16 is 2 bytes, got {len(payload)}; {_VERSIONS}")
    return int(struct.unpack("<h", payload)[0])


def decode_log(payload: bytes) -> Tuple[str, str]:
    """(level name, text) of a rosserial_msgs/Log from the board (FrameError when empty or cut short)."""
    if not payload:
        raise FrameError(f"an empty log message; {_VERSIONS}")
    try:
        text, _at = _string(payload, 1)
    except struct.error as exc:
        raise FrameError(f"a log message cut short ({len(payload)} bytes: {exc}); {_VERSIONS}") from None
    return LOG_LEVELS.get(payload[0], str(payload[0])), text


def encode_log(level: int, text: str) -> bytes:
    """rosserial_msgs/Log: a board's loginfo/logwarn line (level as in :data:`LOG_LEVELS`)."""
    return bytes([level]) + _text(text)
