"""A rosserial board on a pseudo-terminal, speaking as the handout's sketch does (for make doctor's tests).

The package's stand-in (hri_teleop.hardware.sim.rosserial_board, the lab twin's board) in a thread:
silent until a host asks for its topics; then it announces /pub_force (std_msgs/Int16) and asks for
the time; once the time is answered it asks for ~publish_period_ms and, answered or after the
sketch's 500 ms, publishes a constant count every period (the handout's 300 ms without a value).
"""

from __future__ import annotations

import threading

from hri_teleop.hardware.sim.rosserial_board import Piston, PtyBoard, SketchBoard


class FakeRosserialBoard:
    """The board's side of rosserial on a pty; ``port`` is the path a host opens."""

    def __init__(self, count: int = 12) -> None:
        self.board = SketchBoard(Piston(rest_count=count), noise_counts=0.0)
        self._pty = PtyBoard(self.board)
        self.port = self._pty.port
        self._thread = threading.Thread(target=self._pty.run, daemon=True)

    @property
    def stats(self):
        return self.board.stats

    def __enter__(self) -> "FakeRosserialBoard":
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._pty.stop()
        self._thread.join(timeout=5)
