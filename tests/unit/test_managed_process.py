"""Stopping a started process reaches what it started in sessions of their own (roslaunch's nodes)."""

from __future__ import annotations

import os
import sys
import textwrap
import time

from hri_teleop.ros.proc_table import ProcessIds, start_ticks
from hri_teleop.ros.processes import ManagedProcess

# A parent that, as roslaunch, starts a child in a session of its own; the child ignores SIGINT and
# SIGTERM (as a node whose shutdown hangs); the parent ends on SIGINT.
PARENT = textwrap.dedent("""
    import signal, subprocess, sys, time
    child = subprocess.Popen([sys.executable, "-c",
        "import signal, time; signal.signal(signal.SIGINT, signal.SIG_IGN); "
        "signal.signal(signal.SIGTERM, signal.SIG_IGN); print('ready', flush=True); time.sleep(600)"],
        start_new_session=True, stdout=subprocess.PIPE, text=True)
    child.stdout.readline()
    print(child.pid, flush=True)
    time.sleep(600)
""")


def _alive(pid: int) -> bool:
    ticks = start_ticks(pid)
    return ticks is not None


def test_stop_kills_a_hung_child_that_left_the_group(tmp_path):
    proc = ManagedProcess([sys.executable, "-c", PARENT], dict(os.environ), tmp_path / "parent.log")
    deadline = time.monotonic() + 60
    while not proc.output().strip() and time.monotonic() < deadline:
        time.sleep(0.02)
    child = int(proc.output().strip().splitlines()[-1])
    assert _alive(child)
    proc.stop(timeout_s=0.5)
    gone_by = time.monotonic() + 10
    while _alive(child) and time.monotonic() < gone_by:
        time.sleep(0.02)
    assert not _alive(child)


def test_known_processes_are_told_from_a_later_process_with_the_same_pid():
    known = ProcessIds([os.getpid()])
    assert known.alive() == [os.getpid()]
    known.started[os.getpid()] = (known.started[os.getpid()] or 0) + 1  # as if this pid had been reused
    assert known.alive() == []
