"""The plain-serial sensor board's line protocol (``firmware/fsr_serial``), parsed without I/O.

The fsr_serial sketch sends each count at 100 Hz as a checked text line instead of rosserial's
frames (the protocol: firmware/README.md). The host (``serial_bridge.py``, ``hardware.real.calibrate``)
must tell a good count from a line garbled by a loose cable or cut short by an unplug: sequence
numbers reveal lost lines, a CRC-8 corrupt ones. :func:`parse_line`, :class:`SequenceTracker`,
:class:`LineFramer` and :class:`BoardStream` do that; reading the port is the caller's job.
"""

from __future__ import annotations

import errno
from dataclasses import dataclass
from typing import Dict, List, Optional, Union

from hri_teleop.core.checks import ADC_MAX_COUNT, is_count
from hri_teleop.core.errors import HriTeleopError

__all__ = [
    "SerialProtocolError",
    "Sample",
    "BoardInfo",
    "LinkCounters",
    "SequenceTracker",
    "LineFramer",
    "BoardStream",
    "crc8",
    "format_line",
    "parse_line",
    "PROTOCOL_VERSION",
    "BAUD",
    "SEQ_MODULO",
    "MAX_COUNT",
    "MAX_LINE_BYTES",
    "BANNER_PREFIX",
    "REASONS",
    "open_error_message",
]

PROTOCOL_VERSION = 1
#: The sketch's baud rate (fast enough for 100 lines/s of at most 17 bytes with room to spare).
BAUD = 115200
#: ``seq`` counts modulo this (a 16-bit counter on the board).
SEQ_MODULO = 65536
#: Largest count a 10-bit ADC gives.
MAX_COUNT = ADC_MAX_COUNT
#: No valid line is longer (the banner is the longest, about 45 bytes); longer means garbage.
MAX_LINE_BYTES = 64
#: The start-up banner's first word: the board (re)started.
BANNER_PREFIX = "# fsr_serial"

#: Why a line was refused (``SerialProtocolError.reason``).
REASONS = ("format", "checksum", "range", "too_long", "encoding")


class SerialProtocolError(HriTeleopError, ValueError):
    """A line from the board is not a valid sample; ``reason`` is one of :data:`REASONS`."""

    def __init__(self, reason: str, line: bytes, detail: str) -> None:
        self.reason = reason
        self.line = bytes(line)
        super().__init__(f"corrupt line from the sensor board ({reason}: {detail}): {bytes(line)[:40]!r}")


@dataclass(frozen=True)
class Sample:
    """One count.  ``lost_before``: lines lost between the previous sample and this one."""

    seq: int
    count: int
    lost_before: int = 0


@dataclass(frozen=True)
class BoardInfo:
    """A ``#`` line.  ``restarted`` for the start-up banner; ``fields`` holds its ``key=value`` words."""

    text: str
    restarted: bool
    fields: Dict[str, str]


def crc8(data: bytes, crc: int = 0) -> int:
    """CRC-8/SMBUS (polynomial 0x07, init 0) of ``data``: what the sketch appends to each line.

    Why CRC-8 and not a sum: a sum misses two flipped bits that cancel and swapped digits
    ("517" vs "571"); CRC-8 catches every single flipped bit and every swap of two
    neighbouring digits in these lines (the unit tests check both), for a few microseconds
    of the Uno's time.
    """
    for byte in bytes(data):
        crc ^= byte
        for _ in range(8):
            crc = ((crc << 1) ^ 0x07) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc


def format_line(seq: int, count: int) -> bytes:
    """The line the sketch sends for one sample (the reference for tests and simulations)."""
    if not 0 <= int(seq) < SEQ_MODULO or not is_count(int(count)):
        raise SerialProtocolError("range", b"", f"seq {seq!r} not in 0..65535 or count {count!r} not in 0..1023")
    payload = f"F {int(seq)} {int(count)}".encode("ascii")
    return payload + b" %02X\n" % crc8(payload)


def _decimal(word: bytes, line: bytes, what: str, maximum: int) -> int:
    if not word.isdigit() or len(word) > 5 or (len(word) > 1 and word[:1] == b"0"):
        raise SerialProtocolError("format", line, f"{what} {word!r} is not a plain decimal number")
    value = int(word)
    if value > maximum:
        raise SerialProtocolError("range", line, f"{what} {value} is above {maximum}")
    return value


def parse_line(line: bytes) -> Union[Sample, BoardInfo]:
    """One line (with or without its ``\\n``) -> :class:`Sample` or :class:`BoardInfo`.

    Raises :class:`SerialProtocolError` for anything the protocol does not allow; its
    ``reason`` says which rule the line broke, so a caller can count and log by reason.
    """
    raw = bytes(line)
    body = raw[:-1] if raw.endswith(b"\n") else raw
    if body.endswith(b"\r"):
        body = body[:-1]
    if len(body) > MAX_LINE_BYTES:
        raise SerialProtocolError("too_long", raw, f"{len(body)} bytes, at most {MAX_LINE_BYTES}")
    if body.startswith(b"#"):
        try:
            text = body.decode("ascii")
        except UnicodeDecodeError:
            raise SerialProtocolError("encoding", raw, "not ASCII") from None
        if not text.isprintable():
            raise SerialProtocolError("encoding", raw, "control characters in an information line")
        fields = dict(w.split("=", 1) for w in text.split() if "=" in w)
        return BoardInfo(text=text, restarted=text.startswith(BANNER_PREFIX), fields=fields)
    words = body.split(b" ")
    if len(words) != 4 or words[0] != b"F":
        raise SerialProtocolError("format", raw, "expected 'F <seq> <count> <crc>'")
    crc_word = words[3]
    if len(crc_word) != 2 or any(c not in b"0123456789ABCDEF" for c in crc_word):
        raise SerialProtocolError("format", raw, f"checksum {crc_word!r} is not two upper-case hex digits")
    payload = body[: len(body) - 3]
    if crc8(payload) != int(crc_word, 16):
        raise SerialProtocolError("checksum", raw, f"CRC-8 is {crc8(payload):02X}, the line says {crc_word.decode()}")
    seq = _decimal(words[1], raw, "seq", SEQ_MODULO - 1)
    count = _decimal(words[2], raw, "count", MAX_COUNT)
    return Sample(seq=seq, count=count)


class SequenceTracker:
    """Lost lines from the gaps in ``seq`` (modulo 65536), and restarts from backward jumps."""

    #: A forward gap larger than this is a restart without banner (seq went backwards).
    MAX_GAP = SEQ_MODULO // 2

    def __init__(self) -> None:
        self.last_seq: Optional[int] = None

    def reset(self) -> None:
        """Forget the last ``seq``: after a banner, a reconnect or a reopen of the port."""
        self.last_seq = None

    def feed(self, seq: int) -> Optional[int]:
        """Lines lost just before ``seq``; ``None`` when ``seq`` says the board restarted."""
        last, self.last_seq = self.last_seq, int(seq)
        if last is None:
            return 0
        gap = (int(seq) - last - 1) % SEQ_MODULO
        if gap >= self.MAX_GAP:
            return None
        return gap


class LineFramer:
    """Splits the byte stream into lines; an overlong line is cut and the rest of it dropped.

    Why: a read returns whatever has arrived, which may end mid-line, and a board sending
    the wrong protocol (the rosserial sketch's binary frames) may send no ``\\n`` for a
    long time; the buffer must not grow without bound.
    """

    def __init__(self, max_line_bytes: int = MAX_LINE_BYTES) -> None:
        self.max_line_bytes = int(max_line_bytes)
        self._buffer = bytearray()
        self._discarding = False

    def reset(self) -> None:
        """Forget a half-received line, as after (re)opening the port."""
        self._buffer.clear()
        self._discarding = False

    def feed(self, data: bytes) -> List[bytes]:
        """Complete lines in ``data``, each ending in ``\\n``.

        A line longer than ``max_line_bytes`` comes out once as its first
        ``max_line_bytes + 1`` bytes (no ``\\n``, so :func:`parse_line` refuses it as
        too long); its remainder up to the next ``\\n`` is dropped.
        """
        lines: List[bytes] = []
        data = bytes(data)
        start = 0
        while start <= len(data):
            end = data.find(b"\n", start)
            piece = data[start:] if end < 0 else data[start:end + 1]
            start = len(data) + 1 if end < 0 else end + 1
            if self._discarding:
                if end >= 0:
                    self._discarding = False
                continue
            self._buffer += piece
            if end >= 0 and len(self._buffer) <= self.max_line_bytes + 1:
                lines.append(bytes(self._buffer))
                self._buffer.clear()
            elif len(self._buffer) > self.max_line_bytes:
                lines.append(bytes(self._buffer[: self.max_line_bytes + 1]))
                self._buffer.clear()
                self._discarding = end < 0
        return lines


@dataclass
class LinkCounters:
    """What a :class:`BoardStream` has seen since it was made (it survives reconnects).

    ``partial``: first lines after an open that did not parse; they are the tail of a line
    sent before the port was opened, not a fault, and are not counted as ``corrupt``.
    """

    samples: int = 0
    corrupt: int = 0
    lost: int = 0
    restarts: int = 0
    info_lines: int = 0
    partial: int = 0

    def summary(self) -> str:
        return (f"{self.samples} samples, {self.lost} lost, {self.corrupt} corrupt, "
                f"{self.restarts} board restarts")


Event = Union[Sample, BoardInfo, SerialProtocolError]


class BoardStream:
    """Bytes from the board -> events (samples, info lines, errors), counted in ``counters``.

    Call :meth:`reopened` after (re)opening the port: a half-received line is forgotten,
    the first line is allowed to be the tail of one sent before the open, and the next
    ``seq`` is not compared with one from before the gap.
    """

    def __init__(self) -> None:
        self.framer = LineFramer()
        self.tracker = SequenceTracker()
        self.counters = LinkCounters()
        self._first_line = True

    def reopened(self) -> None:
        self.framer.reset()
        self.tracker.reset()
        self._first_line = True

    def feed(self, data: bytes) -> List[Event]:
        """Every complete line in ``data`` as an event, in order; counters updated."""
        events: List[Event] = []
        for line in self.framer.feed(data):
            first, self._first_line = self._first_line, False
            try:
                parsed = parse_line(line)
            except SerialProtocolError as exc:
                if first:
                    self.counters.partial += 1
                else:
                    self.counters.corrupt += 1
                    events.append(exc)
                continue
            if isinstance(parsed, BoardInfo):
                self.counters.info_lines += 1
                if parsed.restarted:
                    self.counters.restarts += 1
                    self.tracker.reset()
                events.append(parsed)
                continue
            lost = self.tracker.feed(parsed.seq)
            if lost is None:
                self.counters.restarts += 1
                lost = 0
            self.counters.lost += lost
            self.counters.samples += 1
            events.append(Sample(seq=parsed.seq, count=parsed.count, lost_before=lost))
        return events


def open_error_message(port: str, error_number: Optional[int], detail: str, port_hint: str) -> str:
    """One line naming why ``port`` could not be opened and the fix.

    ``error_number`` is the ``errno`` of the failed open (pyserial's ``SerialException``
    carries it), ``detail`` the original text, ``port_hint`` how this program is told
    another port (``"port:=..."`` for a launch file, ``"--port ..."`` for a CLI).
    """
    if error_number in (errno.ENOENT, errno.ENODEV, errno.ENXIO):
        return (f"no serial port {port}: plug the board in or pass {port_hint} "
                "(`ls /dev/ttyACM* /dev/ttyUSB*` lists the boards)")
    if error_number in (errno.EACCES, errno.EPERM):
        return (f"no permission to open {port}: add yourself to the dialout group "
                "(`sudo usermod -aG dialout $USER`, then log in again)")
    if error_number == errno.EBUSY:
        return (f"serial port {port} is busy: close the program that holds it "
                "(Arduino IDE serial monitor, another bridge or serial_node)")
    return f"cannot open serial port {port} ({detail}): check the cable and the board, or pass {port_hint}"
