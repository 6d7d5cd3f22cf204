"""The notebook widgets on a real roscore: live plots at 100 Hz, calibration, the graph of Ex. 15.

The widget side runs in a process of its own (tests/integration/notebook_ros_scripts.py),
as in a kernel: rospy allows one node per process, and each test has its own master.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from hri_teleop.course.widgets.graph import GraphView, draw_graph, read_graph
from hri_teleop.course.widgets.live import lab_topics

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
SCRIPTS = Path(__file__).with_name("notebook_ros_scripts.py")
PYTHON = str(REPO / ".venv" / "bin" / "python")


def _run(master, name, *args):
    return master.run([PYTHON, str(SCRIPTS), *map(str, args)], name)


def _finish(master, proc, out, timeout_s):
    code = proc.wait(timeout_s)
    assert code == 0, f"{proc.argv[2]} exited with {code}: {proc.output()[-1500:]}"
    return json.loads(Path(out).read_text())


def test_four_topics_at_100_hz_arrive_complete_and_in_order_while_the_plot_redraws(ros_master, tmp_path):
    count = 500  # 5 s at 100 Hz on each of the lab's four topics
    out = tmp_path / "live.json"
    # The teleoperation node's start check said the pad refuses rumble (latched): the plot shows it in red.
    refused = ros_master.run(["rostopic", "pub", "--latch", "/teleoperation/rumble_ok", "std_msgs/Bool", "data: false"],
                             "rumble_ok")
    plot = _run(ros_master, "live-plot", "live-plot", count, out)
    burst = _run(ros_master, "burst", "publish-burst", count, 100)
    result = _finish(ros_master, plot, out, 90)
    burst.stop()
    refused.stop()
    assert "refuses rumble" in result["pad_cue"] and "#b00020" in result["pad_cue"], result["pad_cue"]
    topics = [spec.topic for spec in lab_topics()]
    assert sorted(result["topics"]) == sorted(topics)
    for topic in topics:
        got = result["topics"][topic]
        assert got["received"] == count, f"{topic}: {count - got['received']} of {count} messages dropped"
        assert got["first_column"] == [float(i) for i in range(count)], f"{topic}: messages out of order"
    # Redrawn while the messages arrived, each time with more of them: the kernel's redraws and rospy's threads
    # run side by side (how many redraws fit in the 5 s depends on the machine's speed, not on the plot).
    growing = result["arriving"]
    assert len(set(growing)) >= 2 and growing == sorted(growing), \
        f"the plot did not keep redrawing while the messages arrived: {result['draws']} redraws, {growing}"
    print(f"\nlive plot: 4 x {count} messages at 100 Hz, 0 dropped; {result['draws']} redraws, "
          f"{result['draw_ms_mean']:.0f} ms mean, {result['draw_ms_max']:.0f} ms max")


def test_calibration_sets_the_parameter_and_writes_only_the_value_into_the_launch_file(ros_master, tmp_path):
    launch = tmp_path / "teleoperation.launch"
    original = (REPO / "solutions" / "hri_lab" / "launch" / "teleoperation.launch").read_text()
    launch.write_text(original)
    ros_master.set_param("/max_sensor_force", 700)
    press = _run(ros_master, "press", "publish-press", 688)
    out = tmp_path / "calibrate.json"
    result = _finish(ros_master, _run(ros_master, "calibrate", "calibrate", launch, out), out, 60)
    press.stop()
    assert result["result"] == 688 and result["samples"] >= 150, result
    assert ros_master.get_param("/max_sensor_force") == 688
    assert launch.read_text() == original.replace('name="max_sensor_force" value="700"',
                                                  'name="max_sensor_force" value="688"')
    line = next(n for n, text in enumerate(original.splitlines(), 1) if 'name="max_sensor_force"' in text)
    assert "/max_sensor_force = 688" in result["message"] and f"teleoperation.launch:{line}" in result["message"]


def test_ensure_ros_twice_in_one_process_gives_one_node_on_the_running_master(ros_master, tmp_path):
    out = tmp_path / "twice.json"
    result = _finish(ros_master, _run(ros_master, "twice", "twice", out), out, 60)
    assert result["same"] and not result["started_master"]
    assert result["uri"] == ros_master.uri == result["env_uri"]
    assert result["node"].startswith("/twice_") and result["node"] in result["nodes"]
    assert not [n for n in result["nodes"] if n.startswith("/another_name")]


def test_the_graph_of_the_sensor_launch_has_its_nodes_topics_and_types(ros_master, tmp_path):
    ros_master.roslaunch("hri_lab", "sensor.launch", {"rate_hz": 20})
    ros_master.wait_for(lambda: "/mapping_node" in ros_master.subscribers("/pub_force")
                        and ros_master.publishers("/pub_force") and ros_master.publishers("/force_mapped"), 30,
                        "sensor.launch's nodes")
    graph = read_graph(ros_master.uri)
    assert {"/FSR_sensor", "/mapping_node"} <= set(graph.nodes)
    assert "/rosout" not in graph.nodes and "/rosout" not in graph.topics
    assert graph.topics["/pub_force"] == "std_msgs/Int16"
    assert graph.topics["/force_mapped"] == "std_msgs/Float32"
    assert ("/FSR_sensor", "/pub_force") in graph.publishes
    assert ("/mapping_node", "/pub_force") in graph.subscribes
    assert ("/mapping_node", "/force_mapped") in graph.publishes
    draw_graph(graph, title="sensor.launch").savefig(tmp_path / "graph.png")
    view = GraphView(ros_master.uri, figure="image")
    assert view.graph == graph and "2 nodes, 2 topics" in view.status.value


def test_the_graph_view_without_a_master_says_what_to_start(tmp_path):
    from hri_teleop.ros.master import free_port

    uri = f"http://127.0.0.1:{free_port()}/"
    view = GraphView(uri, figure="image")
    assert view.graph is None and f"no ROS master at {uri}" in view.status.value
