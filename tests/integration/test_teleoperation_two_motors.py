"""teleoperation.py keeps force and joint warning apart on the pad's two motors, and says the pad took rumble.

Over a real roscore: /force_mapped at 0.3 and joint 7 within the warning margin of its limit. The
node's rumble log (which records both motors) must show the force on the low-frequency motor and
the warning's pulse on the high-frequency one; ~rumble_ok is latched True for a pad that accepts.
"""

from __future__ import annotations

import pytest
import yaml
from test_teleoperation_node import TELEOP  # tests/integration, on sys.path under pytest

from hri_teleop.core.joints import JOINT_NAMES, READY_POSE_RAD, ROBOT_JOINT_LIMITS, WARNING_MARGIN_RAD, WARNING_RUMBLE
from hri_teleop.sim.virtual_pad import read_rumble_log

pytestmark = pytest.mark.ros

FORCE = 0.3


def test_force_on_the_strong_motor_warning_on_the_weak_one_and_rumble_ok_latched(ros_master, tmp_path):
    master = ros_master
    near = list(READY_POSE_RAD)
    near[6] = ROBOT_JOINT_LIMITS.position_max_rad[6] - WARNING_MARGIN_RAD / 2  # joint 7 inside the margin
    states = yaml.safe_dump({"name": list(JOINT_NAMES), "position": near}, default_flow_style=True).strip()
    master.run(["rostopic", "pub", "-r", "30", "/franka_state_controller/joint_states", "sensor_msgs/JointState",
                states], "joint_states")
    master.run(["rostopic", "pub", "-r", "50", "/force_mapped", "std_msgs/Float32", f"data: {FORCE}"], "force")
    script, log = tmp_path / "still.yaml", tmp_path / "rumble.log"
    script.write_text(yaml.safe_dump([{"t": 0.0, "axis": "left_y", "value": 0.0}]))  # a pad held at rest
    node = master.run([str(TELEOP), "_pad:=virtual", f"_pad_script:={script}", "_script_wait_s:=0",
                       f"_rumble_log:={log}"], "teleoperation")

    def both_phases() -> bool:
        records = read_rumble_log(log) if log.exists() else []
        pairs = {(r.low, r.high) for r in records}
        return ((FORCE, WARNING_RUMBLE) in pairs and (FORCE, 0.0) in pairs) or not node.running

    master.wait_for(both_phases, 30, "the rumble log to show the warning's pulse on and off over the force")
    echo = master.run(["rostopic", "echo", "-n", "1", "/teleoperation/rumble_ok"], "echo")
    assert echo.wait(20) == 0, echo.output()
    assert node.stop() == 0, node.output()
    assert "data: True" in echo.output()
    records = [r for r in read_rumble_log(log) if r.intensity > 0.0]
    # The two publishers connect to the node in either order: until its first force arrives, the
    # warning's pulse alone is on the weak motor; from then on the force alone is on the strong one.
    first = next(i for i, r in enumerate(records) if r.low == FORCE)
    assert all((r.low, r.high) == (0.0, WARNING_RUMBLE) for r in records[:first]), records[:first]
    assert {r.low for r in records[first:]} == {FORCE}  # the log keeps 6 decimals
    assert {r.high for r in records[first:]} == {0.0, WARNING_RUMBLE}  # the pulse alone on the weak one
    assert all(r.intensity == max(r.low, r.high) for r in records)
