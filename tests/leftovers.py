"""What a test run left running: processes of this checkout, started during the run, whose parent is gone.

Every test stops what it started. A process that outlives its test (a node hung in its shutdown,
a child of a roslaunch killed before its nodes) is reparented to init; the run's end finds it
here, kills it, and fails the run naming it, instead of leaving it to burn a core for hours.
"""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path
from typing import List, Tuple

from hri_teleop.ros.proc_table import proc_table, start_ticks

#: Parents an orphan is handed to (pid 1 or a subreaper).
INITS = {"init", "systemd", "tini", "docker-init", "dumb-init"}


def _comm(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/comm").read_text().strip()
    except OSError:
        return ""


def _cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()
    except OSError:
        return ""


def leftovers(repo: Path, since_ticks: int) -> List[Tuple[int, str]]:
    """(pid, command line) of orphans of this checkout started at or after ``since_ticks``."""
    found = []
    for pid, (ppid, state) in proc_table().items():
        if state in (b"Z", b"X") or pid == os.getpid() or not (ppid == 1 or _comm(ppid) in INITS):
            continue
        ticks = start_ticks(pid)
        command = _cmdline(pid)
        if ticks is not None and ticks >= since_ticks and str(repo) in command:
            found.append((pid, command))
    return found


def reap(repo: Path, since_ticks: int, grace_s: float = 10.0) -> List[Tuple[int, str]]:
    """Wait ``grace_s`` for the run's orphans to end, then SIGKILL those left; returns them."""
    deadline = time.monotonic() + grace_s
    left = leftovers(repo, since_ticks)
    while left and time.monotonic() < deadline:
        time.sleep(0.2)
        left = leftovers(repo, since_ticks)
    for pid, _command in left:
        try:
            os.kill(pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
    return left
