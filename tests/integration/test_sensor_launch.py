"""sensor.launch (handout Ex. 5-7) for real: roslaunch on a private roscore, rosbag record,
and the mapping checked message by message against hri_teleop.core.mapping."""

from __future__ import annotations

from pathlib import Path

import pytest

from hri_teleop.core.mapping import map_force
from hri_teleop.core.traces import pair_outputs
from hri_teleop.ros.sensor_demo import record_sensor_launch

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
MAPPING_NODE = REPO / "hri_lab" / "scripts" / "mapping_node.py"


def _record_sensor_launch(master, tmp_path, duration_s, **launch_args):
    rec = record_sensor_launch(master, tmp_path / "sensor.bag", duration_s, launch_args)
    return rec.topic_types, rec.counts, rec.mapped


@pytest.mark.parametrize("max_sensor_force", [700, 350])
def test_force_mapped_is_float32_and_equals_the_mapping_of_pub_force(ros_master, tmp_path, max_sensor_force):
    types, counts, mapped = _record_sensor_launch(ros_master, tmp_path, 3.0,
                                                  max_sensor_force=max_sensor_force, rate_hz=50)
    assert types["/pub_force"] == "std_msgs/Int16"
    assert types["/force_mapped"] == "std_msgs/Float32"
    # enough to judge the mapping by; the rate itself is counted on simulated time (test_rates_on_sim_clock.py)
    assert len(mapped) >= 10, f"only {len(mapped)} messages on /force_mapped in 3 s at 50 Hz"
    # rosbag connects to the two topics one after the other, and a busy machine delays the outputs:
    # the first outputs may answer counts recorded before, the last counts' outputs may come after.
    # Those edges are outside the matched span, however many a load makes them; inside it every
    # output must be its count's mapping, and at most two unjudged (a duplicate, a lost count).
    pairing = pair_outputs(counts, mapped, lambda c: float(map_force(c, max_sensor_force)), tolerance=1e-6)
    assert pairing.unmatched_outputs == 0, "values on /force_mapped that are no count's mapping"
    assert pairing.unjudged_outputs - pairing.outside_outputs <= 2, pairing
    assert len(pairing.pairs) >= 10, f"only {len(pairing.pairs)} outputs paired with their counts"
    assert all(0.0 <= v <= 1.0 for _, v in mapped)
    # The simulated presses go past the parameter, so the clipping is exercised too.
    assert max(c for _, c in counts) > max_sensor_force * 0.9


def test_sensor_launch_optionally_loads_the_robot_params_of_ex_7(ros_master):
    launch = ros_master.roslaunch("hri_lab", "sensor.launch", {"load_robot_params": "true"})
    ros_master.wait_for(lambda: bool(ros_master.publishers("/force_mapped")), 20, "/force_mapped")
    assert ros_master.get_param("/robot_mass") == 18.0
    assert isinstance(ros_master.get_param("/robot_mass"), float)
    assert ros_master.get_param("/load_gripper") is True
    assert ros_master.get_param("/gains") == {"p": 10.0, "i": 1.0, "d": 5.0}
    assert ros_master.get_param("/max_sensor_force") == 700
    launch.stop()


@pytest.mark.parametrize("value, words", [
    (None, "not set"),
    (0, "0"),
    (-5, "-5"),
    ("abc", "abc"),
    (2000, "1023"),
])
def test_mapping_node_refuses_a_bad_max_sensor_force_in_one_line(ros_master, value, words):
    if value is not None:
        ros_master.set_param("/max_sensor_force", value)
    node = ros_master.run([str(MAPPING_NODE)], "mapping_node")
    code = node.wait(20)
    out = node.output()
    assert code not in (None, 0), f"mapping_node kept running with /max_sensor_force={value!r}:\n{out}"
    assert "Traceback" not in out, out
    lines = [ln for ln in out.splitlines() if "/max_sensor_force" in ln]
    assert lines, out
    assert words in lines[0], lines[0]
