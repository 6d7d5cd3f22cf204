"""``make lab-twin``: the lab twin in the foreground for a lab engineer's rehearsal.

Prints one block (the nodes, what to export, the board's pty, how to stop), then takes commands on
standard input -- ``press 700 2``, ``activate``, ``deactivate``, ``report``, ``help`` -- until Ctrl-C
(without standard input it runs until interrupted), and says in one line each node that comes up
from the twin's packages, is replaced or stops. Ctrl-C stops all it started.

    python -m hri_teleop.apps.lab_twin [--folder DIR] [--publish-period-ms N] [--deactivated] [--bare]
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator, List, Optional, Set, TextIO

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.paths import REPO
from hri_teleop.hardware.sim.rosserial_board import FULL_PRESS_COUNT
from hri_teleop.ros.lab_twin.report import TwinReport
from hri_teleop.ros.lab_twin.twin import DEFAULT_PUBLISH_PERIOD_MS, LabTwin
from hri_teleop.ros.master import run_reporting

__all__ = ["COMMANDS", "handle", "news", "main"]

#: How often the twin's nodes are checked for being replaced or stopped from outside (s).
WATCH_PERIOD_S = 1.0
COMMANDS = ("press COUNT [HOLD_S]  press the piston (a full press: press 700 2)",
            "activate | deactivate  release or engage the robot's user stop (for any franka_control)",
            "report                 what reached the twin so far",
            "help                   this list")


def handle(twin: LabTwin, line: str, say: Callable[[str], None] = print) -> None:
    """One command from standard input; a wrong one is one line saying what to type."""
    words = line.split()
    if not words:
        return
    command, args = words[0].lower(), words[1:]
    try:
        if command == "press":
            count = int(args[0]) if args else FULL_PRESS_COUNT
            hold_s = float(args[1]) if len(args) > 1 else 2.0
            twin.press(count, hold_s)
            say(f"twin: piston pressed to {count} for {hold_s:g} s")
        elif command in ("activate", "deactivate"):
            twin.set_activated(command == "activate")
            say("twin: the robot is activated" if command == "activate"
                else "twin: user stop engaged: twists are counted, the arm stays")
        elif command == "report":
            for text in twin.report().lines():
                say(f"twin: {text}")
        elif command == "help":
            for text in COMMANDS:
                say(f"twin: {text}")
        else:
            say(f"twin: unknown command {words[0]!r}; type help")
    except HriTeleopError as exc:  # before ValueError: a press the board refuses is one (BoardStandInError)
        say(f"twin: {exc}")
    except ValueError:
        say(f"twin: {line.strip()!r}: give numbers, e.g. press 700 2")


def _block(twin: LabTwin) -> List[str]:
    rule = "-" * 78
    return ([rule, "lab twin: a master that looks like the lab PC's (docs/lab-day.md)"] + twin.describe()
            + ["stop     Ctrl-C stops everything it started",
               "type     press 700 2 | activate | deactivate | report | help", rule])


def news(report: TwinReport) -> List[str]:
    """What a person watching the twin should hear about its nodes now (each line once: the caller
    keeps what it said): a twin node replaced or stopped, a node of the installed packages running."""
    return ([f"{node} replaced by another node of that name (the rest keeps running; Ctrl-C stops it)"
             for node in report.replaced]
            + [f"{node} stopped (the rest keeps running; Ctrl-C stops it)" for node in report.stopped]
            + [f"{node} runs from the twin's installed packages (pid {report.pids.get(node, '?')})"
               for node in report.launched])


def _run(args: argparse.Namespace, stdin: TextIO) -> int:
    with LabTwin(args.folder, activated=not args.deactivated, publish_period_ms=args.publish_period_ms,
                 nodes_running=not args.bare) as twin:
        print("\n".join(_block(twin)), flush=True)

        def read_commands() -> None:
            for line in stdin:
                handle(twin, line, lambda text: print(text, flush=True))
            # End of standard input (CI, a closed pipe): keep running until interrupted.

        threading.Thread(target=read_commands, name="commands", daemon=True).start()
        said: Set[str] = set()
        with _stop_requests() as stopped:
            while not stopped:
                for news_line in news(twin.report()):
                    if news_line not in said:
                        said.add(news_line)
                        print(f"twin: {news_line}", flush=True)
                time.sleep(WATCH_PERIOD_S)  # a signal's handler runs in it; the loop then ends
    print("lab-twin: interrupted; everything it started has been stopped", file=sys.stderr, flush=True)
    return 130


@contextmanager
def _stop_requests() -> Iterator[List[int]]:
    """Ctrl-C and SIGTERM while the twin runs: noted, not raised, so the twin stops from one known place
    (an exception raised in the middle of a poll or a file write could leave a lock held)."""
    signals: List[int] = []
    previous = {sig: signal.signal(sig, lambda signum, _frame: signals.append(signum))
                for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield signals
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=Path, default=REPO / "out" / "lab-twin",
                        help="where the counts and logs go (default: out/lab-twin)")
    parser.add_argument("--publish-period-ms", type=int, default=DEFAULT_PUBLISH_PERIOD_MS,
                        help="serial_node's ~publish_period_ms (default %(default)s, as teleoperation.launch)")
    parser.add_argument("--deactivated", action="store_true", help="start with the robot's user stop engaged")
    parser.add_argument("--bare", action="store_true",
                        help="only the master and the board: the nodes come up when a launch starts them")
    args = parser.parse_args(argv)
    signal.signal(signal.SIGTERM, signal.default_int_handler)  # a kill stops all it started, as Ctrl-C does
    return run_reporting(lambda: _run(args, sys.stdin), "lab-twin")


if __name__ == "__main__":
    sys.exit(main())
