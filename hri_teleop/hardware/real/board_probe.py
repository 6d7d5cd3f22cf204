"""Which sketch a sensor board on a serial port runs, and at what rate: fsr_serial's lines or rosserial's frames.

``make doctor`` opens a port only when no node reads it (two readers of one tty steal each other's
bytes). Opening restarts an Uno, whose first byte comes after about 1.6 s of boot: one open tries
fsr_serial's lines, then switches the baud rate and asks for rosserial's topics.
"""

from __future__ import annotations

import glob
import struct
import time
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional

import serial

from hri_teleop.core.doctor import FSR_SERIAL, ROSSERIAL, measured_rate_hz
from hri_teleop.core.rosserial_frames import (
    ID_PARAMETER_REQUEST,
    ID_PUBLISHER,
    ID_TIME,
    NO_PARAMETER,
    ROSSERIAL_BAUD,
    TOPIC_REQUEST,
    FrameReader,
    decode_topic_info,
    frame,
)
from hri_teleop.core.serial_protocol import BAUD, BoardInfo, BoardStream, Sample

__all__ = ["BoardReading", "candidate_ports", "probe_port", "PORT_PATTERNS"]

#: Where a USB Arduino appears on Linux (CDC ACM: the Uno; a USB-serial adapter: ttyUSB).
PORT_PATTERNS = ("/dev/ttyACM*", "/dev/ttyUSB*")


@dataclass(frozen=True)
class BoardReading:
    """What a port sent: its sketch, its banner or topics, the counts and when they came (s)."""

    port: str
    sketch: str  # "fsr_serial", "rosserial" or "" (nothing recognised)
    banner: str
    counts: List[int]
    times_s: List[float]
    banner_fields: Dict[str, str] = field(default_factory=dict)  # fsr_serial's key=value words

    @property
    def rate_hz(self) -> Optional[float]:
        return measured_rate_hz(self.times_s)


def candidate_ports() -> List[str]:
    """The serial ports a USB Arduino could be on, sorted."""
    return sorted(p for pattern in PORT_PATTERNS for p in glob.glob(pattern))


def _open(port: str, baud: int) -> Any:
    return serial.Serial(port, baud, timeout=0.02)


def _read_fsr_serial(ser: Any, boot_s: float, count_s: float) -> BoardReading:
    """Lines of the fsr_serial sketch: the banner, then counts for ``count_s`` from the first one."""
    stream = BoardStream()
    counts: List[int] = []
    times: List[float] = []
    banner: Optional[BoardInfo] = None
    deadline = time.monotonic() + boot_s
    while time.monotonic() < deadline:
        now = time.monotonic()
        for event in stream.feed(ser.read(max(1, ser.in_waiting))):
            if isinstance(event, BoardInfo) and event.restarted:
                banner = event
            elif isinstance(event, Sample):
                if not times:
                    deadline = now + count_s
                counts.append(event.count)
                times.append(now)
    sketch = FSR_SERIAL if counts or banner else ""
    if banner is None:
        return BoardReading(ser.port, sketch, "", counts, times)
    return BoardReading(ser.port, sketch, banner.text, counts, times, dict(banner.fields))


def _time_answer(now_s: float) -> bytes:
    """rosserial's answer to a board's time request: std_msgs/Time (sec, nsec) on ID_TIME."""
    return frame(ID_TIME, struct.pack("<II", int(now_s), int((now_s % 1) * 1e9)))


def _read_rosserial(ser: Any, boot_s: float, count_s: float) -> BoardReading:
    """rosserial: ask for the topics as serial_node does, answer the board's time requests (it sends
    nothing before one is answered), then count ``pub_force``'s frames for ``count_s``."""
    reader = FrameReader()
    counts: List[int] = []
    times: List[float] = []
    topics: List[str] = []
    pub_force: Optional[int] = None
    deadline = time.monotonic() + boot_s
    next_request = time.monotonic()
    while time.monotonic() < deadline:
        now = time.monotonic()
        if pub_force is None and now >= next_request:  # the board answers once it has booted
            ser.write(TOPIC_REQUEST)
            next_request = now + 0.5
        for f in reader.feed(ser.read(max(1, ser.in_waiting))):
            if f.topic_id == ID_PUBLISHER and f.payload:
                try:
                    info = decode_topic_info(f.payload)
                except ValueError:
                    continue
                topics.append(f"{info.topic_name} ({info.message_type})")
                if info.topic_name.strip("/") == "pub_force" and pub_force is None:
                    pub_force = info.topic_id
                    deadline = now + count_s
            elif f.topic_id == ID_TIME:
                ser.write(_time_answer(time.time()))
            elif f.topic_id == ID_PARAMETER_REQUEST:  # no serial_node here: the sketch's default period
                ser.write(frame(ID_PARAMETER_REQUEST, NO_PARAMETER))
            elif pub_force is not None and f.topic_id == pub_force and len(f.payload) >= 2:
                counts.append(struct.unpack_from("<h", f.payload)[0])
                times.append(now)
    return BoardReading(ser.port, ROSSERIAL if topics else "", ", ".join(topics), counts, times)


def probe_port(port: str, boot_s: float = 2.5, count_s: float = 2.0) -> BoardReading:
    """fsr_serial first (it speaks at once, 115200 baud), then rosserial (57600) on the same open port:
    opening restarts an Uno, a second open would wait for its boot again. ``sketch`` "" when neither answered."""
    with _open(port, BAUD) as ser:
        reading = _read_fsr_serial(ser, boot_s, count_s)
        if reading.sketch:
            return reading
        ser.baudrate = ROSSERIAL_BAUD
        ser.reset_input_buffer()
        return _read_rosserial(ser, 1.0, count_s)
