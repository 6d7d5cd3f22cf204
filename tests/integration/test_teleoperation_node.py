"""teleoperation.py for real on a private roscore, driven by a scripted virtual pad.

What a student does with the pad (handout Ex. 8-9) must come out on the topics: stick ->
twist with the gain, held cross -> gripper width in k_gripper/rate steps, triangle ->
rotation mode, /force_mapped -> rumble, pad lost -> twist ramps to zero inside the limits.
"""

from __future__ import annotations

import re
import time
from pathlib import Path

import pytest
import yaml

from hri_teleop.core.config import load_teleop_config
from hri_teleop.core.gamepad import normalize_analog_input
from hri_teleop.core.limits import limit_violations
from hri_teleop.ros.bags import read_topics

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
TELEOP = REPO / "hri_lab" / "scripts" / "teleoperation.py"
CONFIG = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml")
P = CONFIG.params
TWIST = CONFIG.twist_topic
TOPICS = [TWIST, "/gripper_width", "/teleoperation/rumble", "/joy", "/force_mapped"]


def _write_script(tmp_path, steps) -> Path:
    path = tmp_path / "pad_script.yaml"
    path.write_text(yaml.safe_dump(steps))
    return path


def _start_node(master, *args):
    # No robot here: the tests' scripts start at once (see test_a_pad_script_waits_for_the_robot).
    if not any(a.startswith("_script_wait_s:=") for a in args):
        args = args + ("_script_wait_s:=0",)
    node = master.run([str(TELEOP), "_pad:=virtual", *args], "teleoperation")
    master.wait_for(lambda: bool(master.publishers("/gripper_width")) or not node.running, 20,
                    "teleoperation to advertise /gripper_width")
    assert node.running, node.output()
    return node


def _twists(msgs):
    """Twists as tuples; the scripts start still, so the first recorded one must be zero."""
    assert msgs and all(c == 0.0 for c in _as_tuple(msgs[0][1])), "recording started mid-motion"
    return [_as_tuple(m) for _, m in msgs]


def _as_tuple(m):
    return (m.linear.x, m.linear.y, m.linear.z, m.angular.x, m.angular.y, m.angular.z)


def judged_violations(twists) -> list:
    """limit_violations of the recorded twists, each pair judged one tick apart.

    The node queues one second of ticks for each subscriber and rosbag keeps every message, so
    consecutive recorded twists are consecutive ticks of the controller however late the machine
    delivered them (their receipt times say nothing about that). A tick lost on the way would show
    here as a double step.
    """
    dt = 1.0 / P.rate_hz
    return limit_violations(CONFIG.limits, twists, [dt] * len(twists), rel_tol=1e-6)


def _echoed(echo) -> list:
    """The floats ``rostopic echo <topic>/<field>`` printed so far."""
    return [float(v) for v in re.findall(r"^(-?\d+\.\d+(?:e-?\d+)?)$", echo.output(), re.M)]


def test_pad_script_drives_twist_gripper_mode_and_rumble_then_loss_ramps_to_zero(ros_master, tmp_path):
    script = _write_script(tmp_path, [
        {"t": 0.5, "axis": "left_y", "value": 1.0},   # full forward
        {"t": 2.5, "axis": "left_y", "value": 0.0},
        {"t": 3.0, "press": "south"},                 # cross: close for 1 s
        {"t": 4.0, "release": "south"},
        {"t": 4.5, "press": "north"},                 # triangle: rotation mode
        {"t": 4.6, "release": "north"},
        {"t": 5.0, "axis": "left_y", "value": 0.5},
        {"t": 6.5, "disconnect": True},               # pad unplugged
    ])
    bag = tmp_path / "teleop.bag"
    recorder = ros_master.record(bag, TOPICS)
    force = ros_master.run(["rostopic", "pub", "-r", "50", "/force_mapped", "std_msgs/Float32", "data: 0.6"],
                           "force_pub")
    widths = ros_master.run(["rostopic", "echo", "/gripper_width/data"], "width_echo")
    turns = ros_master.run(["rostopic", "echo", f"{TWIST}/angular/x"], "wx_echo")
    node = _start_node(ros_master, f"_pad_script:={script}")
    try:
        # The script runs on the node's ticks: wait for what it did, not for the wall clock.
        closed = P.initial_width_m - P.k_gripper * 1.0 + 2 * P.k_gripper / P.rate_hz
        ros_master.wait_for(lambda: any(w <= closed for w in _echoed(widths)) or not node.running, 60,
                            "the held cross to close the gripper (script t = 3..4 s)")
        force.stop()  # the sensor goes silent: rumble must stop after force_timeout
        # rotation from t = 5 s, the pad unplugged at t = 6.5 s: the turn ramps to zero and stays there
        def turned_then_stopped() -> bool:
            wx = _echoed(turns)
            return any(v > 0 for v in wx) and all(v == 0.0 for v in wx[-25:]) and wx[-1:] == [0.0]

        ros_master.wait_for(lambda: turned_then_stopped() or not node.running, 60,
                            "the unplugged pad's turn to ramp to zero (script t = 6.5 s)")
    finally:
        widths.stop()
        turns.stop()
    types = ros_master.topic_types()
    assert node.stop() == 0, node.output()
    recorder.stop()

    assert types[TWIST] == "geometry_msgs/Twist"
    assert types["/gripper_width"] == "std_msgs/Float32"
    assert types["/joy"] == "sensor_msgs/Joy"
    data = read_topics(bag, TOPICS)
    msgs = data[TWIST]
    twists = _twists(msgs)
    assert len(twists) > 20

    # stick -> twist with the gain (full deflection: exactly k_trans after the ramp)
    assert max(t[0] for t in twists) == pytest.approx(P.k_trans, abs=1e-9)
    # triangle -> rotation: the same stick now turns about x, scaled by k_rot after the dead zone
    expected_wx = P.k_rot * normalize_analog_input(0.5, P.deadzone)
    assert max(t[3] for t in twists) == pytest.approx(expected_wx, abs=1e-9)
    assert all(abs(t[3]) < 1e-12 for t in twists if abs(t[0]) > 1e-12), "translation and rotation at once"
    # pad lost -> the command goes to zero and stays there
    assert all(c == 0.0 for t in twists[-20:] for c in t)
    # every command, including the ramps, is inside the configured limits
    assert judged_violations(twists) == []

    # held cross -> width shrinks by k_gripper/rate per tick, never below 0
    widths = [m.data for _, m in data["/gripper_width"]]
    assert widths[0] == pytest.approx(P.initial_width_m, abs=1e-7)
    steps = {round(a - b, 6) for a, b in zip(widths, widths[1:])}
    assert steps <= {0.0, round(P.k_gripper / P.rate_hz, 6)}, steps
    closed_by = P.initial_width_m - min(widths)
    assert closed_by == pytest.approx(P.k_gripper * 1.0, abs=3 * P.k_gripper / P.rate_hz)

    # /force_mapped -> rumble; silent sensor -> rumble off within force_timeout (+ one tick)
    rumble = [(t, m.data) for t, m in data["/teleoperation/rumble"]]
    assert any(abs(v - 0.6) < 1e-6 for _, v in rumble)
    last_force_t = data["/force_mapped"][-1][0]
    off = [t for t, v in rumble if t > last_force_t and v == 0.0]
    assert off, "rumble never stopped after /force_mapped went silent"
    assert all(v == 0.0 for t, v in rumble if t > off[0])  # (within force_timeout: the controller's unit tests)

    # /joy carries the raw pad state while it is connected
    assert len(data["/joy"]) > 100


def test_square_quits_after_ramping_the_twist_to_zero(ros_master, tmp_path):
    script = _write_script(tmp_path, [
        {"t": 1.0, "axis": "left_x", "value": -1.0},
        {"t": 2.5, "press": "west"},
    ])
    bag = tmp_path / "quit.bag"
    recorder = ros_master.record(bag, [TWIST])
    node = _start_node(ros_master, f"_pad_script:={script}")
    code = node.wait(15)
    recorder.stop()
    assert code == 0, node.output()
    msgs = read_topics(bag, [TWIST])[TWIST]
    twists = _twists(msgs)
    assert max(t[1] for t in twists) == pytest.approx(P.k_trans, abs=1e-9)  # -left_x drives +vy
    assert all(c == 0.0 for c in twists[-1])
    assert judged_violations(twists) == []


def test_sigint_mid_motion_ramps_to_zero_before_exit(ros_master, tmp_path):
    script = _write_script(tmp_path, [{"t": 1.0, "axis": "left_y", "value": 1.0}])
    bag = tmp_path / "sigint.bag"
    recorder = ros_master.record(bag, [TWIST])
    node = _start_node(ros_master, f"_pad_script:={script}")
    time.sleep(3.0)
    assert node.stop() == 0, node.output()
    recorder.stop()
    msgs = read_topics(bag, [TWIST])[TWIST]
    twists = _twists(msgs)
    assert max(t[0] for t in twists) > 0.05
    assert all(c == 0.0 for c in twists[-1]), twists[-5:]
    assert judged_violations(twists) == []


@pytest.mark.parametrize("args, words", [
    (["_pad:=pygame"], "no gamepad"),
    (["_layout:=nintendo64"], "nintendo64"),
    (["_k_trans:=-1"], "k_trans"),
    (["_rumble_log:=/nonexistent-dir/rumble.log"], "cannot write the rumble log '/nonexistent-dir/rumble.log'"),
])
def test_bad_setup_stops_the_node_with_one_line_and_no_traceback(ros_master, args, words):
    node = ros_master.run([str(TELEOP), *(["_pad:=virtual"] if "_pad:=pygame" not in args else []), *args],
                          "teleoperation")
    code = node.wait(20)
    out = node.output()
    assert code not in (None, 0), out
    assert "Traceback" not in out, out
    assert any(words in line for line in out.splitlines()), out


def test_malformed_config_yaml_names_the_file_and_line(ros_master, tmp_path):
    bad = tmp_path / "teleop.yaml"
    bad.write_text("rate: 50\nk_trans: [0.1\n")
    node = ros_master.run([str(TELEOP), "_pad:=virtual", f"_config:={bad}"], "teleoperation")
    code = node.wait(20)
    out = node.output()
    assert code not in (None, 0) and "Traceback" not in out, out
    assert any(str(bad) in line for line in out.splitlines()), out


def test_a_second_sigint_ends_the_node_at_once(ros_master, tmp_path):
    import os
    import re
    import signal

    script = _write_script(tmp_path, [{"t": 0.5, "axis": "left_y", "value": 1.0}])
    # A slow deceleration: the ramp down takes as long as the ramp up (seconds), so the second signal
    # reliably arrives while it runs; without the signal's effect the ramp ends at zero, not abandoned.
    config = tmp_path / "slow_ramp.yaml"
    data = yaml.safe_load((REPO / "hri_lab" / "config" / "teleop.yaml").read_text())
    data["limits"]["translation"].update(acceleration=0.01, jerk=0.05)
    config.write_text(yaml.safe_dump(data))
    node = _start_node(ros_master, f"_pad_script:={script}", f"_config:={config}", "_stop_timeout_s:=60.0")
    echo = ros_master.run(["rostopic", "echo", f"{TWIST}/linear/x"], "twist_x")
    try:
        def moving():
            return [float(v) for v in re.findall(r"^(-?\d+\.\d+(?:e-?\d+)?)$", echo.output(), re.M)]

        ros_master.wait_for(lambda: any(v > 0.04 for v in moving()) or not node.running, 30, "the twist to move")
        os.killpg(node.pgid, signal.SIGINT)
        ros_master.wait_for(lambda: "ramping the twist to zero" in node.output() or not node.running, 30,
                            "the first Ctrl-C to start the ramp")
        os.killpg(node.pgid, signal.SIGINT)
        code = node.wait(30)  # a hang guard
    finally:
        echo.stop()
    assert code == 0, node.output()
    assert "ramp abandoned" in node.output() and "twist not zero after" not in node.output()


def test_a_pad_that_cannot_be_read_ramps_the_twist_to_zero_and_resumes_after(ros_master, tmp_path):
    script = _write_script(tmp_path, [
        {"t": 1.0, "axis": "left_y", "value": 1.0},
        {"t": 3.0, "fail": True},      # the device stops answering while the stick is held
        {"t": 5.0, "recover": True},
    ])
    bag = tmp_path / "fail.bag"
    recorder = ros_master.record(bag, [TWIST])
    node = _start_node(ros_master, f"_pad_script:={script}")
    time.sleep(7.5)
    assert node.stop() == 0, node.output()
    recorder.stop()
    msgs = read_topics(bag, [TWIST])[TWIST]
    twists = _twists(msgs)
    vx = [t[0] for t in twists]
    first_full = vx.index(max(vx))
    zero_after = next(i for i in range(first_full, len(vx)) if vx[i] == 0.0)
    assert any(v == pytest.approx(P.k_trans) for v in vx[zero_after:]), "did not resume after recovery"
    assert "cannot read the gamepad" in node.output()
    assert judged_violations(twists) == []


def test_virtual_joy_drives_the_pad_and_silence_ramps_to_zero(ros_master, tmp_path):
    """pad:=virtual without a script listens on ~virtual_joy; input older than input_timeout stops."""
    from hri_teleop.core.gamepad import PadState
    from hri_teleop.core.gamepad.layout import as_layout

    layout = as_layout(CONFIG.layout)  # auto: a virtual pad has the default
    axes, buttons = layout.raw_from_state(PadState({"left_y": 1.0}, {}, True))
    joy = "{axes: %s, buttons: %s}" % ([float(a) for a in axes], [int(b) for b in buttons])
    bag = tmp_path / "vjoy.bag"
    recorder = ros_master.record(bag, [TWIST])
    node = _start_node(ros_master)
    time.sleep(1.0)
    pub = ros_master.run(["rostopic", "pub", "-r", "20", "/teleoperation/virtual_joy", "sensor_msgs/Joy", joy],
                         "virtual_joy")
    time.sleep(3.0)
    pub.stop()  # the input goes stale
    silent_at = time.time()
    time.sleep(3.0)
    assert node.stop() == 0, node.output()
    recorder.stop()
    msgs = read_topics(bag, [TWIST])[TWIST]
    twists = _twists(msgs)
    assert max(t[0] for t in twists) == pytest.approx(P.k_trans)
    # stale after input_timeout, then the ramp down from k_trans (how soon: the watchdog's unit tests)
    assert any(t > silent_at and m.linear.x == 0.0 for t, m in msgs), "the twist never came back to zero"
    assert twists[-1] == (0.0,) * 6
    assert judged_violations(twists) == []


def test_a_pad_script_waits_for_the_robot_to_listen_before_it_moves_the_stick(ros_master, tmp_path):
    """Nodes of one launch start in any order: a stick moved before the robot subscribed would
    reach it as a velocity step. The script starts when the twist topic has a subscriber other
    than a recorder (rosbag may well subscribe first)."""
    script = _write_script(tmp_path, [{"t": 0.2, "axis": "left_y", "value": 1.0}])
    node = _start_node(ros_master, f"_pad_script:={script}", "_script_wait_s:=30")
    bag = tmp_path / "late.bag"
    recorder = ros_master.record(bag, [TWIST])  # a recorder is no robot: the script keeps waiting
    time.sleep(2.0)
    robot_at = time.time()
    robot = ros_master.run(["rostopic", "echo", "-n", "1000", TWIST], "robot_stand_in")
    time.sleep(2.5)
    recorder.stop()
    robot.stop()
    node.stop()
    msgs = read_topics(bag, [TWIST])[TWIST]
    before = [m.linear.x for t, m in msgs if t < robot_at]
    after = [m.linear.x for t, m in msgs if t >= robot_at]
    assert len(before) > 50 and all(v == 0.0 for v in before), "the stick moved before the robot listened"
    assert max(after) > 0.05
    assert "pad script starts: " in node.output()
