"""A student's own teleoperation.launch on the lab twin, with the packages the lab PC has installed.

The twin writes franka_control (franka_control_cartesian_velocity.launch and its nodes) and
rosserial_python (serial_node.py) into its folder and puts them last on ROS_PACKAGE_PATH. On a bare
twin (only the master and the board: the lab PC before anybody launched anything) the answer key's
teleoperation.launch brings the lab up from those packages, and the twin counts what reaches its
nodes as it does for its own. On a running twin the notebook's start of the same launch is refused;
a launch by hand over the twin's nodes replaces them, and the report tells the two apart.
Nothing here times a duration: each step waits for the graph or the counts.
"""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import threading
from pathlib import Path
from typing import List

import pytest
from test_lab_twin import WAIT_S, assert_board_rate, standin_env, wait_until  # tests/integration

from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M
from hri_teleop.grading.run.workspace import prepare_workspace, ros_package_path
from hri_teleop.ros.lab_twin import NODES, LabTwin, TwinReport
from hri_teleop.ros.lab_twin.counts import counts_path, read_json
from hri_teleop.ros.launch_inspect import launched_nodes
from hri_teleop.ros.master import ManagedProcess

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
ANSWER_KEY = REPO / "solutions" / "hri_lab"
ANSWER_LAUNCH = ANSWER_KEY / "launch" / "teleoperation.launch"
#: The student's nodes of the answer key's launch (the rest are the lab's).
STUDENT_NODES = {"/teleoperation", "/mapping_node", "/gripper_manager"}
#: The person at the pad: cross held for 1 s (the hand closes by 4 cm: gripper goals), the stick forward
#: from 2 s; let go at the first rumble (the first press of the piston), pushed again at a rumble 5 s
#: later (the second press: by then the first one's rumble is long over). Waits give up after 10 min.
PAD_STEPS = [{"t": 1.0, "press": "south"}, {"t": 2.0, "release": "south"},
             {"t": 2.0, "axis": "left_y", "value": 1.0},
             {"t": 2.5, "axis": "left_y", "value": 0.0, "when": "rumble", "above": 0.5, "max_wait": 600},
             {"t": 7.5, "axis": "left_y", "value": 1.0, "when": "rumble", "above": 0.5, "max_wait": 600}]
#: What a notebook cell of Ex. 14 does in the lab: lab.launch_student of the student's package.
KERNEL = ("import sys\n"
          "from hri_teleop.course import lab\n"
          "from hri_teleop.course.errors import CourseError\n"
          "try:\n"
          "    started = lab.launch_student('teleoperation.launch', package=sys.argv[1])\n"
          "except CourseError as exc:\n"
          "    print('refused:', exc)\n"
          "else:\n"
          "    print('started:', type(started).__name__)\n"
          "    lab.stop()\n")


def wait_report(twin: LabTwin, condition, what: str) -> TwinReport:
    """The first report that meets ``condition``; on a timeout the failure shows the last one."""
    found: List[TwinReport] = []
    try:
        wait_until(lambda: bool(found.append(twin.report()) or condition(found[-1])), what)
    except AssertionError as exc:
        last = found[-1] if found else None
        raise AssertionError(f"{exc}; the twin's last report: {last.lines() if last else None}, "
                             f"its nodes' counts: {last.nodes if last else None}") from None
    return found[-1]


def logged(folder: Path, text: str) -> bool:
    """Whether any ROS log under ``folder`` (a node's own, roslaunch's, rosout's) has ``text``."""
    return any(text in path.read_text(errors="replace") for path in folder.rglob("*.log") if path.is_file())


def start_answer_key_launch(twin: LabTwin, tmp_path: Path, steps):
    """The answer key's teleoperation.launch as a student launches it on the lab PC: their package as
    hri_lab in a workspace without the grader's stand-ins, the person at the pad stood in."""
    ws = prepare_workspace(ANSWER_KEY, tmp_path / "session", standins=False).ws
    env = dict(standin_env(tmp_path, steps), ROS_PACKAGE_PATH=ros_package_path(ws, twin.env))
    assert not (ws / "franka_control").exists() and not (ws / "rosserial_python").exists()
    return twin.run(["roslaunch", "--wait", str(ws / "hri_lab" / "launch" / "teleoperation.launch")],
                    "teleoperation_launch", extra_env=env)


def test_on_a_bare_twin_a_students_teleoperation_launch_brings_the_lab_up_and_the_twin_counts_it(tmp_path, ros_env):
    with LabTwin(tmp_path / "twin", nodes_running=False, base_env=ros_env) as twin:
        bare = twin.report()
        assert twin.master.node_names() == {"/rosout"} and twin.processes == {}
        assert (bare.missing, bare.launched, bare.replaced, bare.stopped) == (list(NODES), [], [], [])
        twin.set_activated(False)  # the user stop engaged before any franka_control runs

        launch = start_answer_key_launch(twin, tmp_path, PAD_STEPS)
        up = wait_report(twin, lambda r: r.launched == list(NODES) or not launch.running, "the launch's lab nodes")
        assert launch.running, launch.output()
        assert (up.missing, up.replaced, up.stopped) == ([], [], [])  # the launch's nodes, none replaced
        assert {node: up.nodes[node]["package"] for node in NODES} == {
            "/franka_control": "franka_control", "/franka_gripper": "franka_control",
            "/joint_state_publisher": "franka_control", "/serial_node": "rosserial_python"}
        wait_until(lambda: STUDENT_NODES <= twin.master.node_names(), "the student's nodes")
        assert twin.master.node_names() == {"/rosout", *NODES, *STUDENT_NODES}
        wait_until(lambda: logged(twin.work_dir, f"lab twin: ~port /dev/ttyACM0 is the twin's board at "
                                                 f"{twin.board_port}"), "serial_node's line about ~port")

        # The board's counts reach /pub_force through the launched serial_node at the launch's period.
        board = wait_report(twin, lambda r: r.board_samples_sent >= 100, "100 counts from the board")
        assert (board.board_period_ms, board.board["period_from_param"]) == (10, True)
        assert board.nodes["/serial_node"]["param_answers"] == {"~publish_period_ms": 1}
        assert board.pub_force_publishers == ["/serial_node"]
        assert_board_rate(board, 10)

        # The user stop holds for the franka_control the launch started: twists counted, the arm stays.
        held = wait_report(twin, lambda r: r.nonzero_twists >= 25 or not launch.running, "non-zero twists")
        assert launch.running, launch.output()
        assert held.activated is False and held.ignored_twists == held.twists >= held.nonzero_twists
        assert held.arm_moved_m == 0.0
        # The hand is not under the user stop: cross closed it from fully open (the fingers' joint states).
        closed = wait_report(twin, lambda r: r.gripper_goals.get("move", 0) >= 1
                             and (r.gripper_width_m or 1.0) < GRIPPER_MAX_WIDTH_M - 0.02, "the hand to close")
        assert set(closed.gripper_goals) == {"move"}

        # A press rises on /force_mapped (board -> serial_node -> the student's mapping_node): the pad
        # rumbles and the person lets go of the stick.
        watch = twin.run(["rostopic", "echo", "-n", "1", "--filter", "m.data > 0.5", "/force_mapped",
                          "__name:=force_watch"], "force_watch")
        wait_until(lambda: twin.master.connections("/force_watch", "/force_mapped") >= 1 or not watch.running,
                   "the watch on /force_mapped to connect")
        assert twin.report().board_last_count < 50  # at rest
        twin.press(700, 0.5)
        assert watch.wait(WAIT_S) == 0, watch.output()
        assert float(watch.output().split("data:")[1].split()[0]) > 0.5
        pushed = twin.report()
        at_rest = wait_report(twin, lambda r: r.twists - r.nonzero_twists >= pushed.twists - pushed.nonzero_twists + 10,
                              "the node to command rest once the stick is let go")
        assert at_rest.arm_moved_m == 0.0 and at_rest.board_presses == 1

        # The user stop released with the arm at rest (a released stop under a running command is a
        # reflex, as on the Panda): the next press, and the stick forward moves the arm, joints and all.
        twin.set_activated(True)
        twin.press(700, 20.0)
        moved = wait_report(twin, lambda r: r.arm_moved_m >= 0.01 or not launch.running, "the arm to move")
        assert launch.running, launch.output()
        assert moved.arm_position_m is not None and moved.arm_start_position_m is not None
        assert moved.arm_position_m[0] > moved.arm_start_position_m[0] + 0.005  # stick forward: +x
        joints = "joint_positions_rad"
        assert moved.nodes["/franka_control"][joints] != held.nodes["/franka_control"][joints]
        assert moved.nodes["/franka_control"]["arm_state"] != "reflex" and moved.error_recoveries == 0
        assert moved.board_presses == 2

        launch.stop()
        after = wait_report(twin, lambda r: r.missing == list(NODES), "the launch's nodes to be gone")
        assert (after.launched, after.replaced, after.stopped) == ([], [], [])
        assert all(after.nodes[node].get("stopped") is True for node in NODES), after.nodes
    assert not [p.argv for p in twin.started() if p.anything_left]


def test_on_a_running_twin_the_notebooks_start_of_the_launch_is_refused_in_one_line(lab_twin, tmp_path):
    env = lab_twin.env
    assert env["ROS_PACKAGE_PATH"].split(":")[-1] == str(lab_twin.packages)  # last, as an installed ROS
    listed = lab_twin.run(["roslaunch", "--nodes", str(ANSWER_LAUNCH)], "roslaunch_nodes")
    assert listed.wait(WAIT_S) == 0, listed.output()
    assert set(listed.output().split()) == {*NODES, *STUDENT_NODES}
    hardware = {(n.name, n.package, n.type) for n in launched_nodes([str(ANSWER_LAUNCH)], env) if n.package != "hri_lab"}
    assert hardware == {("/serial_node", "rosserial_python", "serial_node.py"),
                        ("/franka_control", "franka_control", "franka_control_node"),
                        ("/franka_gripper", "franka_control", "franka_gripper_node"),
                        ("/joint_state_publisher", "franka_control", "joint_state_publisher")}
    without_hand = launched_nodes(["franka_control", "franka_control_cartesian_velocity.launch", "load_gripper:=false"],
                                  env)
    assert [n.name for n in without_hand] == ["/franka_control", "/joint_state_publisher"]
    serial_node = lab_twin.packages / "rosserial_python" / "scripts" / "serial_node.py"
    assert os.access(serial_node, os.X_OK)

    before = lab_twin.report()
    kernel = lab_twin.run([sys.executable, "-c", KERNEL, str(ANSWER_KEY)], "kernel")
    assert kernel.wait(WAIT_S * 2) == 0, kernel.output()
    lines = kernel.output().strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("refused: "), lines
    assert "/franka_control" in lines[0] and "/serial_node" in lines[0] and "already running" in lines[0]
    after = lab_twin.report()
    assert (after.replaced, after.stopped, after.launched, after.missing) == ([], [], [], [])
    assert after.pids == before.pids
    assert lab_twin.master.node_names() == {"/rosout", *NODES}


def test_a_launch_by_hand_over_the_running_twins_robot_replaces_it_and_the_counts_go_on(lab_twin):
    robot = lab_twin.run(["roslaunch", "--wait", "franka_control", "franka_control_cartesian_velocity.launch"],
                         "robot_launch")
    robot_nodes = ["/franka_control", "/franka_gripper", "/joint_state_publisher"]
    report = wait_report(lab_twin, lambda r: r.launched == robot_nodes and r.stopped == robot_nodes
                         or not robot.running, "the launch's robot in place of the twin's")
    assert robot.running, robot.output()
    assert report.replaced == robot_nodes and report.stopped == robot_nodes  # the twin's own, taken over
    own = {node: lab_twin.processes[node].popen.pid for node in NODES}
    assert all(report.pids[node] != own[node] for node in robot_nodes)
    assert report.pids["/serial_node"] == own["/serial_node"] and "/serial_node" not in report.replaced
    # The replaced processes' last counts never overwrite the launched ones'.
    for node in robot_nodes:
        assert read_json(counts_path(lab_twin.folder, node)).get("stopped") is None
    # The user stop reaches the franka_control that runs now.
    lab_twin.set_activated(False)
    assert lab_twin.report().activated is False
    robot.stop()
    gone = lab_twin.report()
    assert gone.launched == [] and gone.missing == robot_nodes


def test_make_lab_twin_bare_says_what_to_export_and_each_node_a_launch_brings_up(tmp_path, ros_env):
    folder = tmp_path / "rehearsal"
    proc = subprocess.Popen([sys.executable, "-m", "hri_teleop.apps.lab_twin", "--bare", "--folder", str(folder)],
                            env=ros_env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True, cwd=REPO, start_new_session=True)
    lines: "queue.Queue[str]" = queue.Queue()
    threading.Thread(target=lambda: [lines.put(line) for line in proc.stdout], daemon=True).start()

    def read_until(*texts: str) -> List[str]:
        """Lines until each of ``texts`` was in one (a hang guard, never a measured time)."""
        seen: List[str] = []
        while not all(any(text in line for line in seen) for text in texts):
            seen.append(lines.get(timeout=WAIT_S * 2))
        return seen

    launch = None
    try:
        block = read_until("press 700 2 | activate")
        assert any(line.startswith("nodes    none yet (bare)") for line in block), block
        exports = dict(line.split("export ", 1)[1].split()[0].split("=", 1) for line in block if "export " in line)
        env = dict(ros_env, ROS_MASTER_URI=exports["ROS_MASTER_URI"], ROS_HOSTNAME="127.0.0.1",
                   ROS_LOG_DIR=str(tmp_path / "log"), ROS_HOME=str(tmp_path / "home"),
                   ROS_PACKAGE_PATH=exports["ROS_PACKAGE_PATH"].replace("$ROS_PACKAGE_PATH", ros_env["ROS_PACKAGE_PATH"]))
        launch = ManagedProcess(["roslaunch", "--wait", "franka_control", "franka_control_cartesian_velocity.launch",
                                 "load_gripper:=false"], env, tmp_path / "launch.log")
        said = "".join(read_until(*[f"{node} runs from the twin's installed packages"
                                    for node in ("/franka_control", "/joint_state_publisher")]))
        assert "/franka_gripper" not in said and "replaced" not in said, said
        launch.stop()
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=WAIT_S) == 130
    finally:
        if launch is not None:
            launch.stop()
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
