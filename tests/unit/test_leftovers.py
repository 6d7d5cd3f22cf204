"""The run's end finds a process of this checkout that outlived its parent, kills it and names it."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
import uuid

from leftovers import leftovers, reap

from hri_teleop.ros.proc_table import start_ticks


def _orphan(tmp_path, marker: str) -> int:
    """A python sleeping 60 s, whose shell parent has exited: reparented to init. The system's
    python, not the checkout's .venv (its path would name the checkout)."""
    pidfile = tmp_path / "pid"
    python = shutil.which("python3", path="/usr/bin:/bin") or sys.executable
    subprocess.run(["sh", "-c", f'{python} -c "import time; time.sleep(60)" {marker} & echo $! > {pidfile}'],
                   check=True)
    return int(pidfile.read_text())


def test_an_orphan_of_the_checkout_started_during_the_run_is_killed_and_named(tmp_path):
    """Reaped under a path of its own inside the checkout: the other worker's processes are of the
    checkout too, and one whose roslaunch is ending is an orphan for a moment (a run saw one here)."""
    from conftest import REPO

    since = start_ticks(os.getpid()) or 0
    own = REPO / f"marker-{uuid.uuid4().hex}"
    pid = _orphan(tmp_path, str(own))
    deadline = time.monotonic() + 10
    while pid not in [p for p, _ in leftovers(REPO, since)] and time.monotonic() < deadline:
        time.sleep(0.02)  # until the shell has exited: then an orphan of the checkout
    left = reap(own, since, grace_s=0.2)
    assert [p for p, _c in left] == [pid] and str(own) in left[0][1]
    gone_by = time.monotonic() + 10
    while start_ticks(pid) is not None and time.monotonic() < gone_by:
        time.sleep(0.02)
    assert start_ticks(pid) is None


def test_an_orphan_of_another_folder_is_left_alone(tmp_path):
    from conftest import REPO

    since = start_ticks(os.getpid()) or 0
    pid = _orphan(tmp_path, str(tmp_path / "elsewhere"))
    try:
        time.sleep(0.3)
        assert pid not in [p for p, _ in leftovers(REPO, since)]
    finally:
        os.kill(pid, 9)
