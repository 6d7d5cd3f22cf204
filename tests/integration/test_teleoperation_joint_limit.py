"""teleoperation.py warns before a joint limit and recovers the robot on a pad gesture, for real.

With lab_sim on a private roscore: in rotation mode the right stick held down turns the hand about
the vertical until joint 7 reaches its limit (hri_lab/scenarios/joint_limit.yaml). The node must
warn (a log line, a pulsing rumble) before the robot stops, and options (start) must then send
franka_control's error recovery, which lab_sim serves. The pad is driven through ``~virtual_joy``
by virtual_pad_driver.py, which waits for lab_sim's state instead of guessing durations.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Dict

import pytest
import yaml

from hri_teleop.core.config import load_teleop_config
from hri_teleop.core.joints import JOINT_NAMES, JOINT_POSITION_LIMITS_VIOLATION, READY_POSE_RAD, ROBOT_JOINT_LIMITS
from hri_teleop.ros.bags import read_topics

pytestmark = pytest.mark.ros

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
TELEOP = REPO / "hri_lab" / "scripts" / "teleoperation.py"
LAB_SIM = REPO / "hri_lab" / "scripts" / "lab_sim.py"
DRIVER = HERE / "virtual_pad_driver.py"
CONFIG = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml")
TWIST = CONFIG.twist_topic
RUMBLE = "/teleoperation/rumble"
STATUS = "/lab_sim/arm_status"
WARNING_RUMBLE = 0.6  # ~joint_warning_rumble's default

NEUTRAL: Dict[str, object] = {}
PLAN = [
    {"pad": NEUTRAL, "for": 0.5},
    {"pad": {"buttons": ["north"]}, "for": 0.2},                            # triangle: rotation mode
    {"pad": NEUTRAL, "for": 0.3},
    {"pad": {"axes": {"right_y": -1.0}}, "until": "reflex", "timeout": 40},  # turn about -z until the robot stops
    {"pad": NEUTRAL, "until": "still", "timeout": 10},                      # let go: the twist ramps to zero
    {"pad": {"buttons": ["start"]}, "for": 0.2},                            # options: error recovery
    {"pad": NEUTRAL, "until": "idle", "timeout": 10},
    {"pad": NEUTRAL, "for": 0.3},
]


def _values(status) -> Dict[str, str]:
    return {kv.key: kv.value for kv in status.values}


def _start_teleop(master, *args):
    node = master.run([str(TELEOP), "_pad:=virtual", *args], "teleoperation")
    master.wait_for(lambda: bool(master.publishers(RUMBLE)) or not node.running, 20, "teleoperation to advertise ~rumble")
    assert node.running, node.output()
    return node


def test_turning_to_joint_7s_limit_warns_before_the_reflex_and_options_recovers(ros_master, tmp_path):
    master = ros_master
    sim = master.run([str(LAB_SIM), "_object:=none", "_board:=false"], "lab_sim")
    master.wait_for(lambda: bool(master.subscribers(TWIST)) or not sim.running, 30,
                    "lab_sim to subscribe the twist topic (the last thing it sets up)")
    assert sim.running, sim.output()
    teleop = _start_teleop(master)
    # the node's joint states and its recovery client are connected to lab_sim
    master.wait_for(lambda: master.connections("/teleoperation", "/franka_state_controller/joint_states") >= 1, 20,
                    "teleoperation to connect to lab_sim's joint states")
    master.wait_for(lambda: master.connections("/teleoperation", "/franka_control/error_recovery/status") >= 1
                    and master.connections("/lab_sim", "/franka_control/error_recovery/goal") >= 1, 20,
                    "the error recovery client and server to connect")
    bag = tmp_path / "joint_limit.bag"
    topics = [RUMBLE, STATUS, "/rosout", "/franka_state_controller/joint_states"]
    recorder = master.record(bag, topics)
    plan, log = tmp_path / "plan.json", tmp_path / "driver.jsonl"
    plan.write_text(json.dumps(PLAN))
    driver = master.run([str(DRIVER), f"_plan:={plan}", f"_log:={log}", f"_layout:={CONFIG.layout}"], "driver")
    assert driver.wait(90.0) == 0, driver.output()
    recorder.stop()
    assert teleop.stop() == 0, teleop.output()
    assert sim.stop() == 0, sim.output()

    events = [json.loads(line) for line in log.read_text().splitlines()]
    assert events[0]["event"] == "ready" and events[0]["connected"], events[0]
    assert [e["event"] for e in events[1:]] == ["done"] * len(PLAN), events
    data = read_topics(bag, topics)

    # lab_sim's reflex: joint 7's position limit, nothing else
    reflexes = [(t, _values(m)) for t, m in data[STATUS] if _values(m)["state"] == "reflex"]
    assert reflexes, "the robot never stopped"
    reflex_t, reflex = reflexes[0]
    assert reflex["reflex_errors"] == JOINT_POSITION_LIMITS_VIOLATION, reflex
    assert "joint 7" in reflex["explanation"], reflex["explanation"]

    # the warning: one log line naming joint 7, before the reflex
    warnings = [(t, m.msg) for t, m in data["/rosout"] if m.name == "/teleoperation" and m.msg.startswith("joint limit:")]
    assert len(warnings) == 1, warnings
    warned_t, line = warnings[0]
    assert "joint 7 is" in line and "max limit" in line, line
    assert warned_t < reflex_t
    # where the joint was when it was warned: inside the margin, short of the limit
    states = [m for t, m in data["/franka_state_controller/joint_states"] if t <= warned_t]
    assert list(states[-1].name) == list(JOINT_NAMES)
    q7_limit = ROBOT_JOINT_LIMITS.position_max_rad[6]
    assert 0.0 < q7_limit - states[-1].position[6] < 0.1  # the state that started it: inside 0.1 rad
    assert states[0].position[6] == pytest.approx(READY_POSE_RAD[6], abs=1e-6)

    # the pulse: the warning's rumble, on and off, starting before the reflex (no force: no board)
    rumble = [(t, m.data) for t, m in data[RUMBLE]]
    before = [v for t, v in rumble if t < warned_t - 0.1]
    assert before and all(v == 0.0 for v in before)
    pulse = [(t, v) for t, v in rumble if t >= warned_t - 0.1]
    first_on = next(t for t, v in pulse if v == pytest.approx(WARNING_RUMBLE))
    assert first_on < reflex_t
    assert sum(1 for t, v in rumble if warned_t < t < first_on) <= 2, "the pulse must start on, with the warning"
    after_on = [v for t, v in pulse if first_on <= t <= first_on + 1.0]
    switches = sum(1 for a, b in zip(after_on, after_on[1:]) if (a == 0.0) != (b == 0.0))
    assert switches >= 3, after_on  # on, off, on, off ...: a pulse of 0.4 s
    assert set(round(v, 6) for v in after_on) <= {0.0, WARNING_RUMBLE}

    # options: the node sends franka_control's error recovery, lab_sim recovers
    out = teleop.output()
    assert "error recovery: goal sent to /franka_control/error_recovery" in out, out
    assert "error recovery succeeded: recovered from reflex" in out, out
    after = [_values(m)["state"] for t, m in data[STATUS] if t > reflex_t]
    assert after[-1] == "idle", after[-10:]
    assert after.count("reflex") >= 1 and "recovered from reflex" in sim.output()


def test_without_a_recovery_server_options_says_so_in_one_line(ros_master, tmp_path):
    script = tmp_path / "options.yaml"
    script.write_text(yaml.safe_dump([{"t": 0.3, "tap": "start", "hold": 0.1}, {"t": 1.0, "tap": "start", "hold": 0.1}]))
    node = _start_teleop(ros_master, f"_pad_script:={script}", "_script_wait_s:=0")
    ros_master.wait_for(lambda: node.output().count("error recovery: no franka_msgs/ErrorRecoveryAction server") >= 2
                        or not node.running, 20, "two presses of options to be answered")
    assert node.stop() == 0, node.output()
    lines = [line for line in node.output().splitlines() if "error recovery" in line]
    assert len(lines) == 2, lines  # one line per press
    assert "on /franka_control/error_recovery; in the lab start franka_control" in lines[0]
    assert "Traceback" not in node.output()


def test_stale_joint_states_end_the_warning_and_its_rumble(ros_master, tmp_path):
    near = list(READY_POSE_RAD[:6]) + [ROBOT_JOINT_LIMITS.position_max_rad[6] - 0.05]
    script = tmp_path / "still.yaml"  # a connected pad that stays still (a silent pad would stop the node's rumble)
    script.write_text(yaml.safe_dump([{"t": 600.0, "axis": "left_x", "value": 0.0}]))
    node = _start_teleop(ros_master, "_joint_states_topic:=/test_joint_states", f"_pad_script:={script}",
                         "_script_wait_s:=0")
    bag = tmp_path / "stale.bag"
    recorder = ros_master.record(bag, [RUMBLE])
    state = "{name: %s, position: %s}" % (list(JOINT_NAMES) + ["panda_finger_joint1"], near + [0.04])
    pub = ros_master.run(["rostopic", "pub", "-r", "30", "/test_joint_states", "sensor_msgs/JointState", state],
                         "joint_states")
    ros_master.wait_for(lambda: "joint limit: joint 7 is 0.05 rad from its max limit" in node.output()
                        or not node.running, 20, "the warning")
    ros_master.wait_for(lambda: ros_master.connections("/teleoperation", "/test_joint_states") >= 1, 5, "connection")
    pub.stop()
    ros_master.wait_for(lambda: "joint limit warning ended: no joint states for 0.50 s" in node.output()
                        or not node.running, 10, "the warning to end")
    assert node.stop() == 0, node.output()
    recorder.stop()
    rumble = [(t, m.data) for t, m in read_topics(bag, [RUMBLE])[RUMBLE]]
    on = [t for t, v in rumble if v > 0.0]
    assert on, "the warning never rumbled"
    # after the last pulse, silence to the end: the warning ended with the states
    assert all(v == 0.0 for t, v in rumble if t > on[-1])
    assert rumble[-1][1] == 0.0
    assert node.output().count("joint limit:") == 1
