"""A program that started a private roscore and is killed with SIGTERM leaves nothing behind.

roscore runs in a session of its own (so stopping it reaches rosmaster and rosout), so
without hri_teleop.ros.master's SIGTERM hook it outlives its parent: a `kill`, or a job
runner's timeout, would leave masters running.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import _ros_env

pytestmark = pytest.mark.ros

SCRIPT = """
import sys, time
from hri_teleop.ros.master import PrivateMaster
master = PrivateMaster()
master.start()
print(" ".join(str(p.popen.pid) for p in master.started), flush=True)
time.sleep(120)
"""


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().split(")")[-1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def test_sigterm_stops_the_private_master_before_the_program_dies(tmp_path):
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT], env=dict(_ros_env(), ROS_HOME=str(tmp_path)),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        line = proc.stdout.readline()
        pids = [int(p) for p in line.split()]
        assert pids and all(_alive(p) for p in pids), (line, proc.stderr.read() if proc.poll() is not None else "")
        deadline = time.monotonic() + 10  # roscore starts rosmaster and rosout (in sessions of their own)
        children: list = []
        while time.monotonic() < deadline and len(children) < 2:
            children = [int(c) for p in pids
                        for c in subprocess.run(["pgrep", "-P", str(p)], capture_output=True, text=True).stdout.split()]
            time.sleep(0.1)
        assert len(children) >= 2, children
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == -signal.SIGTERM  # it still dies of SIGTERM
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and any(_alive(p) for p in pids + children):
            time.sleep(0.1)
        assert not [p for p in pids + children if _alive(p)], "roscore, rosmaster or rosout outlived its parent"
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
