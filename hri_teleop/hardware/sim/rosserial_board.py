"""The handout's rosserial sketch as a stand-in board: a piston, the sketch's logic, and a pseudo-terminal.

Debian has no rosserial Arduino library, so the lab twin's board is this: :class:`Piston` gives the
FSR count (a small count at rest, a press someone asks for), :class:`SketchBoard` answers a rosserial
host as ``firmware/arduino_code_force_node`` does (topics on request, time sync, ``~publish_period_ms``
with the sketch's 500 ms timeout and 5..10000 ms range, a count every period without bursts), and
:class:`PtyBoard` runs it on the master side of a pty whose other end a host opens like a serial port.
Frames: :mod:`hri_teleop.core.rosserial_frames`.
"""

from __future__ import annotations

import os
import select
import threading
import time
import tty
from dataclasses import dataclass
from typing import Callable, List, Optional, Tuple

from hri_teleop.core.board_rates import HANDOUT_PERIOD_S, MAX_PERIOD_MS, MIN_PERIOD_MS
from hri_teleop.core.checks import ADC_MAX_COUNT, is_finite_number, is_int
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.rosserial_frames import (
    ID_LOG,
    ID_PARAMETER_REQUEST,
    ID_PUBLISHER,
    ID_TIME,
    ID_TX_STOP,
    INT16_MD5,
    Frame,
    FrameReader,
    TopicInfo,
    decode_param_answer,
    decode_time,
    encode_int16,
    encode_log,
    encode_param_request,
    encode_topic_info,
    frame,
)
from hri_teleop.sim.board import BoardConfig, SensorBoard

__all__ = ["BoardStandInError", "REST_COUNT", "FULL_PRESS_COUNT", "PRESS_RAMP_S", "PARAM_TIMEOUT_S",
           "PUB_FORCE_ID", "Piston", "SketchBoard", "PtyBoard"]

#: The count a piston at rest gives (an FSR with nothing on it still reads a little).
REST_COUNT = 12
#: A full press of the piston (the lab's calibration is near it).
FULL_PRESS_COUNT = 700
#: How long a press takes to reach its count, and to come back to rest (s).
PRESS_RAMP_S = 0.2
#: The sketch's getParam timeout (FORCE_NODE_PARAM_TIMEOUT_MS).
PARAM_TIMEOUT_S = 0.5
#: The topic id the sketch's only publisher gets (rosserial numbers publishers from 125).
PUB_FORCE_ID = 125
#: rosserial_arduino asks for the time again this often once connected (SYNC_SECONDS).
SYNC_PERIOD_S = 5.0
#: ... and counts as disconnected without an answer for this long (SYNC_SECONDS * 2.2).
SYNC_LOST_S = 11.0
_PERIOD_PARAM = "~publish_period_ms"
_INFO, _WARN = 1, 2


class BoardStandInError(HriTeleopError, ValueError):
    """A press or a board setting that cannot be used (the message names the fix)."""


class Piston:
    """The FSR piston: at rest ``rest_count``; a press ramps to its count, holds, and ramps back."""

    def __init__(self, rest_count: int = REST_COUNT, ramp_s: float = PRESS_RAMP_S) -> None:
        self.rest_count = int(rest_count)
        self.ramp_s = float(ramp_s)
        self._press: Optional[Tuple[float, int, float]] = None  # (start, count, hold)
        self.presses = 0

    def press(self, count: int, hold_s: float, now_s: float) -> None:
        """Press to ``count`` (0..1023) and hold it ``hold_s`` seconds from ``now_s``, then let go."""
        if not is_int(count) or not 0 <= count <= ADC_MAX_COUNT:
            raise BoardStandInError(f"a press count must be a whole count in 0..{ADC_MAX_COUNT}, got {count!r}; "
                                    f"e.g. {FULL_PRESS_COUNT} for a full press")
        if not is_finite_number(hold_s) or hold_s < 0:
            raise BoardStandInError(f"a press hold must be a time in s >= 0, got {hold_s!r}; e.g. 2")
        self._press = (float(now_s), int(count), float(hold_s))
        self.presses += 1

    def count_at(self, now_s: float) -> int:
        """The count the FSR gives at ``now_s``."""
        if self._press is None:
            return self.rest_count
        start, count, hold = self._press
        elapsed = now_s - start
        ramp = self.ramp_s
        if elapsed < 0:
            return self.rest_count
        if elapsed < ramp:
            share = elapsed / ramp
        elif elapsed < ramp + hold:
            share = 1.0
        elif elapsed < 2 * ramp + hold:
            share = 1.0 - (elapsed - ramp - hold) / ramp
        else:
            self._press = None
            return self.rest_count
        return int(round(self.rest_count + share * (count - self.rest_count)))

    @property
    def pressing(self) -> bool:
        return self._press is not None


@dataclass
class BoardStats:
    """What the board did, for the twin's report (times on the board's clock, s)."""

    announced: int = 0
    time_requests: int = 0
    time_answers: int = 0
    last_time: Optional[Tuple[int, int]] = None  # (sec, nsec) of the host's last time answer
    param_answers: int = 0  # answers to ~publish_period_ms, with a value or without
    period_from_param: bool = False  # the period in use came from the parameter
    period_ms: int = 0
    samples_sent: int = 0
    first_sample_s: Optional[float] = None
    last_sample_s: Optional[float] = None
    last_count: int = 0


class SketchBoard:
    """arduino_code_force_node's behaviour without I/O: feed it the host's bytes and the time, send what it returns."""

    def __init__(self, piston: Piston, noise_counts: float = 1.0, seed: Optional[int] = 0) -> None:
        self.piston = piston
        self._adc = SensorBoard(BoardConfig(noise_counts=noise_counts, seed=seed))
        self._reader = FrameReader()
        self.stats = BoardStats()
        self._connected = False
        self._configured = False
        self._last_sync_s = 0.0
        self._last_sync_answer_s = 0.0
        self._param_asked_s: Optional[float] = None
        self._period_s = HANDOUT_PERIOD_S
        self._last_publish_s = 0.0

    @property
    def connected(self) -> bool:
        return self._connected

    def receive(self, data: bytes, now_s: float) -> bytes:
        """The host's bytes arrive; returns the board's replies."""
        out = b""
        for message in self._reader.feed(data):
            out += self._on_frame(message, now_s)
        return out

    def _on_frame(self, message: Frame, now_s: float) -> bytes:
        if message.topic_id == ID_PUBLISHER:  # the host asks for the topics: negotiateTopics, requestSyncTime
            self.stats.announced += 1
            self._configured = False
            self._param_asked_s = None
            info = TopicInfo(PUB_FORCE_ID, "pub_force", "std_msgs/Int16", INT16_MD5, 150)
            self._last_sync_s = self._last_sync_answer_s = now_s
            self.stats.time_requests += 1
            return frame(ID_PUBLISHER, encode_topic_info(info)) + frame(ID_TIME, b"")
        if message.topic_id == ID_TIME:
            self.stats.time_answers += 1
            try:
                self.stats.last_time = decode_time(message.payload)
            except ValueError:
                pass
            self._last_sync_answer_s = now_s
            self._connected = True
            return b""
        if message.topic_id == ID_PARAMETER_REQUEST and self._param_asked_s is not None:
            self._param_asked_s = None
            self.stats.param_answers += 1
            return self._configure(now_s, self._period_from(message.payload))
        if message.topic_id == ID_TX_STOP:
            self._connected = self._configured = False
        return b""

    def _period_from(self, payload: bytes) -> Tuple[Optional[int], bool]:
        try:
            answer = decode_param_answer(payload)
        except ValueError:
            return None, False
        if len(answer.ints) != 1:
            return None, False
        value = answer.ints[0]
        return value, MIN_PERIOD_MS <= value <= MAX_PERIOD_MS

    def _configure(self, now_s: float, found: Tuple[Optional[int], bool]) -> bytes:
        value, good = found
        self._configured = True
        self.stats.period_from_param = good
        period_ms = value if good and value is not None else int(HANDOUT_PERIOD_S * 1000)
        self.stats.period_ms = period_ms
        self._period_s = period_ms / 1000.0
        self._last_publish_s = now_s - self._period_s  # first sample right away
        if value is None:
            return _log(_WARN, "no ~publish_period_ms: 300 ms (handout); 10 recommended")
        if not good:
            return _log(_WARN, "~publish_period_ms not in 5..10000: 300 ms; 10 recommended")
        return _log(_INFO, "period from ~publish_period_ms")

    def tick(self, now_s: float) -> bytes:
        """The sketch's loop at ``now_s``: sync, the parameter, and a count when one is due."""
        if not self._connected:
            return b""
        if now_s - self._last_sync_answer_s > SYNC_LOST_S:
            self._connected = self._configured = False
            return b""
        out = b""
        if now_s - self._last_sync_s > SYNC_PERIOD_S:
            self._last_sync_s = now_s
            self.stats.time_requests += 1
            out += frame(ID_TIME, b"")
        if not self._configured:
            if self._param_asked_s is None:
                self._param_asked_s = now_s
                return out + frame(ID_PARAMETER_REQUEST, encode_param_request(_PERIOD_PARAM))
            if now_s - self._param_asked_s < PARAM_TIMEOUT_S:
                return out  # getParam blocks the sketch until the answer or its timeout
            self._param_asked_s = None
            out += self._configure(now_s, (None, False))
        if now_s - self._last_publish_s < self._period_s:
            return out
        self._last_publish_s += self._period_s
        if now_s - self._last_publish_s >= self._period_s:
            self._last_publish_s = now_s  # fell a whole period behind: no burst
        count = self._adc.sample(self.piston.count_at(now_s), now_s)
        stats = self.stats
        stats.samples_sent += 1
        stats.last_count = count
        stats.first_sample_s = now_s if stats.first_sample_s is None else stats.first_sample_s
        stats.last_sample_s = now_s
        return out + frame(PUB_FORCE_ID, encode_int16(count))


def _log(level: int, text: str) -> bytes:
    return frame(ID_LOG, encode_log(level, text))


class PtyBoard:
    """A :class:`SketchBoard` on the master side of a pty; a host opens :attr:`port` as the Arduino's serial port.

    ``run`` loops until ``stop`` (or ``until()`` is true); ``on_loop`` is called every loop with the time.
    """

    def __init__(self, board: SketchBoard, loop_period_s: float = 0.001,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.board = board
        self._fd, slave = os.openpty()
        tty.setraw(slave)
        os.set_blocking(self._fd, False)  # nobody reading: bytes are lost, as on a serial line
        self.port = os.ttyname(slave)
        self._slave = slave  # kept open: a pty whose slave nobody holds reads EIO between two hosts
        self._loop_period_s = loop_period_s
        self._clock = clock
        self._stop = threading.Event()
        self.on_loop: List[Callable[[float], None]] = []

    def stop(self) -> None:
        self._stop.set()

    def run(self) -> None:
        try:
            while not self._stop.is_set():
                ready, _w, _x = select.select([self._fd], [], [], self._loop_period_s)
                now = self._clock()
                data = self._read() if ready else b""
                out = self.board.receive(data, now) if data else b""
                out += self.board.tick(now)
                if out:
                    self._write(out)
                for call in self.on_loop:
                    call(now)
        finally:
            os.close(self._fd)
            os.close(self._slave)

    def _read(self) -> bytes:
        try:
            return os.read(self._fd, 4096)
        except (BlockingIOError, OSError):
            return b""

    def _write(self, data: bytes) -> None:
        try:
            os.write(self._fd, data)
        except (BlockingIOError, OSError):
            pass  # the host's side is full or closed: the bytes are lost, as on a serial line
