"""The grader's wait for quiet processes after a tick (lockstep.Quiescence): it returns only once
every process below the roots waits for something, and gives up, once, on a process that never does."""

from __future__ import annotations

import subprocess
import sys
import time

import pytest

from hri_teleop.grading.run import lockstep
from hri_teleop.grading.run.lockstep import Quiescence, busy_threads

WORK_THEN_SLEEP = """
import sys, time
end = time.monotonic() + float(sys.argv[2])
while time.monotonic() < end:
    pass
open(sys.argv[1], "w").write("done")
time.sleep(60)
"""

SPIN = "import sys; open(sys.argv[1], 'w').close()\nwhile True: pass"


@pytest.fixture
def processes():
    started = []

    def start(argv):
        proc = subprocess.Popen(argv)
        started.append(proc)
        return proc

    yield start
    for proc in started:
        proc.kill()
        proc.wait()


def _wait_file(path, timeout_s=20.0):
    deadline = time.monotonic() + timeout_s
    while not path.exists() and time.monotonic() < deadline:
        time.sleep(0.01)


def test_it_returns_only_after_a_grandchild_has_done_its_work(tmp_path, processes):
    marker = tmp_path / "done"
    # The worker is the shell's child: roslaunch starts the student's nodes the same way.
    shell = processes(["sh", "-c", f'"{sys.executable}" -c \'{WORK_THEN_SLEEP}\' {marker} 0.4; sleep 60'])
    quiet = Quiescence([shell.pid])
    deadline = time.monotonic() + 10
    while len(quiet.pids) < 2 and time.monotonic() < deadline:  # the worker started
        quiet.refresh()
    assert len(quiet.pids) >= 2
    assert quiet.wait()
    assert marker.read_text() == "done"
    assert busy_threads(quiet.pids) == 0


@pytest.fixture
def waits(monkeypatch):
    """Every wait Quiescence starts (its timeout) and what it came to, the real wait doing the waiting."""
    calls = []
    real = lockstep.wait_for

    def recorded(condition, timeout_s, poll_s=0.02):
        calls.append([timeout_s, None])
        calls[-1][1] = real(condition, timeout_s, poll_s)
        return calls[-1][1]

    monkeypatch.setattr(lockstep, "wait_for", recorded)
    return calls


def _spinner(processes, tmp_path):
    """A process in a busy loop, once it is in it (its start may wait on the disk)."""
    marker = tmp_path / "spinning"
    spinner = processes([sys.executable, "-c", SPIN, str(marker)])
    _wait_file(marker)
    assert marker.exists(), "the spinner did not start"
    return spinner


def test_it_does_not_wait_for_processes_outside_the_roots(tmp_path, processes, waits):
    spinner = _spinner(processes, tmp_path)
    sleeper = processes(["sleep", "60"])
    assert busy_threads([spinner.pid]) >= 1
    quiet = Quiescence([sleeper.pid])
    assert quiet.wait()
    # quiet within its wait: the spinner, outside the roots, never held it to the timeout
    assert waits == [[Quiescence.TIMEOUT_S, True]] and (quiet.enabled, quiet.timeouts) == (True, 0)


def test_it_gives_up_once_on_a_busy_loop_and_then_stops_waiting(tmp_path, processes, monkeypatch, waits):
    monkeypatch.setattr(Quiescence, "TIMEOUT_S", 0.3)
    spinner = _spinner(processes, tmp_path)
    quiet = Quiescence([spinner.pid])
    assert not quiet.wait()
    assert waits == [[0.3, False]]  # the whole timeout waited for, and never quiet
    assert (quiet.enabled, quiet.timeouts) == (False, 1)
    assert quiet.wait()
    assert waits == [[0.3, False]]  # no second wait


def test_an_ended_process_counts_as_quiet(tmp_path, processes):
    marker = tmp_path / "done"
    worker = processes([sys.executable, "-c", "import sys; open(sys.argv[1], 'w').write('x')", str(marker)])
    worker.wait()
    assert Quiescence([worker.pid]).wait()
