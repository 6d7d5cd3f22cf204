"""A private roscore whose port was taken between free_port() and its bind starts on another port;
a port the caller chose is never changed, and a failed start leaves no process behind."""

from __future__ import annotations

import socket

import pytest
from conftest import _ros_env

from hri_teleop.ros import master as master_module
from hri_teleop.ros.master import MasterError, PrivateMaster

pytestmark = pytest.mark.ros


@pytest.fixture
def taken_port():
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.bind(("127.0.0.1", 0))
    # bound, not listening: rosmaster cannot bind it, and contacting it is refused at once
    yield sock.getsockname()[1]
    sock.close()


def test_a_port_of_its_own_choice_that_was_taken_is_replaced(taken_port, tmp_path, monkeypatch):
    ports = iter([taken_port])
    real = master_module.free_port
    monkeypatch.setattr(master_module, "free_port", lambda: next(ports, None) or real())
    ros = PrivateMaster(base_env=_ros_env(), work_dir=tmp_path / "ros")
    assert ros.port == taken_port
    with ros:
        assert ros.port != taken_port and ros.env["ROS_MASTER_URI"] == ros.uri
        assert "/rosout" in ros.node_names()
    assert not [p for p in ros.started if p.anything_left]


def test_a_port_the_caller_chose_is_not_changed_and_nothing_is_left(taken_port, tmp_path):
    ros = PrivateMaster(port=taken_port, base_env=_ros_env(), work_dir=tmp_path / "ros")
    with pytest.raises(MasterError, match=f"master on port {taken_port} exited"):
        ros.start()
    assert ros.port == taken_port
    assert not [p for p in ros.started if p.anything_left]
    assert not [p for p in master_module.LIVE_PROCESSES if p in ros.started]


def test_a_port_where_another_master_answers_is_never_joined(foreign_roscore, tmp_path):
    """rosmaster, unlike roscore, does not refuse a port another master serves by itself: the start does."""
    port = int(foreign_roscore.uri.rstrip("/").rsplit(":", 1)[1])
    ros = PrivateMaster(port=port, base_env=_ros_env(), work_dir=tmp_path / "ros")
    with pytest.raises(MasterError, match=f"master on port {port} exited: taken"):
        ros.start()
    assert not [p for p in ros.started if p.anything_left]
    assert foreign_roscore.core.running


def test_a_port_of_its_own_choice_where_another_master_answers_is_replaced(foreign_roscore, tmp_path, monkeypatch):
    port = int(foreign_roscore.uri.rstrip("/").rsplit(":", 1)[1])
    ports = iter([port])
    real = master_module.free_port
    monkeypatch.setattr(master_module, "free_port", lambda: next(ports, None) or real())
    ros = PrivateMaster(base_env=_ros_env(), work_dir=tmp_path / "ros")
    with ros:
        assert ros.port != port and ros.master_pid() == ros.core.popen.pid
    assert foreign_roscore.core.running
