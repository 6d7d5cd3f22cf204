"""The lab twin's Arduino: the rosserial sketch's stand-in on a pty, with a piston a person or a test presses.

Not a ROS node (the Arduino is none): ``python -m hri_teleop.ros.lab_twin.board FOLDER`` runs
:class:`hri_teleop.hardware.sim.rosserial_board.SketchBoard` on a pseudo-terminal and writes what it
did to ``FOLDER/board.json`` (the pty's path first, for serial_node's ``~port``). A press is asked
for by replacing ``FOLDER/piston.json`` with ``{"seq": n, "count": 700, "hold_s": 2}``
(:func:`request_press`): each new ``seq`` is one press.
"""

from __future__ import annotations

import argparse
import signal
import sys
from pathlib import Path
from typing import Any, List, Optional

from hri_teleop.hardware.sim.rosserial_board import BoardStandInError, Piston, PtyBoard, SketchBoard
from hri_teleop.ros.lab_twin.counts import CountsFile, read_json, write_json_atomic

__all__ = ["CONTROL_FILE", "COUNTS_NODE", "request_press", "main"]

#: The file a press is asked for with, in the twin's folder.
CONTROL_FILE = "piston.json"
#: The board's counts file is <folder>/board.json.
COUNTS_NODE = "board"
#: How often the control file is read (s).
CONTROL_POLL_S = 0.02
#: How often the board's statistics are copied to its counts file (s).
STATS_PERIOD_S = 0.05


def request_press(folder: Path, count: int, hold_s: float) -> int:
    """Ask the board in ``folder`` for a press (checked here first); returns the press's sequence number."""
    Piston().press(count, hold_s, 0.0)  # the same checks the board makes: a bad press fails here, in one line
    path = Path(folder) / CONTROL_FILE
    seq = int(read_json(path).get("seq", 0)) + 1
    write_json_atomic(path, {"seq": seq, "count": int(count), "hold_s": float(hold_s)})
    return seq


class _Controls:
    """Reads the control file and copies the board's statistics to its counts file, from the board's loop."""

    def __init__(self, folder: Path, piston: Piston, board: SketchBoard, counts: CountsFile) -> None:
        self.path = Path(folder) / CONTROL_FILE
        self.piston = piston
        self.board = board
        self.counts = counts
        self.seq = int(read_json(self.path).get("seq", 0))  # presses asked for before the start do not count
        self._next_read = 0.0
        self._next_stats = 0.0

    def __call__(self, now: float) -> None:
        if now >= self._next_read:
            self._next_read = now + CONTROL_POLL_S
            self._read(now)
        if now >= self._next_stats:
            self._next_stats = now + STATS_PERIOD_S
            stats = self.board.stats
            for key, value in vars(stats).items():
                self.counts.set(key, value)
            self.counts.set("connected", self.board.connected)
            self.counts.set("piston_count", self.piston.count_at(now))

    def _read(self, now: float) -> None:
        control: Any = read_json(self.path)
        try:
            seq = int(control.get("seq", 0))
        except (TypeError, ValueError):
            return
        if seq <= self.seq:
            return
        self.seq = seq
        try:
            self.piston.press(control.get("count"), control.get("hold_s"), now)
        except BoardStandInError as exc:
            print(f"board: {exc}", file=sys.stderr, flush=True)
            return
        self.counts.add("presses")
        self.counts.set("last_press", {"count": control.get("count"), "hold_s": control.get("hold_s")})


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the twin's folder (board.json and piston.json)")
    args = parser.parse_args(argv)
    piston = Piston()
    board = SketchBoard(piston)
    port = PtyBoard(board)
    counts = CountsFile(Path(args.folder) / f"{COUNTS_NODE}.json", COUNTS_NODE)
    counts.set("port", port.port)
    counts.flush()
    port.on_loop.append(_Controls(args.folder, piston, board, counts))

    def stop(_signum: int, _frame: object) -> None:
        port.stop()

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    try:
        port.run()
    finally:
        counts.close(stopped=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
