"""The notebooks' starts on a real roscore: the simulation at home, nothing simulated in the lab
or next to real hardware, never a second node of a running name."""

from __future__ import annotations

import sys

import pytest

from hri_teleop.course import lab, lab_nodes
from hri_teleop.course.errors import CourseError
from hri_teleop.ros.master_api import running_nodes

pytestmark = pytest.mark.ros

SPIN = "import rospy, sys; rospy.init_node(sys.argv[1]); rospy.spin()"


@pytest.fixture
def kernel(ros_master, monkeypatch):
    """This process as a notebook kernel on the test's master (course's starts read the environment)."""
    for key, value in ros_master.env.items():
        monkeypatch.setenv(key, value)
    monkeypatch.delenv("HRI_MODE", raising=False)
    monkeypatch.delenv("NBGRADER_EXECUTION", raising=False)
    yield ros_master
    lab.stop()


def _spin_node(master, name):
    proc = master.run([sys.executable, "-c", SPIN, name], name)
    assert lab_nodes._wait_until_up(proc, "/rosout", True, "/" + name, 30.0) is None
    return proc


def test_at_home_the_board_starts_once_and_a_second_start_of_its_name_is_refused(kernel):
    board = lab_nodes.start_board(max_value=700, rate_hz=100)
    assert board is not None and board.running
    assert running_nodes(among=["/FSR_sensor"]) == ["/FSR_sensor"]
    with pytest.raises(CourseError, match=r"^/FSR_sensor already running on this master.*lab\.stop\(\)"):
        lab_nodes.start_board(max_value=700, rate_hz=100)
    assert board.running, "the refused start must leave the running board alone"


def test_in_lab_mode_no_simulated_robot_or_board_starts_and_one_line_says_so(kernel, monkeypatch, capsys):
    monkeypatch.setenv("HRI_MODE", "lab")
    assert lab_nodes.start_board() is None
    assert lab_nodes.start_robot() is None
    assert lab_nodes.start_pipeline() is None
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 3 and all(line.startswith("lab mode: no simulated") for line in lines)
    assert running_nodes(among=["/FSR_sensor", "/lab_sim"]) == []
    with pytest.raises(CourseError, match="^lab mode: this check reads the simulated robot"):
        lab_nodes.hand_z_m()


def test_at_home_next_to_a_real_board_nothing_simulated_starts(kernel, capsys):
    _spin_node(kernel, "serial_node")
    assert lab_nodes.start_board() is None
    assert "this master runs real hardware (/serial_node)" in capsys.readouterr().out
    assert running_nodes(among=["/FSR_sensor"]) == []


def test_a_killed_nodes_stale_registration_does_not_block_a_restart(kernel):
    stale = _spin_node(kernel, "FSR_sensor")
    stale.popen.kill()  # SIGKILL: no chance to unregister from the master
    stale.wait(10)
    board = lab_nodes.start_board(max_value=700, rate_hz=100)
    assert board is not None and board.running
