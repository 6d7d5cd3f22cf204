"""The notebooks' starts on a real roscore: the simulation at home, nothing simulated or scripted
on a master the kernel did not start (the lab's) or next to real hardware, never a second node of a
running name."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from hri_teleop.course import lab, lab_nodes
from hri_teleop.course.errors import CourseError
from hri_teleop.course.master_mode import NotStarted, master_mode
from hri_teleop.ros.master import OWN_MASTER_ENV
from hri_teleop.ros.master_api import running_nodes
from hri_teleop.sim.world import LAB_ARM_CONFIG

REPO = Path(__file__).resolve().parents[2]
ANSWER_KEY = REPO / "solutions" / "hri_lab"

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


@pytest.fixture
def foreign_master(foreign_roscore, monkeypatch):
    """This process as a kernel on a master it did not start (as the lab PC's is)."""
    for key, value in foreign_roscore.env.items():
        if key.startswith("ROS_"):
            monkeypatch.setenv(key, value)
    for key in ("HRI_MODE", "NBGRADER_EXECUTION", OWN_MASTER_ENV):
        monkeypatch.delenv(key, raising=False)
    try:
        yield foreign_roscore.uri
    finally:
        lab.stop()


def _spin_node(master, name):
    proc = master.run([sys.executable, "-c", SPIN, name], name)
    assert lab_nodes.wait_until_up(proc, "/rosout", True, "/" + name, 30.0) is None
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
    refused = [lab_nodes.start_board(), lab_nodes.start_robot(), lab_nodes.start_pipeline()]
    assert all(isinstance(r, NotStarted) and not r and not r.running for r in refused)
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 3 and all(line.startswith("refused to start the") and "HRI_MODE=lab" in line
                                   for line in lines)
    assert [r.output().strip() for r in refused] == lines
    assert running_nodes(among=["/FSR_sensor", "/lab_sim"]) == []


def test_at_home_next_to_a_real_board_nothing_simulated_starts(kernel, capsys):
    _spin_node(kernel, "serial_node")
    assert not lab_nodes.start_board()
    assert "this master runs real hardware (/serial_node)" in capsys.readouterr().out
    assert running_nodes(among=["/FSR_sensor"]) == []


def test_the_kernels_own_master_is_home_and_another_is_the_lab(kernel, foreign_master):
    assert master_mode(kernel.uri).own and master_mode(kernel.uri).mode == "home"
    assert not master_mode(foreign_master).own and master_mode(foreign_master).mode == "lab"
    assert lab_nodes.mode() == "lab" and lab.default_pad() == "pygame"


@pytest.mark.parametrize("hri_mode", [None, "home", "grading"])
def test_on_a_master_the_kernel_did_not_start_nothing_simulated_or_scripted_starts(foreign_master, monkeypatch,
                                                                                   capsys, hri_mode):
    if hri_mode:
        monkeypatch.setenv("HRI_MODE", hri_mode)
    drive = ANSWER_KEY / "scripts" / "teleoperation.py"
    refused = {
        "board": lab_nodes.start_board(),
        "robot": lab_nodes.start_robot(),
        "pipeline": lab_nodes.start_pipeline(package=ANSWER_KEY),
        "FSR_sensor.py": lab.run_provided("FSR_sensor.py"),
        "lab_sim.py": lab.run_provided("lab_sim.py"),
        "scripted teleoperation": lab.run_student(drive, "teleoperation", pad="virtual", pad_script="/tmp/x.yaml"),
        "browser-pad teleoperation": lab.run_student(drive, "teleoperation", pad="virtual"),
        "sensor.launch": lab.launch_student("sensor.launch", package=ANSWER_KEY),
    }
    lines = capsys.readouterr().out.strip().splitlines()
    assert {k: type(v).__name__ for k, v in refused.items()} == {k: "NotStarted" for k in refused}
    refusals = [line for line in lines if line.startswith("refused to start")]
    assert len(refusals) == len(refused), lines
    assert all("not started by this process" in line for line in refusals)
    assert running_nodes(among=["/FSR_sensor", "/lab_sim", "/teleoperation", "/mapping_node"]) == []


def test_on_the_labs_master_a_node_with_the_real_pad_starts(foreign_master, capsys):
    node = lab.run_student(ANSWER_KEY / "scripts" / "mapping_node.py")
    assert not isinstance(node, NotStarted) and "refused" not in capsys.readouterr().out
    teleop = lab.run_student(ANSWER_KEY / "scripts" / "teleoperation.py", "teleoperation", **lab.pad_params("pygame"))
    assert not isinstance(teleop, NotStarted)


def test_the_hand_height_comes_from_the_arms_joint_states(kernel):
    robot = lab_nodes.start_robot(object="none")
    assert robot.running

    reader = kernel.run([sys.executable, "-c", "from hri_teleop.course import ensure_ros, lab; "
                         "ensure_ros(quiet=True); print('z_m', lab.hand_z_m())"], "hand_reader")
    assert reader.wait(60) == 0, reader.output()
    z_m = float(reader.output().split("z_m")[-1])
    assert z_m == pytest.approx(LAB_ARM_CONFIG.start_position_m[2], abs=0.002)


def test_a_killed_nodes_stale_registration_does_not_block_a_restart(kernel):
    stale = _spin_node(kernel, "FSR_sensor")
    stale.popen.kill()  # SIGKILL: no chance to unregister from the master
    stale.wait(10)
    board = lab_nodes.start_board(max_value=700, rate_hz=100)
    assert board is not None and board.running


def test_on_the_labs_master_the_browser_pad_drives_nothing(foreign_master, capsys):
    node = lab.run_student(ANSWER_KEY / "scripts" / "teleoperation.py", "teleoperation", **lab.pad_params("browser"))
    app = lab.start_application(pad="browser", package=ANSWER_KEY)
    shown = lab.browser_pad("browser")
    out = capsys.readouterr().out
    assert isinstance(node, NotStarted) and isinstance(app, NotStarted) and shown is None, out
    assert out.count("with the browser pad") == 2 and 'set PAD = "pygame"' in out, out
    assert "in the lab your node reads the lab's gamepad" in out
    assert running_nodes(among=["/teleoperation", "/lab_sim", "/mapping_node"]) == []


def test_at_home_ex14_with_the_browser_pad_squeezes_the_simulated_egg_from_the_students_nodes_and_rumbles(
        kernel, capsys):
    from hri_teleop.core.gamepad import PadState
    from hri_teleop.core.gamepad.layout import load_layout

    app = lab.start_application(pad="browser", package=ANSWER_KEY)
    assert app.running, app.output()
    assert lab_nodes.wait_for_subscriber("/teleoperation/virtual_joy", "/teleoperation", app, 60), app.output()
    axes, buttons = load_layout("dualshock4").raw_from_state(PadState({}, {"south": True}))
    # the page's pad as widgets.BrowserPad publishes it: cross held
    pad = kernel.run(["rostopic", "pub", "-r", "25", "/teleoperation/virtual_joy", "sensor_msgs/Joy",
                      f"{{axes: {axes}, buttons: {buttons}}}"], "browser_pad")
    rumble = kernel.run(["rostopic", "echo", "/teleoperation/rumble/data"], "rumble",
                        extra_env={"PYTHONUNBUFFERED": "1"})
    try:
        kernel.wait_for(lambda: any(line.strip() not in ("", "---", "0.0") for line in rumble.output().splitlines())
                        or not app.running, 60, "the egg squeezed by the student's nodes to rumble the pad")
        assert app.running, app.output()
        capsys.readouterr()
        assert lab.wait_for_quit(app, 600) is None  # it does not wait: the page's pad needs the kernel free
        assert "not waiting" in capsys.readouterr().out
    finally:
        pad.stop()
        rumble.stop()
    assert running_nodes(among=["/lab_sim", "/mapping_node", "/gripper_manager", "/teleoperation"]) == [
        "/gripper_manager", "/lab_sim", "/mapping_node", "/teleoperation"]
