"""The launch files' feedback (Ex. 6-7, Ex. 12-13): the cause of each common mistake, charged in one part.

A <node> whose type= is not the script's file name is told that the element is there and what type=
must name; serial_node's ~port is judged against the port the handout's Ex. 11 and Ex. 12 f) give;
a part that depends on one that failed says "not judged: <cause>" instead of failing again.

Judged on what roslaunch's loader reports, built by hand (no master); the simulation's part on an
observation like the grader's session records.
"""

from __future__ import annotations

import pytest

from hri_teleop.grading.exercises.sensor_launch.judge import PARTS as SENSOR_LAUNCH
from hri_teleop.grading.exercises.sensor_launch.judge import compare_sensor_launch
from hri_teleop.grading.exercises.sensor_launch.session import SensorLaunchObservation
from hri_teleop.grading.exercises.teleoperation_launch.cases import launch_sim_case
from hri_teleop.grading.exercises.teleoperation_launch.judge import (
    HANDOUT_PORT,
    compare_teleop_launch,
    compare_teleop_launch_sim,
)
from hri_teleop.grading.exercises.teleoperation_launch.judge import PARTS as TELEOP_LAUNCH
from hri_teleop.grading.judge.compare_launch import EMPTY_CAUSE
from hri_teleop.grading.run.records import LaunchNode, LaunchParseResult, Message
from hri_teleop.grading.run.workspace import FRANKA_MARKER_PARAM

SENSOR_NODES = [("FSR_sensor", "hri_lab", "FSR_sensor.py"), ("mapping_node", "hri_lab", "mapping_node.py")]
TELEOP_NODES = [("serial_node", "rosserial_python", "serial_node.py"), ("mapping_node", "hri_lab", "mapping_node.py"),
                ("teleoperation", "hri_lab", "teleoperation.py"), ("gripper_manager", "hri_lab", "gripper_manager.py")]
TELEOP_PARAMS = {"/max_sensor_force": 700, "/serial_node/port": "/dev/ttyACM0", FRANKA_MARKER_PARAM: True}


def _launch(nodes, params):
    return LaunchParseResult(ok=True, nodes=[LaunchNode(name=n, namespace="/", package=pkg, type=t) for n, pkg, t in nodes],
                             params=params, files=[])


def _flowing(supplied=()):
    return SensorLaunchObservation(force_mapped=[Message(t / 10, "std_msgs/Float32", 0.5) for t in range(5)],
                                   supplied=list(supplied))


def _with_type(nodes, name, new_type):
    return [(n, pkg, new_type if n == name else t) for n, pkg, t in nodes]


def _sensor(nodes, params=None, observation=None):
    parts = compare_sensor_launch(_launch(nodes, {"/max_sensor_force": 700} if params is None else params),
                                          observation or _flowing())
    return dict(zip(SENSOR_LAUNCH, parts))


def _teleop(nodes, params=TELEOP_PARAMS):
    return dict(zip(TELEOP_LAUNCH, compare_teleop_launch(_launch(nodes, params))))


def _failed(parts):
    return {key: part.message for key, part in parts.items() if not part.passed}


@pytest.mark.parametrize("written, words", [
    ("FSR_sensor", "extension included"),
    ("fsr_sensor.py", "upper and lower case included"),
    ("scripts/FSR_sensor.py", "without its folder"),
])
def test_a_sensor_node_whose_type_is_not_the_files_name_is_told_the_element_is_there_and_what_type_must_name(written,
                                                                                                          words):
    failed = _failed(_sensor(_with_type(SENSOR_NODES, "FSR_sensor", written)))
    assert list(failed) == ["nodes"]
    message = failed["nodes"]
    assert message.startswith(f'FSR_sensor.py: the <node name="FSR_sensor"> is there, but its type="{written}"')
    assert words in message and "start it with a <node> element" not in message


def test_a_teleoperation_node_whose_type_lacks_py_is_told_so_and_the_simulation_is_not_judged_for_it():
    nodes = _with_type(TELEOP_NODES, "teleoperation", "teleoperation")
    failed = _failed(_teleop(nodes))
    assert list(failed) == ["nodes"] and "extension included" in failed["nodes"]
    sim = compare_teleop_launch_sim(_launch(nodes, TELEOP_PARAMS), None, launch_sim_case())
    assert sim.message.startswith("not judged: the file starts no teleoperation.py of hri_lab (the nodes part: "
                                  "teleoperation.py: the <node name=\"teleoperation\"> is there")


def test_a_node_named_for_the_script_that_runs_another_file_is_told_type_names_the_script():
    failed = _failed(_sensor(_with_type(SENSOR_NODES, "mapping_node", "mapping.py")))
    assert failed["nodes"].startswith('mapping_node.py: the <node name="mapping_node"> is there, but its '
                                      'type="mapping.py" names another file')


def test_a_serial_node_whose_type_lacks_py_is_told_so():
    failed = _failed(_teleop(_with_type(TELEOP_NODES, "serial_node", "serial_node")))
    assert list(failed) == ["serial"] and "extension included" in failed["serial"]


def test_a_node_that_is_not_there_at_all_is_told_to_start_it():
    failed = _failed(_sensor(SENSOR_NODES[1:]))
    assert failed["nodes"] == "no node runs FSR_sensor.py of hri_lab: start it with a <node> element (handout Ex. 6)"


@pytest.mark.parametrize("port, passes, words", [
    (HANDOUT_PORT, True, ""),
    ("/dev/ttyUSB0", False, '/serial_node/port is "/dev/ttyUSB0": the Arduino\'s port is the one the handout\'s Ex. 11 '
                            "and Ex. 12 f) give, /dev/ttyACM0"),
    ("/dev/ttyACM1", False, "make it a roslaunch <arg> whose default is the handout's"),
    ("/dev/ttyACMO", False, "(last digit zero)"),
    ("COM3", False, '"COM3"'),
    (0, False, "(int, not a string)"),
])
def test_the_serial_port_is_judged_against_the_handouts(port, passes, words):
    parts = _teleop(TELEOP_NODES, {**TELEOP_PARAMS, "/serial_node/port": port})
    assert _failed(parts) == ({} if passes else {"serial": parts["serial"].message})
    assert words in parts["serial"].message


def test_the_serial_part_label_quotes_only_the_port_the_handout_gives():
    assert TELEOP_LAUNCH["serial"][0] == f"starts rosserial_python's serial_node.py with ~port {HANDOUT_PORT} " \
                                                 "(a string)"


def test_an_empty_launch_file_fails_the_parse_part_only_and_the_rest_is_not_judged():
    empty = _launch([], {})
    for parts in (_sensor([], {}, _flowing(["/max_sensor_force", "FSR_sensor.py", "mapping_node.py"])),
                  _teleop([], {})):
        assert "starts no node and sets no parameter" in parts["parse"].message
        assert all(p.message == f"not judged: {EMPTY_CAUSE}" for key, p in parts.items() if key != "parse")
        assert sum(p.score for p in parts.values()) == 0
    sim = compare_teleop_launch_sim(empty, None, launch_sim_case())
    assert sim.message == f"not judged: {EMPTY_CAUSE}"


@pytest.mark.parametrize("kept, flow_judged", [(0, False), (1, True), (2, True)])
def test_the_flow_is_not_judged_when_the_file_starts_neither_sensor_node(kept, flow_judged):
    supplied = [script for _n, _p, script in SENSOR_NODES[kept:]]
    parts = _sensor(SENSOR_NODES[:kept], observation=_flowing(supplied))
    assert parts["flow"].passed is flow_judged
    assert parts["flow"].message.startswith("not judged: the file starts neither node (the nodes part)") is not flow_judged


@pytest.mark.parametrize("package, passes", [("hri_lab", True), ("ros_intro", True), ("beginner_tutorials", False)])
def test_a_sensor_script_from_another_package_is_charged_in_the_nodes_part_only(package, passes):
    nodes = [(n, package if n == "FSR_sensor" else p, t) for n, p, t in SENSOR_NODES]
    failed = _failed(_sensor(nodes, observation=_flowing([] if passes else ["FSR_sensor.py"])))
    assert failed == ({} if passes else {"nodes": "FSR_sensor.py is started from package 'beginner_tutorials'; at "
                                                  "home and in the lab it is in hri_lab"})


@pytest.mark.parametrize("nodes, params, key", [
    (_with_type(TELEOP_NODES, "gripper_manager", "gripper_manager"), TELEOP_PARAMS, "nodes"),
    ([n for n in TELEOP_NODES if n[0] != "mapping_node"], TELEOP_PARAMS, "nodes"),
    (TELEOP_NODES, {**TELEOP_PARAMS, "/serial_node/port": "/dev/ttyUSB0"}, "serial"),
    (TELEOP_NODES, {k: v for k, v in TELEOP_PARAMS.items() if k != "/max_sensor_force"}, "param"),
    (TELEOP_NODES, {k: v for k, v in TELEOP_PARAMS.items() if k != FRANKA_MARKER_PARAM}, "include"),
])
def test_one_teleoperation_launch_mistake_fails_one_part(nodes, params, key):
    assert list(_failed(_teleop(nodes, params))) == [key]


@pytest.mark.parametrize("value, words", [("650", 'write value="650" without type="str"'),
                                          ("seven hundred", 'write value="<the count>" without type="str"')])
def test_a_max_sensor_force_written_as_text_is_told_to_drop_the_type_with_the_students_own_count(value, words):
    failed = _failed(_teleop(TELEOP_NODES, {**TELEOP_PARAMS, "/max_sensor_force": value}))
    assert list(failed) == ["param"] and words in failed["param"] and "700" not in failed["param"]
