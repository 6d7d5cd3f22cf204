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
print(" ".join(str(p) for p in master.core_pids), flush=True)
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
        assert len(pids) == 2, pids  # rosmaster and rosout, in sessions of their own
        children: list = []
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == -signal.SIGTERM  # it still dies of SIGTERM
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and any(_alive(p) for p in pids + children):
            time.sleep(0.1)
        assert not [p for p in pids + children if _alive(p)], "rosmaster or rosout outlived its parent"
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _children(pids):
    return [int(c) for p in pids
            for c in subprocess.run(["pgrep", "-P", str(p)], capture_output=True, text=True).stdout.split()]


def _gone(pids, within_s=10.0):
    deadline = time.monotonic() + within_s
    while time.monotonic() < deadline and any(_alive(p) for p in pids):
        time.sleep(0.05)
    return [p for p in pids if _alive(p)]


def test_a_killed_master_takes_rosmaster_and_rosout_with_it(tmp_path):
    """The grader kills its master (quick stop): rosmaster and rosout run in sessions of their own,
    so killing one process group alone would leave the other running."""
    from hri_teleop.ros.master import PrivateMaster

    master = PrivateMaster(base_env=dict(_ros_env(), ROS_HOME=str(tmp_path))).start()
    family = master.core_pids
    assert len(family) == 2, family  # rosmaster and rosout
    master.stop(quick=True)
    assert not _gone(family), "rosmaster or rosout outlived the quick stop"


def test_a_killed_roscore_takes_rosmaster_and_rosout_with_it(tmp_path):
    """The same for a full roscore (the lab twin's), whose rosmaster and rosout are its children."""
    from hri_teleop.ros.master import PrivateMaster

    master = PrivateMaster(base_env=dict(_ros_env(), ROS_HOME=str(tmp_path)), roscore=True).start()
    core = master.core.popen.pid
    deadline = time.monotonic() + 10
    children: list = []
    while time.monotonic() < deadline and len(children) < 2:
        children = _children([core])
        time.sleep(0.1)
    assert len(children) >= 2, children
    master.stop(quick=True)
    assert not _gone([core, *children]), "rosmaster or rosout outlived the killed roscore"


NODE = """
import signal, sys, time
count = 0
def on_int(*_):
    global count
    count += 1
    with open(sys.argv[1], "a") as fh:
        fh.write("SIGINT\\n")
signal.signal(signal.SIGINT, on_int)
print("ready", flush=True)
while count == 0:
    time.sleep(0.01)
time.sleep(0.3)  # a node's clean shutdown (rospy.spin notices within 0.5 s)
"""

KERNEL = """
import sys
from hri_teleop.course.notebook_ros import ensure_ros
from hri_teleop.course.nodes import start_gated
ros = ensure_ros(quiet=True)
node = start_gated([sys.executable, "-c", sys.argv[1], sys.argv[2]], "counter", [])
while "ready" not in node.output():
    pass
import subprocess, time
family = ros._master.core_pids  # rosmaster and rosout, in sessions of their own
assert len(family) == 2, family
print(node.popen.pid, *family, flush=True)
"""


def test_a_closing_kernel_interrupts_its_nodes_once_and_kills_its_master(tmp_path):
    """What a notebook kernel does at exit: its nodes get one SIGINT (a second would cut a clean
    shutdown, a bag's, short), the kernel's node unregisters, then the private master is killed."""
    log = tmp_path / "sigints.txt"
    env = dict(_ros_env(), ROS_HOME=str(tmp_path), ROS_MASTER_URI="http://127.0.0.1:1/", HRI_MODE="home")
    proc = subprocess.run([sys.executable, "-c", KERNEL, NODE, str(log)], env=env, capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr[-2000:]
    pids = [int(p) for p in proc.stdout.split()]
    assert len(pids) == 3, proc.stdout
    assert log.read_text().splitlines() == ["SIGINT"]
    assert not _gone(pids), "the node, rosmaster or rosout outlived the kernel"
