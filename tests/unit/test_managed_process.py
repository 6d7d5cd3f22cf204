"""Stopping a started process reaches what it started in sessions of their own (roslaunch's nodes)."""

from __future__ import annotations

import os
import signal
import sys
import textwrap
import threading
import time

from hri_teleop.ros.proc_table import ProcessIds, ignores_signal, start_ticks
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


# Started as a job in the background of a script (a CI runner, `make test &`): SIGINT ignored from
# the start, as rosmaster then runs (it installs no handler of its own). It ends on SIGTERM, saying so.
IGNORES_SIGINT = textwrap.dedent("""
    import signal, sys, time
    def on_term(*_):
        print("ended by SIGTERM", flush=True)
        sys.exit(0)
    signal.signal(signal.SIGTERM, on_term)
    print("ready", flush=True)
    time.sleep(600)
""")


#: Sets SIGINT as asked, then execs the script: the child's start is the same whatever this test
#: process inherited (a run started in the background of a script ignores SIGINT, and a shell cannot
#: undo that: L23 failed when its worker had not yet run a test that installs a handler).
_EXEC_WITH_SIGINT = ("import os, signal, sys; signal.signal(signal.SIGINT, "
                     "signal.SIG_IGN if sys.argv[1] == 'ignored' else signal.SIG_DFL); "
                     "os.execv(sys.executable, [sys.executable, '-c', sys.argv[2]])")


def _started(tmp_path, script: str, ignore_sigint: bool) -> ManagedProcess:
    argv = [sys.executable, "-c", _EXEC_WITH_SIGINT, "ignored" if ignore_sigint else "default", script]
    proc = ManagedProcess(argv, dict(os.environ), tmp_path / f"child-{ignore_sigint}.log")
    deadline = time.monotonic() + 60
    while "ready" not in proc.output() and time.monotonic() < deadline:
        time.sleep(0.02)
    return proc


def test_a_process_that_ignores_sigint_is_told_from_one_that_does_not(tmp_path):
    ignoring, plain = _started(tmp_path, IGNORES_SIGINT, True), _started(tmp_path, IGNORES_SIGINT, False)
    try:
        assert ignores_signal(ignoring.popen.pid, signal.SIGINT)
        assert not ignores_signal(ignoring.popen.pid, signal.SIGTERM)  # it handles SIGTERM
        assert not ignores_signal(plain.popen.pid, signal.SIGINT)
    finally:
        ignoring.kill()
        plain.kill()
    assert not ignores_signal(ignoring.popen.pid, signal.SIGINT)  # ended: nothing to ignore


def test_stop_asks_a_process_that_ignores_sigint_with_sigterm_at_once(tmp_path):
    """The old stop sent it SIGINT and waited the whole timeout (10 s a master, 40 masters of one run)."""
    proc = _started(tmp_path, IGNORES_SIGINT, True)
    stopper = threading.Thread(target=proc.stop, kwargs={"timeout_s": 3600.0}, daemon=True)
    stopper.start()
    stopper.join(120.0)  # a hang guard: the old code waits out the hour
    if stopper.is_alive():
        proc.kill()
    assert not stopper.is_alive(), "stop() sent SIGINT to a process that ignores it and waited for its timeout"
    assert "ended by SIGTERM" in proc.output()
    assert proc.popen.returncode == 0  # its own clean end, not the escalation's SIGKILL
