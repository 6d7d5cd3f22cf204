"""teleoperation.py with a wireless pad that freezes mid-deflection: the stale-input watchdog stops the arm.

The scripted pad plays a hand (its held stick trembles by a float step) until a ``freeze`` step,
after which it keeps reporting the same reading, as a pad whose Bluetooth link dropped without a
removal event. The node's input timeout sees a pad that answers; only the watchdog stops the twist.
"""

from __future__ import annotations

import pytest
import yaml
from test_teleoperation_node import TELEOP, TWIST, P, judged_violations  # tests/integration, on sys.path

from hri_teleop.core.gamepad import normalize_analog_input
from hri_teleop.ros.bags import read_topics

pytestmark = pytest.mark.ros

FREEZE_S, RESUME_S, QUIT_S = 2.0, 4.5, 5.5  # script times (node ticks)


def test_a_pad_frozen_mid_deflection_ramps_the_twist_to_zero_and_resumes_when_it_changes(ros_master, tmp_path):
    script = tmp_path / "frozen.yaml"
    script.write_text(yaml.safe_dump([
        {"t": 0.2, "axis": "left_y", "value": 1.0},     # full forward, held by a (trembling) hand
        {"t": FREEZE_S, "freeze": True},                # the link drops: the same reading from now on
        {"t": RESUME_S, "axis": "left_y", "value": 0.6},  # the link is back with a new reading
        {"t": QUIT_S, "press": "west"},                 # square: quit (ramps to zero, then exits)
    ]))
    bag = tmp_path / "frozen.bag"
    recorder = ros_master.record(bag, [TWIST])
    node = ros_master.run([str(TELEOP), "_pad:=virtual", f"_pad_script:={script}", "_script_wait_s:=60"],
                          "teleoperation")
    # The script starts once something other than rosbag listens: first let the recorder connect.
    ros_master.wait_for(lambda: any(ros_master.connections(s, TWIST) >= 1 for s in ros_master.subscribers(TWIST)
                                    if s.startswith("/record")) or not node.running, 20, "the recorder on the twist")
    robot = ros_master.run(["rostopic", "hz", TWIST], "robot_stand_in")
    code = node.wait(40)
    robot.stop()
    recorder.stop()
    out = node.output()
    assert code == 0, out
    msgs = read_topics(bag, [TWIST])[TWIST]
    vx = [m.linear.x for _, m in msgs]
    dt = 1.0 / P.rate_hz
    twists = [(m.linear.x, m.linear.y, m.linear.z, m.angular.x, m.angular.y, m.angular.z) for _, m in msgs]
    assert judged_violations(twists) == []

    # held by a hand for longer than stale_input_timeout before the freeze: full speed, no stop
    first_full = next(i for i, v in enumerate(vx) if v == pytest.approx(P.k_trans, abs=1e-9))
    held_ticks = int((FREEZE_S - 0.2) * P.rate_hz)
    assert held_ticks * dt > P.stale_input_timeout_s
    # frozen: the twist comes down to exactly zero and stays there until the reading changes
    stopped = next(i for i in range(first_full, len(vx)) if vx[i] == 0.0)
    resumed = next(i for i in range(stopped, len(vx)) if vx[i] > 0.0)
    frozen_for = (stopped - first_full) * dt
    assert P.stale_input_timeout_s < frozen_for < (FREEZE_S - 0.2) + P.stale_input_timeout_s + 1.0, frozen_for
    assert (resumed - stopped) * dt > 0.5, "did not stay stopped while frozen"
    # the new reading drives it again (0.6 through the dead zone, times the gain)
    assert max(vx[resumed:]) == pytest.approx(P.k_trans * normalize_analog_input(0.6, P.deadzone), abs=1e-9)
    assert out.count("have not changed for") == 1 and out.count("readings change again") == 1, out
