"""The frames of rosserial's serial protocol, parsed without I/O, enough to ask a board for its topics and count them.

The handout's sketch speaks rosserial (57600 baud). ``make doctor`` checks such a board without
serial_node: it sends rosserial's topic request, reads the TopicInfo the board answers with, and
counts its ``/pub_force`` frames. Frame: 0xff 0xfe, length (2 bytes LE), length checksum, topic id
(2 bytes LE), payload, checksum over topic id and payload.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import List, Tuple

__all__ = ["ROSSERIAL_BAUD", "TOPIC_REQUEST", "ID_PUBLISHER", "ID_TIME", "ID_PARAMETER_REQUEST", "NO_PARAMETER", "Frame", "TopicInfo", "FrameReader", "frame",
           "decode_topic_info"]

#: rosserial_arduino's default baud rate.
ROSSERIAL_BAUD = 57600
#: Topic id of a TopicInfo for a publisher (also of the host's request for the board's topics).
ID_PUBLISHER = 0
#: Topic id of time: the board's request (empty) and the host's answer (sec, nsec as uint32).
ID_TIME = 10
#: Topic id of a parameter request (the board's getParam) and of the host's answer.
ID_PARAMETER_REQUEST = 6
#: An answer with no value (rosserial_msgs/RequestParamResponse: no ints, floats or strings):
#: the board's getParam fails at once and the sketch keeps its default, instead of waiting.
NO_PARAMETER = bytes(12)
_SYNC = b"\xff\xfe"


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
    return payload[start:start + size].decode("utf-8", "replace"), start + size


def decode_topic_info(payload: bytes) -> TopicInfo:
    """A TopicInfo's fields from its serialized bytes (ValueError when they are cut short)."""
    try:
        topic_id = struct.unpack_from("<H", payload, 0)[0]
        name, at = _string(payload, 2)
        kind, at = _string(payload, at)
        md5, at = _string(payload, at)
        buffer_size = struct.unpack_from("<i", payload, at)[0]
    except struct.error as exc:
        raise ValueError(f"a TopicInfo cut short ({len(payload)} bytes): {exc}") from None
    return TopicInfo(topic_id, name, kind, md5, buffer_size)
