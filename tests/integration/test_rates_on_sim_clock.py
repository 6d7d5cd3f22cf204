"""Each node's topics at their rates, counted on simulated time: the test owns /clock.

lab_sim.py and the sensor launch follow /clock when /use_sim_time is set (as under the
grader). clock_stepper.py moves it in small steps and waits after each until the nodes
wait, so a second of simulated time holds the same messages on an idle or a busy machine;
the counts below are exact but for one message at a window's edge.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Dict, List, Optional

import pytest

from hri_teleop.ros.master import PrivateMaster

pytestmark = pytest.mark.ros

HERE = Path(__file__).resolve().parent
LAB_SIM = HERE.parents[1] / "hri_lab" / "scripts" / "lab_sim.py"
STEPPER = HERE / "clock_stepper.py"
# The judged window, simulated s after the first reading: one second, away from the start and the end.
WINDOW = (0.5, 1.5)


def _step_clock(master: PrivateMaster, tmp_path: Path, roots: List[int], topics: List[str], listeners: int,
                step_s: float, steps: int) -> Dict[str, List[List[Optional[float]]]]:
    log = tmp_path / "clock.json"
    stepper = master.run([str(STEPPER), f"_step_s:={step_s}", f"_steps:={steps}",
                          f"_pids:={','.join(str(p) for p in roots)}", f"_topics:={','.join(topics)}",
                          f"_listeners:={listeners}", f"_log:={log}"], "clock_stepper")
    assert stepper.wait(240.0) == 0, stepper.output()  # hang guard only
    record = json.loads(log.read_text())
    start = record["start_s"]
    return {t: [[r - start, None if s is None else s - start] for r, s in msgs]
            for t, msgs in record["messages"].items()}


def _in_window(times: List[Optional[float]]) -> int:
    return sum(1 for t in times if t is not None and WINDOW[0] <= t < WINDOW[1])


def test_on_the_simulated_clock_lab_sims_topics_come_at_their_rates(ros_master, tmp_path):
    topics = ["/lab_sim/ee_pose", "/lab_sim/ee_twist", "/franka_gripper/joint_states",
              "/franka_state_controller/joint_states", "/joint_states", "/pub_force"]
    ros_master.set_param("/use_sim_time", True)
    node = ros_master.run([str(LAB_SIM), "_object:=none", "_board_rate_hz:=100.0"], "lab_sim")
    ros_master.wait_for(lambda: bool(ros_master.subscribers("/cartesian_velocity_controller/cmd_vel"))
                        or not node.running, 30, "lab_sim to subscribe the twist topic (the last thing it sets up)")
    assert node.running, node.output()
    seen = _step_clock(ros_master, tmp_path, [node.popen.pid], topics, listeners=2, step_s=0.002, steps=1000)
    assert node.stop() == 0, node.output()
    stamped = {t: _in_window([s for _r, s in seen[t]]) for t in topics[:-1]}
    assert stamped == {"/lab_sim/ee_pose": pytest.approx(100, abs=1), "/lab_sim/ee_twist": pytest.approx(100, abs=1),
                       "/franka_gripper/joint_states": pytest.approx(30, abs=1),
                       "/franka_state_controller/joint_states": pytest.approx(30, abs=1),
                       "/joint_states": pytest.approx(30, abs=1)}
    # The board's counts carry no stamp: counted when they came, a tick (2 ms) after their sample at most.
    assert _in_window([r for r, _s in seen["/pub_force"]]) == pytest.approx(100, abs=2)


@pytest.mark.parametrize("rate_hz", [50, 10])
def test_on_the_simulated_clock_the_sensor_launch_publishes_at_its_rate_hz(ros_master, tmp_path, rate_hz):
    ros_master.set_param("/use_sim_time", True)
    launch = ros_master.roslaunch("hri_lab", "sensor.launch", {"rate_hz": rate_hz})
    ros_master.wait_for(lambda: bool(ros_master.subscribers("/pub_force")) or not launch.running, 30,
                        "sensor.launch's mapping node to subscribe /pub_force")
    ros_master.wait_for(lambda: bool(ros_master.publishers("/force_mapped")) or not launch.running, 30,
                        "sensor.launch's mapping node to advertise /force_mapped")
    assert launch.running, launch.output()
    seen = _step_clock(ros_master, tmp_path, [launch.popen.pid], ["/pub_force", "/force_mapped"], listeners=3,
                       step_s=0.005, steps=400)
    launch.stop()
    counts = {t: _in_window([r for r, _s in msgs]) for t, msgs in seen.items()}
    # a count and its mapping come in the tick that sent the count, or the next
    assert counts == {"/pub_force": pytest.approx(rate_hz, abs=1), "/force_mapped": pytest.approx(rate_hz, abs=1)}
