"""A rosserial board on a pseudo-terminal, speaking as the handout's sketch does (for make doctor's tests).

Silent until a host asks for its topics; then it announces /pub_force (std_msgs/Int16) and asks
for the time; once the time is answered it asks for ~publish_period_ms and, answered or after the
sketch's 500 ms, publishes a count every period. No Arduino library is needed (Debian has none).
"""

from __future__ import annotations

import os
import select
import struct
import threading
import time
import tty
from typing import List, Optional

from hri_teleop.core.rosserial_frames import ID_PARAMETER_REQUEST, ID_PUBLISHER, ID_TIME, FrameReader, frame

PUB_FORCE_ID = 125
INT16_MD5 = "8524586e34fbd7cb1c08c5f5f1ca0e57"
PARAM_TIMEOUT_S = 0.5


def _text(value: str) -> bytes:
    return struct.pack("<I", len(value)) + value.encode()


def topic_info(topic_id: int, name: str, kind: str, md5: str, buffer_size: int = 280) -> bytes:
    return struct.pack("<H", topic_id) + _text(name) + _text(kind) + _text(md5) + struct.pack("<i", buffer_size)


class FakeRosserialBoard:
    """The board's side of rosserial on a pty; ``port`` is the path a host opens."""

    def __init__(self, period_s: float = 0.3, count: int = 12) -> None:
        self._master, slave = os.openpty()
        tty.setraw(slave)
        self.port = os.ttyname(slave)
        self._slave = slave
        self.period_s = period_s
        self.count = count
        self.published = 0
        self.time_answers: List[bytes] = []
        self.param_answered = False
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def __enter__(self) -> "FakeRosserialBoard":
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join(timeout=5)
        os.close(self._master)
        os.close(self._slave)

    def _read(self) -> bytes:
        ready, _w, _x = select.select([self._master], [], [], 0.01)
        return os.read(self._master, 4096) if ready else b""

    def _run(self) -> None:
        reader = FrameReader()
        announced = synced = False
        param_asked_at: Optional[float] = None
        next_publish: Optional[float] = None
        while not self._stop.is_set():
            for f in reader.feed(self._read()):
                if f.topic_id == ID_PUBLISHER and not f.payload:
                    os.write(self._master, frame(ID_PUBLISHER, topic_info(PUB_FORCE_ID, "pub_force", "std_msgs/Int16",
                                                                          INT16_MD5)))
                    os.write(self._master, frame(ID_TIME, b""))
                    announced = True
                elif f.topic_id == ID_TIME and announced:
                    self.time_answers.append(f.payload)
                    if not synced:
                        synced = True
                        os.write(self._master, frame(ID_PARAMETER_REQUEST, _text("~publish_period_ms")))
                        param_asked_at = time.monotonic()
                elif f.topic_id == ID_PARAMETER_REQUEST:
                    self.param_answered = True
                    next_publish = time.monotonic()
            now = time.monotonic()
            if next_publish is None and param_asked_at is not None and now - param_asked_at >= PARAM_TIMEOUT_S:
                next_publish = now
            if next_publish is not None and now >= next_publish:
                os.write(self._master, frame(PUB_FORCE_ID, struct.pack("<h", self.count)))
                self.published += 1
                next_publish += self.period_s
