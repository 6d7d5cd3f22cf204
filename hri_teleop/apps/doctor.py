"""``make doctor``: the preflight of a lab station, one line per part (ok, or the fix), in seconds.

The checks are :mod:`hri_teleop.ros.doctor`'s (the notebooks' Doctor widget runs the same); this is the
terminal's prompt, skip key and summary line.

    python -m hri_teleop.apps.doctor [--walk] [--port /dev/ttyACM0] [--no-sim]
"""

from __future__ import annotations

import argparse
import select
import sys
import time
from typing import List, Optional

from hri_teleop.core.doctor import FAIL, exit_code
from hri_teleop.ros.doctor import run_checks


def _enter_pressed() -> bool:
    """A line on standard input (Enter in a terminal, the widget's Skip, or its end) skips a step."""
    ready, _w, _x = select.select([sys.stdin], [], [], 0)
    if ready:
        sys.stdin.readline()
    return bool(ready)


def _ask(prompt: str) -> str:
    """The prompt on a line of its own (a widget reads it), the answer from standard input ("" at its end)."""
    print(prompt, flush=True)
    return sys.stdin.readline().strip()


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--walk", action="store_true",
                        help="walk through the pad (press each button, feel the rumble) and a full press of the "
                             "piston; answers and skips (Enter) come from standard input")
    parser.add_argument("--port", action="append", default=None,
                        help="the Arduino's serial port (default: every /dev/ttyACM* and /dev/ttyUSB*); repeatable")
    parser.add_argument("--no-sim", action="store_true",
                        help="at home with no master: do not start the simulated lab, only say that none runs")
    args = parser.parse_args(argv)
    started = time.monotonic()
    findings = run_checks(walk=args.walk, ask=_ask, say=lambda line: print(line, flush=True), ports=args.port,
                          simulate=not args.no_sim, skip=_enter_pressed)
    failed = [f for f in findings if f.status == FAIL]
    print(f"doctor: {len(findings) - len(failed)} of {len(findings)} ok or noted, {len(failed)} to fix "
          f"({time.monotonic() - started:.1f} s)")
    return exit_code(findings)


if __name__ == "__main__":
    sys.exit(main())
