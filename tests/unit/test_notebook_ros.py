"""hri_teleop.course.notebook_ros without a master: fast, one-line answers (the live paths: tests/integration)."""

from __future__ import annotations

import pytest

from hri_teleop.course import notebook_ros
from hri_teleop.course.notebook_ros import NotebookRosError, RosSession, ensure_ros
from hri_teleop.ros.master import free_port
from hri_teleop.ros.master_api import MasterApiError, master_call, master_reachable


def test_a_closed_port_is_not_a_master_and_says_so_at_once():
    """At once: the port refuses the connection; no answer is waited for (the timeout is for a master that hangs)."""
    uri = f"http://127.0.0.1:{free_port()}/"
    assert not master_reachable(uri)
    with pytest.raises(MasterApiError, match=f"no ROS master at {uri} \\(ConnectionRefusedError\\).*ensure_ros"):
        master_call("getSystemState", uri=uri)


def test_a_false_session_describes_its_problem_in_one_line():
    session = RosSession(False, problem="rospy is not installed: x")
    assert not session and session.describe() == "ROS: rospy is not installed: x"


def test_without_a_master_and_not_allowed_to_start_one_it_returns_a_false_session(monkeypatch, capsys):
    pytest.importorskip("rospy")
    monkeypatch.setenv("ROS_MASTER_URI", f"http://127.0.0.1:{free_port()}/")
    monkeypatch.setattr(notebook_ros, "_SESSION", None)
    session = ensure_ros(start_master=False)
    assert not session and "start roscore" in session.problem
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("ROS: no ROS master at")
    with pytest.raises(NotebookRosError):
        ensure_ros(start_master=False, required=True)


def test_in_lab_mode_without_the_labs_master_no_private_master_starts_and_one_line_says_why(monkeypatch):
    pytest.importorskip("rospy")
    monkeypatch.setenv("HRI_MODE", "lab")
    monkeypatch.setenv("ROS_MASTER_URI", f"http://127.0.0.1:{free_port()}/")
    monkeypatch.setattr(notebook_ros, "_SESSION", None)
    session = ensure_ros(quiet=True)   # start_master=True: at home it would start one
    assert not session and not session.started_master
    assert session.problem.startswith("lab mode: no ROS master at") and "HRI_MODE=home" in session.problem


def test_an_unknown_mode_is_a_false_session_naming_the_modes(monkeypatch):
    monkeypatch.setenv("HRI_MODE", "school")
    monkeypatch.setattr(notebook_ros, "_SESSION", None)
    session = ensure_ros(quiet=True)
    assert not session and "set it to home, lab or grading" in session.problem
