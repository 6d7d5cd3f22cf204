"""Ex. 15's feedback names the cause and the command that shows the truth, never the graph it asks for.

The handout's Ex. 15 asks the student to find the pipeline's nodes, topics and message types with
`rosnode list`, `rostopic list`, `rostopic info` and `rostopic type`. The feedback on graph.yaml may say
how many of each are missing and quote back what the student wrote; it must not name a node, topic or
type the student did not write. A graph that lists nothing earns nothing, and one mistake costs in one
part: a part that depends on one that failed says "not judged: <cause>".

Judged here on a live graph built by hand (no master), as the grader's session reports it; the last
test grades a file with ``hri-grade graph`` against the lab's real pipeline.
"""

from __future__ import annotations

import copy
import json
from typing import Any, Dict, List

import pytest
import yaml
from grading_helpers import SOLUTIONS, answer_text, hri_grade

from hri_teleop.grading.exercises.graph import check as graph_check
from hri_teleop.grading.exercises.graph.check import graph_of_running_master
from hri_teleop.grading.exercises.graph.judge import PARTS as GRAPH
from hri_teleop.grading.exercises.graph.judge import SEE_NODES, SEE_TOPICS, compare_graph
from hri_teleop.grading.exercises.graph.session import LiveGraphObservation
from hri_teleop.grading.results import Part

TWIST = "/cartesian_velocity_controller/cmd_vel"
#: The lab's pipeline without hardware, as the grader reads it (the simulated board is /FSR_sensor).
LIVE = LiveGraphObservation(
    publishers={"/pub_force": ["/FSR_sensor"], "/force_mapped": ["/mapping_node"], "/gripper_width": ["/teleoperation"],
                TWIST: ["/teleoperation"], "/joy": ["/teleoperation"], "/teleoperation/rumble": ["/teleoperation"],
                "/franka_gripper/move/goal": ["/gripper_manager"],
                "/rosout": ["/FSR_sensor", "/mapping_node", "/teleoperation", "/gripper_manager"]},
    subscribers={"/pub_force": ["/mapping_node"], "/force_mapped": ["/teleoperation"],
                 "/gripper_width": ["/gripper_manager"], "/rosout": ["/rosout"]},
    types={"/pub_force": "std_msgs/Int16", "/force_mapped": "std_msgs/Float32", "/gripper_width": "std_msgs/Float32",
           TWIST: "geometry_msgs/Twist", "/joy": "sensor_msgs/Joy", "/teleoperation/rumble": "std_msgs/Float32",
           "/franka_gripper/move/goal": "franka_gripper/MoveActionGoal", "/rosout": "rosgraph_msgs/Log"},
)
#: What Ex. 15 asks the student to find: never in feedback unless the student wrote it.
ANSWERS = ["/serial_node", "/FSR_sensor", "/mapping_node", "/teleoperation", "/gripper_manager", "/pub_force",
           "/force_mapped", "/gripper_width", TWIST, "std_msgs/Int16", "std_msgs/Float32", "geometry_msgs/Twist"]


def _key() -> Dict[str, Any]:
    """The answer key's graph.yaml (the lab's node names: /serial_node for the board)."""
    return yaml.safe_load(answer_text("graph.yaml"))


def _judge(answer: Any) -> Dict[str, Part]:
    return {key: part for key, part in zip(GRAPH, compare_graph(answer, LIVE))}


def _rename(answer: Dict[str, Any], old: str, new: str) -> Dict[str, Any]:
    """``answer`` with the node ``old`` written as ``new`` everywhere (nodes and every topic's lists)."""
    answer = copy.deepcopy(answer)
    answer["nodes"] = [new if n == old else n for n in answer["nodes"]]
    for entry in answer["topics"].values():
        for role in ("publishers", "subscribers"):
            entry[role] = [new if n == old else n for n in entry[role]]
    return answer


def _without_node(answer: Dict[str, Any], node: str) -> Dict[str, Any]:
    answer = copy.deepcopy(answer)
    answer["nodes"].remove(node)
    for entry in answer["topics"].values():
        for role in ("publishers", "subscribers"):
            entry[role] = [n for n in entry[role] if n != node]
    return answer


def _changed(path: List[str], value: Any):
    def change(answer: Dict[str, Any]) -> Dict[str, Any]:
        answer = copy.deepcopy(answer)
        target = answer
        for key in path[:-1]:
            target = target[key]
        if value is None:
            del target[path[-1]]
        else:
            target[path[-1]] = value
        return answer
    return change


#: One mistake each: the graph, and the parts it may fail (the others must pass).
MISTAKES = {
    "one made-up node": (lambda a: {"nodes": ["/my_node"], "topics": {}}, {"format", "nodes", "types", "links"}),
    "nothing listed": (lambda a: {"nodes": [], "topics": {}}, {"format", "nodes", "types", "links"}),
    "a node missing everywhere": (lambda a: _without_node(a, "/gripper_manager"), {"nodes", "links"}),
    "a node missing from the list only": (_changed(["nodes"], ["/serial_node", "/mapping_node", "/teleoperation"]),
                                          {"nodes"}),
    "a node misspelt everywhere": (lambda a: _rename(a, "/mapping_node", "/mapping"), {"nodes"}),
    "the script's name for the node": (lambda a: _rename(a, "/mapping_node", "/mapping_node.py"), {"nodes"}),
    "a topic missing": (_changed(["topics", "/gripper_width"], None), {"types", "links"}),
    "a topic misspelt": (lambda a: dict(a, topics={("/force_maped" if k == "/force_mapped" else k): v
                                                   for k, v in a["topics"].items()}), {"types", "links"}),
    "a wrong type": (_changed(["topics", "/force_mapped", "type"], "std_msgs/Float64"), {"types"}),
    "a type without its package": (_changed(["topics", "/pub_force", "type"], "Int16"), {"types"}),
    "no type": (_changed(["topics", "/pub_force", "type"], None), {"types"}),
    "publisher and subscriber swapped": (
        _changed(["topics", "/gripper_width"], {"type": "std_msgs/Float32", "publishers": ["/gripper_manager"],
                                                "subscribers": ["/teleoperation"]}), {"links"}),
    "a subscriber missing": (_changed(["topics", "/force_mapped", "subscribers"], []), {"links"}),
}


@pytest.mark.parametrize("name", sorted(MISTAKES))
def test_graph_feedback_never_names_a_node_topic_or_type_the_student_did_not_write(name):
    change, _fails = MISTAKES[name]
    answer = change(_key())
    text = "\n".join(p.message for p in _judge(answer).values())
    written = json.dumps(answer)
    told = [word for word in ANSWERS if word in text and word not in written]
    assert told == [], f"{name}: the feedback names {told}:\n{text}"


@pytest.mark.parametrize("name", sorted(MISTAKES))
def test_one_graph_mistake_fails_only_its_parts_and_the_parts_that_depend_on_them_say_not_judged(name):
    change, fails = MISTAKES[name]
    parts = _judge(change(_key()))
    failed = {key for key, part in parts.items() if not part.passed}
    assert failed == fails, {k: p.message for k, p in parts.items()}
    charged = [key for key in failed if not parts[key].message.startswith("not judged: ")]
    assert len(charged) <= 2, {k: parts[k].message for k in charged}  # a made-up node alone: format and nodes


def test_the_answer_key_with_the_lab_or_the_home_name_of_the_board_gets_every_point():
    assert all(p.passed for p in _judge(_key()).values())
    home = _rename(_key(), "/serial_node", "/FSR_sensor")
    assert all(p.passed for p in _judge(home).values())


def test_a_graph_with_one_made_up_node_earns_nothing_and_is_told_what_shows_the_truth():
    parts = _judge({"nodes": ["my_node"], "topics": {}})
    assert sum(p.score for p in parts.values()) == 0
    assert "lists no topic" in parts["format"].message and SEE_TOPICS in parts["format"].message
    nodes = parts["nodes"].message
    assert "none of the pipeline's 4 nodes is listed" in nodes and "my_node" in nodes and SEE_NODES in nodes
    assert parts["types"].message == parts["links"].message == "not judged: graph.yaml lists no topic (the format part)"


@pytest.mark.parametrize("nodes, topics, format_passes", [
    ([], {}, False),
    (["/talker"], {}, False),
    ([], {"/chatter": {"type": "std_msgs/String", "publishers": [], "subscribers": []}}, False),
    (["/talker"], {"/chatter": {"type": "std_msgs/String", "publishers": ["/talker"], "subscribers": []}}, True),
])
def test_the_format_point_needs_at_least_one_node_and_one_topic(nodes, topics, format_passes):
    assert _judge({"nodes": nodes, "topics": topics})["format"].passed is format_passes


@pytest.mark.parametrize("graph_yaml", ["[not, a, mapping]", "nodes: /a /b\ntopics: {}", "{}", "topics: [a]"])
def test_a_graph_in_another_shape_fails_the_format_part_and_the_rest_is_not_judged(graph_yaml):
    parts = _judge(yaml.safe_load(graph_yaml))
    assert not parts["format"].passed and "nodes:" in parts["format"].message
    assert all(parts[k].message.startswith("not judged: ") for k in ("nodes", "types", "links"))


@pytest.mark.parametrize("kept, words", [
    (4, ""),
    (3, "1 of the pipeline's 4 nodes is not listed"),
    (2, "2 of the pipeline's 4 nodes are not listed"),
    (1, "3 of the pipeline's 4 nodes are not listed"),
])
def test_the_nodes_part_counts_the_nodes_not_listed(kept, words):
    answer = _key()
    answer["nodes"] = answer["nodes"][:kept]
    part = _judge(answer)["nodes"]
    assert part.passed is (kept == 4)
    assert words in part.message and (not words or SEE_NODES in part.message)


def test_a_node_not_in_the_running_graph_is_quoted_back_as_the_student_wrote_it():
    answer = _key()
    answer["nodes"].append("Mapping Node")
    part = _judge(answer)["nodes"]
    assert not part.passed and "not a node of the running graph: Mapping Node" in part.message
    assert "not listed" not in part.message


def test_a_node_of_the_running_graph_outside_the_pipeline_may_be_listed():
    answer = _key()
    answer["nodes"].append("/rosout")
    assert _judge(answer)["nodes"].passed


@pytest.mark.parametrize("kept, words", [
    (4, ""),
    (3, "1 of the pipeline's 4 topics is not listed"),
    (1, "3 of the pipeline's 4 topics are not listed"),
])
def test_the_types_part_counts_the_topics_not_listed_and_links_wait_for_them(kept, words):
    answer = _key()
    answer["topics"] = dict(list(answer["topics"].items())[:kept])
    parts = _judge(answer)
    assert parts["types"].passed is (kept == 4) and words in parts["types"].message
    if kept == 4:
        assert parts["links"].passed
    else:
        assert parts["links"].message.startswith(f"not judged: the connections of {4 - kept} topic")
        assert "(the types part)" in parts["links"].message


def test_a_wrong_type_is_quoted_back_with_the_command_that_prints_the_right_one():
    answer = _changed(["topics", "/force_mapped", "type"], "std_msgs/Float64")(_key())
    message = _judge(answer)["types"].message
    assert message == ("/force_mapped: std_msgs/Float64 is not its type; `rostopic type /force_mapped` prints it "
                       "(package/Message)")


def test_a_listed_topic_outside_the_pipeline_is_judged_by_its_type_and_a_made_up_one_is_quoted_back():
    answer = _key()
    answer["topics"]["/joy"] = {"type": "sensor_msgs/Joy", "publishers": ["/teleoperation"], "subscribers": []}
    assert _judge(answer)["types"].passed
    answer["topics"]["/joy"]["type"] = "sensor_msgs/Joystick"
    answer["topics"]["/force"] = {"type": "std_msgs/Float32", "publishers": [], "subscribers": []}
    message = _judge(answer)["types"].message
    assert "/joy: sensor_msgs/Joystick is not its type" in message
    assert "not a topic of the running graph: /force" in message


def test_a_swapped_publisher_and_subscriber_is_counted_and_the_students_names_quoted():
    answer = MISTAKES["publisher and subscriber swapped"][0](_key())
    message = _judge(answer)["links"].message
    assert "/gripper_width publishers: 1 publisher missing; /gripper_manager does not publish it" in message
    assert "/gripper_width subscribers: 1 subscriber missing; /teleoperation does not subscribe it" in message
    assert "`rostopic info /gripper_width`" in message


def test_a_node_missing_everywhere_costs_in_the_nodes_part_and_leaves_its_connections_not_judged():
    parts = _judge(_without_node(_key(), "/gripper_manager"))
    assert parts["nodes"].message.startswith("1 of the pipeline's 4 nodes is not listed")
    assert parts["links"].message.startswith("not judged: 1 connection of nodes missing from `nodes` (the nodes part)")


def test_a_made_up_node_the_nodes_part_charged_is_not_charged_again_in_links():
    answer = _key()
    answer["nodes"].append("/force_node")
    answer["topics"]["/force_mapped"]["subscribers"].append("/force_node")
    parts = _judge(answer)
    assert not parts["nodes"].passed and "/force_node" in parts["nodes"].message
    assert parts["links"].passed


def test_a_connection_to_a_node_the_list_does_not_hold_is_charged_in_links():
    answer = _key()
    answer["topics"]["/force_mapped"]["subscribers"].append("/force_node")
    parts = _judge(answer)
    assert parts["nodes"].passed
    assert "/force_mapped subscribers: /force_node does not subscribe it" in parts["links"].message


def test_the_robots_controller_may_be_left_out_of_the_twists_subscribers():
    answer = _key()
    answer["topics"][TWIST]["subscribers"] = []
    assert all(p.passed for p in _judge(answer).values())


def test_the_running_master_graph_error_counts_the_nodes_not_up_without_naming_them(monkeypatch):

    from hri_teleop.grading.results import GradingError

    def master_call(method, *args):
        if method == "getSystemState":
            return [["/pub_force", ["/FSR_sensor"]]], [], []
        return [["/pub_force", "std_msgs/Int16"]]

    monkeypatch.setattr(graph_check, "master_call", master_call)
    with pytest.raises(GradingError) as error:
        graph_of_running_master()  # the bundle's path, here without a master
    message = str(error.value)
    assert "3 of its 4 nodes are not up" in message and "rosnode list" in message
    assert not [name for name in ANSWERS if name in message], message


@pytest.mark.ros
def test_hri_grade_graph_gives_a_made_up_node_no_point_and_names_nothing_of_the_pipeline(tmp_path):
    (tmp_path / "hri_lab").mkdir()
    (tmp_path / "hri_lab" / "graph.yaml").write_text("nodes:\n  - /my_node\ntopics: {}\n")
    proc = hri_grade("graph", str(tmp_path / "hri_lab"), "--json")
    assert proc.returncode in (0, 1), proc.stderr
    result = json.loads(proc.stdout)
    assert result["score"] == 0, proc.stdout
    assert not [name for name in ANSWERS if name in proc.stdout], proc.stdout
    key = hri_grade("graph", str(SOLUTIONS), "--json")
    assert json.loads(key.stdout)["score"] == sum(points for _name, points in GRAPH.values()), key.stdout
