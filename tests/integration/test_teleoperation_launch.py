"""teleoperation.launch (handout Ex. 12-13) without robot and Arduino, for real.

The same launch file as in the lab, with robot:=false arduino:=false pad:=virtual: the
simulated sensor replaces the Arduino, and a stand-in franka_gripper move server takes
the gripper_manager's goals so that we can count them.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from hri_teleop.core.config import load_teleop_config
from hri_teleop.ros.bags import read_topics

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
FAKE_GRIPPER = Path(__file__).with_name("fake_gripper_move_server.py")
P = load_teleop_config(REPO / "hri_lab" / "config" / "teleop.yaml").params


def _events(goal_log: Path) -> list:
    """The stand-in server's goal log so far (goal, done, cancel)."""
    if not goal_log.exists():
        return []
    return [json.loads(line) for line in goal_log.read_text().splitlines() if line.endswith("}")]


def test_whole_launch_runs_without_hardware_and_gripper_goals_are_throttled(ros_master, tmp_path):
    goal_log = tmp_path / "goals.jsonl"
    gripper = ros_master.run([str(FAKE_GRIPPER), f"_log:={goal_log}"], "fake_gripper")
    ros_master.wait_for(lambda: bool(ros_master.subscribers("/franka_gripper/move/goal")), 20,
                        "the stand-in gripper server")
    script = tmp_path / "close.yaml"
    script.write_text(yaml.safe_dump([
        {"t": 1.5, "press": "south"},    # close for 1.5 s: 0.06 m at 0.04 m/s
        {"t": 3.0, "release": "south"},
    ]))
    bag = tmp_path / "launch.bag"
    recorder = ros_master.record(bag, ["/gripper_width", "/force_mapped"])
    launch = ros_master.roslaunch("hri_lab", "teleoperation.launch", {
        "robot": "false", "arduino": "false", "pad": "virtual", "pad_script": script, "sim_rate_hz": 50,
    })
    ros_master.wait_for(lambda: {"/teleoperation", "/gripper_manager", "/mapping_node", "/FSR_sensor"}
                        <= ros_master.node_names() or not launch.running, 30, "the launch file's four nodes")
    assert launch.running, launch.output()
    assert ros_master.get_param("/max_sensor_force") == 700
    # The script runs on the node's ticks: the goal of the final width comes once the script is over.
    final = P.initial_width_m - 1.5 * P.k_gripper
    ros_master.wait_for(lambda: any(e["event"] == "goal" and abs(e["width"] - final) <= 3 * P.k_gripper / P.rate_hz
                                    for e in _events(goal_log)) or not launch.running, 60,
                        "the gripper_manager's goal of the final width")
    launch.stop()
    recorder.stop()
    gripper.stop()

    data = read_topics(bag, ["/gripper_width", "/force_mapped"])
    widths = [m.data for _, m in data["/gripper_width"]]
    assert widths[0] == pytest.approx(P.initial_width_m)  # recorded from before the cross was pressed
    assert len(data["/force_mapped"]) >= 10, "the simulated sensor's force did not reach /force_mapped"
    final_width = widths[-1]
    assert final_width == pytest.approx(P.initial_width_m - 1.5 * P.k_gripper, abs=3 * P.k_gripper / P.rate_hz)

    events = _events(goal_log)
    goals = sorted((e for e in events if e["event"] == "goal"), key=lambda e: e["stamp"])
    distinct_targets = len(set(round(w, 6) for w in widths))
    # ~75 distinct targets while closing; at most max_goal_rate_hz (5/s) become goals
    assert distinct_targets > 50
    assert 2 <= len(goals) <= 15, f"{len(goals)} goals for {distinct_targets} targets"
    assert goals[-1]["width"] == pytest.approx(final_width, abs=1e-6), "the final width never became a goal"
    # a newer target preempts: a goal still running when the next one is sent is cancelled (the
    # stand-in server takes 0.3 s per move, longer than the 0.2 s between goals), never the last one
    ends = {e["stamp"]: e["event"] for e in events if e["event"] in ("done", "cancel")}
    assert all(g["stamp"] in ends for g in goals[:-1]), f"a goal neither finished nor was cancelled: {events}"
    cancelled = [g for g in goals if ends.get(g["stamp"]) == "cancel"]
    assert cancelled and goals[-1] not in cancelled, events
    # at most max_goal_rate_hz, on the sender's clock (the goals' stamps: no transport delay in them)
    gaps = [b["stamp"] - a["stamp"] for a, b in zip(goals, goals[1:])]
    assert min(gaps) >= 0.2 - 0.01, f"goals sent {min(gaps):.3f} s apart: faster than 5 per second"
