"""The fsr_serial firmware on a simulated Uno (simavr), its piston pressed every few seconds.

A board to try the serial bridge or the calibration on without an Arduino.

    python -m hri_teleop.apps.simavr_board [--link /tmp/ttyFSR] [--max-count 700] [--period-s 4]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import List, Optional

from hri_teleop.hardware.sim.simavr_board import (
    SimavrBoardError,
    SimulatedUno,
    build_firmware,
    force_profile,
    press_forces,
    write_profile,
)


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description="Run the fsr_serial firmware on a simulated Uno, pressing its "
                                                 "piston every few seconds.")
    parser.add_argument("--link", type=Path, default=Path(tempfile.gettempdir()) / "ttyFSR",
                        help="where the board's serial port appears (default: /tmp/ttyFSR)")
    parser.add_argument("--max-count", type=int, default=700, help="count at the top of each press (default 700)")
    parser.add_argument("--period-s", type=float, default=4.0, help="one press and release, s (default 4)")
    args = parser.parse_args(argv)
    try:
        build_firmware()
        with tempfile.TemporaryDirectory(prefix="hri-uno-") as tmp:
            times, forces = press_forces(args.max_count, args.period_s)
            profile = write_profile(force_profile(times, forces), Path(tmp) / "profile.txt")
            board = SimulatedUno(args.link, profile, repeat_us=int(args.period_s * 1e6))
            board.start(lambda a: subprocess.Popen(a, stdin=subprocess.DEVNULL))
            print(f"simulated Uno on {args.link}: e.g. rosrun hri_lab serial_bridge.py _port:={args.link}, "
                  f"or python -m hri_teleop.apps.calibrate --port {args.link}; Ctrl-C ends it", flush=True)
            try:
                assert board.process is not None
                board.process.wait()
            except KeyboardInterrupt:
                pass
            finally:
                board.stop()
    except SimavrBoardError as exc:
        print(f"simavr_board: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
