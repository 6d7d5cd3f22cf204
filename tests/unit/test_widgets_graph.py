"""The computation graph of Ex. 15: from the master's answers to a left-to-right drawing."""

from __future__ import annotations

import pytest

from hri_teleop.course.widgets.graph import draw_graph, graph_from_state, layered_layout, wrap_name

TWIST = "/cartesian_velocity_controller/cmd_vel"
# getSystemState and getTopicTypes as the master answers them while teleoperation.launch runs.
STATE = [
    [["/pub_force", ["/serial_node"]], ["/force_mapped", ["/mapping_node"]],
     ["/gripper_width", ["/teleoperation"]], [TWIST, ["/teleoperation"]],
     ["/rosout", ["/serial_node", "/mapping_node", "/teleoperation", "/gripper_manager", "/hri_notebook_1"]],
     ["/rosout_agg", ["/rosout"]]],
    [["/pub_force", ["/mapping_node", "/hri_notebook_1"]], ["/force_mapped", ["/teleoperation"]],
     ["/gripper_width", ["/gripper_manager"]], [TWIST, ["/franka_control"]], ["/rosout", ["/rosout"]]],
    [["/rosout/get_loggers", ["/rosout"]], ["/idle/get_loggers", ["/idle"]]],
]
TYPES = [["/pub_force", "std_msgs/Int16"], ["/force_mapped", "std_msgs/Float32"],
         ["/gripper_width", "std_msgs/Float32"], [TWIST, "geometry_msgs/Twist"], ["/rosout", "rosgraph_msgs/Log"],
         ["/rosout_agg", "rosgraph_msgs/Log"]]


def _graph(**kwargs):
    return graph_from_state(STATE, TYPES, hide_nodes=["/hri_notebook_1"], **kwargs)


def test_the_pipeline_has_its_nodes_topics_and_types_without_ros_internals():
    graph = _graph()
    assert graph.nodes == ("/franka_control", "/gripper_manager", "/idle", "/mapping_node", "/serial_node",
                           "/teleoperation")
    assert graph.topics == {"/force_mapped": "std_msgs/Float32", "/gripper_width": "std_msgs/Float32",
                            "/pub_force": "std_msgs/Int16", TWIST: "geometry_msgs/Twist"}
    assert ("/serial_node", "/pub_force") in graph.publishes
    assert ("/mapping_node", "/pub_force") in graph.subscribes
    assert all("/hri_notebook_1" not in edge for edge in graph.publishes + graph.subscribes)


def test_ros_internals_show_on_request():
    graph = _graph(show_ros_internals=True)
    assert "/rosout" in graph.nodes and graph.topics["/rosout"] == "rosgraph_msgs/Log"


def test_data_flows_left_to_right_from_the_sensor_to_the_robot():
    position = layered_layout(_graph())
    x = {key: xy[0] for key, xy in position.items()}
    chain = [("node", "/serial_node"), ("topic", "/pub_force"), ("node", "/mapping_node"),
             ("topic", "/force_mapped"), ("node", "/teleoperation"), ("topic", "/gripper_width"),
             ("node", "/gripper_manager")]
    assert [x[key] for key in chain] == [0, 1, 2, 3, 4, 5, 6]
    assert x[("topic", TWIST)] == 5 and x[("node", "/franka_control")] == 6


def test_no_two_vertices_share_a_position_and_a_node_and_topic_may_share_a_name():
    state = [[["/chatter", ["/chatter"]], ["/loop", ["/b"]]], [["/chatter", ["/b"]], ["/loop", ["/chatter"]]], []]
    graph = graph_from_state(state, [])
    position = layered_layout(graph)
    assert ("node", "/chatter") in position and ("topic", "/chatter") in position
    assert len(set(position.values())) == len(position)


def test_a_feedback_loop_is_laid_out_without_hanging():
    state = [[["/a", ["/n1"]], ["/b", ["/n2"]]], [["/a", ["/n2"]], ["/b", ["/n1"]]], []]
    position = layered_layout(graph_from_state(state, []))
    assert sorted(int(x) for x, _ in position.values()) == [0, 1, 2, 3]


def test_long_names_break_before_a_slash():
    assert wrap_name(TWIST, 22) == "/cartesian_velocity_controller\n/cmd_vel"
    assert wrap_name("/pub_force") == "/pub_force"


def test_the_drawing_labels_every_node_and_topic_with_its_type():
    figure = draw_graph(_graph(), title="t")
    texts = [t.get_text() for t in figure.axes[0].texts]
    assert "/mapping_node" in texts
    assert "/pub_force\n[std_msgs/Int16]" in texts
    arrows = [c for c in figure.axes[0].get_children() if type(c).__name__ == "Annotation" and not c.get_text()]
    assert len(arrows) == len(_graph().publishes) + len(_graph().subscribes)


def test_an_empty_graph_says_what_to_start():
    figure = draw_graph(graph_from_state([[], [], []], []))
    assert "no nodes" in figure.axes[0].texts[0].get_text()


@pytest.mark.parametrize("hide", [["/teleoperation"]])
def test_hidden_nodes_take_their_edges_with_them(hide):
    graph = graph_from_state(STATE, TYPES, hide_nodes=hide)
    assert "/teleoperation" not in graph.nodes and "/gripper_width" in graph.topics  # gripper_manager subscribes
