"""Judging observations (each exercise's judge, robot_params): parts, points, student messages.

No ROS here: the observations are built by hand the way the sessions and probes report them.
"""

from __future__ import annotations

import copy
import dataclasses
from pathlib import Path

import pytest

from hri_teleop.grading.cases.handout import TABLE_1
from hri_teleop.grading.exercises.graph.judge import PARTS as GRAPH
from hri_teleop.grading.exercises.graph.judge import compare_graph
from hri_teleop.grading.exercises.graph.session import LiveGraphObservation
from hri_teleop.grading.exercises.mapping_node.cases import public_mapping_case
from hri_teleop.grading.exercises.mapping_node.judge import PARTS as MAPPING
from hri_teleop.grading.exercises.mapping_node.judge import compare_mapping
from hri_teleop.grading.exercises.mapping_node.session import MappingNodeObservation, MappingRun
from hri_teleop.grading.exercises.robot_params import compare_robot_params
from hri_teleop.grading.exercises.sensor_launch.judge import PARTS as SENSOR_LAUNCH
from hri_teleop.grading.exercises.sensor_launch.judge import compare_sensor_launch
from hri_teleop.grading.exercises.sensor_launch.session import SensorLaunchObservation
from hri_teleop.grading.exercises.teleoperation.cases import public_teleop_parts_case, reference_parts
from hri_teleop.grading.exercises.teleoperation.judge_parts import compare_teleop_parts
from hri_teleop.grading.exercises.teleoperation.parts import PARTS as TELEOP
from hri_teleop.grading.exercises.teleoperation_launch.cases import launch_sim_case
from hri_teleop.grading.exercises.teleoperation_launch.judge import PARTS as TELEOP_LAUNCH
from hri_teleop.grading.exercises.teleoperation_launch.judge import compare_teleop_launch, compare_teleop_launch_sim
from hri_teleop.grading.judge.compare_common import process_hints
from hri_teleop.grading.run.records import (
    LaunchNode,
    LaunchParseResult,
    Message,
    NodeFacts,
    PartsCaseResult,
    PartsTick,
    ProcessFacts,
    Response,
    TeleopLaunchSimObservation,
    TeleopPartsResult,
    Topic,
)
from hri_teleop.grading.run.workspace import FRANKA_MARKER_PARAM


def _failed(parts):
    return {p.name: p.message for p in parts if not p.passed}


# -- robot_params.yaml ----------------------------------------------------------------------

def test_table_1_passes_and_extra_keys_are_fine():
    parts = compare_robot_params({**copy.deepcopy(TABLE_1), "extra": 3})
    assert all(p.passed for p in parts) and sum(p.points for p in parts) == 10


@pytest.mark.parametrize("key, value, words", [
    ("robot_mass", 18, "integer"),
    ("load_gripper", "true", "string"),
    ("robot_number", 1.0, "integer"),
    ("mixed_list", ["text", 1, 1], "mixed_list[1]"),
    ("gains", {"p": 10, "i": 1.0, "d": 5.0}, "gains/p"),
    ("robot_name", "Panda", "FER"),
])
def test_a_wrong_type_or_value_fails_only_its_key_and_says_how_to_write_it(key, value, words):
    params = copy.deepcopy(TABLE_1)
    params[key] = value
    failed = _failed(compare_robot_params(params))
    assert len(failed) == 1
    (name, message), = failed.items()
    assert name.startswith(key) and words in message


def test_a_missing_or_nested_key_is_named():
    params = copy.deepcopy(TABLE_1)
    del params["gains"]
    assert "add the line `gains:" in _failed(compare_robot_params(params))["gains: {p: 10.0, i: 1.0, d: 5.0} (dictionary)"]
    nested = {"robot": copy.deepcopy(TABLE_1)}
    assert all("nested under 'robot'" in m for m in _failed(compare_robot_params(nested)).values())


def test_a_file_that_does_not_load_fails_every_part_with_the_reason_first():
    parts = compare_robot_params(None, "`rosparam load` fails: mapping values are not allowed here")
    assert not any(p.passed for p in parts)
    assert "mapping values" in parts[0].message and "not judged" in parts[1].message


def test_a_file_that_sets_no_parameter_earns_no_point_and_one_key_earns_the_load_point():
    empty = compare_robot_params({})
    assert not any(p.passed for p in empty) and "sets no parameter" in empty[0].message
    one = compare_robot_params({"robot_name": "FER"})
    assert [p.name for p in one if p.passed] == [one[0].name, one[1].name]


# -- mapping_node.py ---------------------------------------------------------------------------

def _run(case, outputs, topic="/force_mapped", kind="std_msgs/Float32", subs=(("/pub_force", "std_msgs/Int16"),)):
    return MappingRun(label=case.label, max_sensor_force=case.max_sensor_force, counts=list(case.counts),
                      input_topic=subs[0][0] if subs else "", input_type=subs[0][1] if subs else "",
                      output_topic=topic, output_type=kind, connected=True,
                      responses=[[Response(kind, v)] if v is not None else [] for v in outputs],
                      node=NodeFacts(started=True, subscriptions=[Topic(*s) for s in subs],
                                     publications=[Topic(topic, kind)], exited_by_itself=False, exit_code=None,
                                     output_tail="", output_bytes=0, problem=""))


def _cases():
    from hri_teleop.grading.exercises.mapping_node.cases import hidden_mapping_cases

    return [public_mapping_case()] + hidden_mapping_cases(3)


def test_the_reference_mapping_gets_full_marks():
    cases = _cases()
    parts = compare_mapping(MappingNodeObservation(runs=[_run(c, c.expected) for c in cases]), cases)
    assert all(p.passed for p in parts) and sum(p.points for p in parts) == 20


def test_a_range_of_700_fails_only_the_hidden_part_and_says_so():
    cases = _cases()
    runs = [_run(c, [min(1.0, x / 700.0) for x in c.counts]) for c in cases]
    failed = _failed(compare_mapping(MappingNodeObservation(runs=runs), cases))
    assert list(failed) == [MAPPING["hidden"][0]]
    assert "0..700" in failed[MAPPING["hidden"][0]] and "rospy.get_param" in failed[MAPPING["hidden"][0]]


def test_missing_and_doubled_messages_are_counted_with_an_example():
    cases = _cases()
    public = _run(cases[0], cases[0].expected)
    public.responses[1] = []
    public.responses[2] = public.responses[2] * 2
    failed = _failed(compare_mapping(MappingNodeObservation(runs=[public] + [_run(c, c.expected)
                                                                                     for c in cases[1:]]), cases))
    message = failed[MAPPING["values"][0]]
    assert "got no message back" in message and "more than one message" in message


def test_a_node_that_never_subscribes_fails_first_and_the_rest_is_not_judged():
    cases = _cases()
    run = _run(cases[0], [], subs=())
    run = dataclasses.replace(run, node=dataclasses.replace(
        run.node, exited_by_itself=True, exit_code=1, output_tail="Traceback...\nKeyError: '/max_force'",
        problem="exited with status 1 before subscribing to a topic"))
    parts = compare_mapping(MappingNodeObservation(runs=[run]), cases)
    assert "KeyError" in parts[0].message and "exited with status 1" in parts[0].message
    assert all(p.message.startswith("not judged") for p in parts[1:])


def test_the_output_limit_and_writes_outside_are_explained():
    facts = ProcessFacts(output_bytes=5 * 1024 * 1024, exit_code=-25,
                         output_tail="OSError: [Errno 30] Read-only file system: '/etc/passwd'")
    hints = " ".join(process_hints(facts))
    assert "output limit" in hints and "/etc/passwd" in hints and "outside its own folder" in hints


@pytest.mark.parametrize("tail,named", [
    ("FileNotFoundError: [Errno 2] No such file or directory: '/home/prof/data.txt'", "/home/prof/data.txt"),
    ("FileNotFoundError: [Errno 2] No such file or directory: 'calibration.yaml'", ""),  # its own folder: no hint
    ("OSError: [Errno 30] Read-only file system: '/usr/x'", ""),  # the write hint says it already
])
def test_a_file_outside_the_folder_that_is_not_there_while_grading_is_explained(tail, named):
    hints = " ".join(process_hints(ProcessFacts(exit_code=1, output_tail=tail)))
    assert (f"{named} is not there while grading" in hints) is bool(named), hints


# -- teleoperation.py: the student's parts ------------------------------------------------------

def _ticks_from_reference(case):
    return [PartsTick(gripper_width=e.gripper_width, rotation_mode=e.rotation_mode,
                      cartesian_velocity=list(e.cartesian_velocity), rumble=e.rumble) for e in reference_parts(case)]


def _parts_result(*cases):
    return TeleopPartsResult(ok=True, cases=list(cases))


def test_reference_parts_pass_and_a_gripper_step_without_rate_is_recognised():
    case = public_teleop_parts_case()
    ticks = _ticks_from_reference(case)
    ok = compare_teleop_parts(_parts_result(PartsCaseResult(case.label, ticks)), [case])
    assert all(p.passed for p in ok)
    bad = []
    width = 0.08
    for tick, t in zip(ticks, case.ticks):
        width += (case.gains.k_gripper if "east" in t.buttons else 0) - (case.gains.k_gripper if "south" in t.buttons else 0)
        width = min(0.08, max(0.0, width))
        bad.append(dataclasses.replace(tick, gripper_width=width))
    failed = _failed(compare_teleop_parts(_parts_result(PartsCaseResult(case.label, bad)), [case]))
    assert list(failed) == [TELEOP["gripper"][0]]
    assert "k_gripper / rate" in failed[TELEOP["gripper"][0]]


def test_a_template_part_left_unfilled_names_the_method():
    case = public_teleop_parts_case()
    ticks = _ticks_from_reference(case)
    result = PartsCaseResult(case.label, ticks, errors={"update_rumble": "NotImplementedError: "},
                             error_ticks={"update_rumble": 0})
    failed = _failed(compare_teleop_parts(_parts_result(result), [case]))
    assert list(failed) == [TELEOP["rumble"][0]]
    assert "update_rumble() raised NotImplementedError" in failed[TELEOP["rumble"][0]]


def test_an_import_failure_fails_the_import_part_and_nothing_is_judged_after_it():
    parts = compare_teleop_parts(TeleopPartsResult(ok=False, error="the file called sys.exit(2) while being "
                                                                           "imported"), [public_teleop_parts_case()])
    assert "sys.exit" in parts[0].message and all("not judged" in p.message for p in parts[1:])


# -- launch files -------------------------------------------------------------------------------

def _launch(nodes, params):
    return LaunchParseResult(ok=True, nodes=[LaunchNode(name=n, namespace="/", package=pkg, type=t) for n, pkg, t in nodes],
                             params=params, files=[])


TELEOP_NODES = [("serial_node", "rosserial_python", "serial_node.py"), ("mapping_node", "hri_lab", "mapping_node.py"),
                ("teleoperation", "hri_lab", "teleoperation.py"), ("gripper_manager", "hri_lab", "gripper_manager.py")]
TELEOP_PARAMS = {"/max_sensor_force": 700, "/serial_node/port": "/dev/ttyACM0", FRANKA_MARKER_PARAM: True}


def test_a_complete_teleoperation_launch_passes():
    assert all(p.passed for p in compare_teleop_launch(_launch(TELEOP_NODES, TELEOP_PARAMS)))


@pytest.mark.parametrize("drop_node, params, key, words", [
    ("gripper_manager", TELEOP_PARAMS, "nodes", "gripper_manager.py"),
    (None, {k: v for k, v in TELEOP_PARAMS.items() if k != "/max_sensor_force"}, "param", "max_sensor_force"),
    (None, {**{k: v for k, v in TELEOP_PARAMS.items() if k != "/max_sensor_force"}, "/mapping_node/max_sensor_force": 700},
     "param", "private"),
    (None, {**TELEOP_PARAMS, "/max_sensor_force": "700"}, "param", "type=\"str\""),
    (None, {k: v for k, v in TELEOP_PARAMS.items() if k != "/serial_node/port"}, "serial", "port"),
    (None, {k: v for k, v in TELEOP_PARAMS.items() if k != FRANKA_MARKER_PARAM}, "include", "franka_control"),
])
def test_each_teleoperation_launch_mistake_fails_its_part_only(drop_node, params, key, words):
    nodes = [n for n in TELEOP_NODES if n[0] != drop_node]
    failed = _failed(compare_teleop_launch(_launch(nodes, params)))
    assert list(failed) == [TELEOP_LAUNCH[key][0]] and words in failed[TELEOP_LAUNCH[key][0]]


def _serial_note(params):
    parts = {p.name: p for p in compare_teleop_launch(_launch(TELEOP_NODES, params))}
    serial = parts[TELEOP_LAUNCH["serial"][0]]
    assert serial.passed and sum(p.points for p in parts.values()) == sum(v[1] for k, v in TELEOP_LAUNCH.items()
                                                                         if k != "sim")
    return serial.note


def test_a_launch_without_publish_period_ms_is_told_the_board_sends_every_300_ms_at_no_cost():
    note = _serial_note(TELEOP_PARAMS)
    assert "every 300 ms, 3.3 Hz" in note and "publish_period_ms to 10 for 100 Hz" in note


def test_a_launch_with_publish_period_ms_10_is_told_the_board_sends_100_hz():
    note = _serial_note({**TELEOP_PARAMS, "/serial_node/publish_period_ms": 10})
    assert note == "the board sends every 10 ms, 100 Hz (serial_node's publish_period_ms)"


def test_another_usable_publish_period_says_its_rate_and_the_labs():
    note = _serial_note({**TELEOP_PARAMS, "/serial_node/publish_period_ms": 20})
    assert "every 20 ms, 50 Hz" in note and "10 ms gives the 100 Hz" in note


@pytest.mark.parametrize("value, words", [
    ("10", "'10' (str)"),      # type="string": rosserial answers with a string the sketch cannot take
    (10.0, "10.0 (float)"),
    (2, "2, which"),            # below the sketch's 5 ms
    (20000, "20000, which"),
])
def test_a_bad_publish_period_ms_is_named_with_the_300_ms_the_board_keeps(value, words):
    note = _serial_note({**TELEOP_PARAMS, "/serial_node/publish_period_ms": value})
    assert words in note and "it sends every 300 ms, 3.3 Hz" in note and "5..10000" in note


def test_the_board_rate_note_follows_the_serial_node_s_own_name():
    nodes = [("arduino", "rosserial_python", "serial_node.py")] + TELEOP_NODES[1:]
    params = {**TELEOP_PARAMS, "/arduino/port": "/dev/ttyACM0", "/arduino/publish_period_ms": 10}
    parts = {p.name: p for p in compare_teleop_launch(_launch(nodes, params))}
    serial = parts[TELEOP_LAUNCH["serial"][0]]
    assert serial.passed and serial.note == "the board sends every 10 ms, 100 Hz (serial_node's publish_period_ms)"


def _sim_observation(**changes):
    """What the grader records when the answer key's teleoperation.launch runs in simulation."""
    twist = "/cartesian_velocity_controller/cmd_vel"
    messages = {
        twist: [[t / 10, "geometry_msgs/Twist", [0.0, 0.0, 0.05 if 36 <= t < 46 else 0.0, 0.0, 0.0, 0.0]]
                for t in range(60)],
        "/lab_sim/ee_pose": [[t / 10, "geometry_msgs/PoseStamped", [0.3, 0.0, 0.03 + 0.005 * max(0, min(t, 46) - 36)]]
                             for t in range(60)],
        "/franka_gripper/joint_states": [[t / 10, "sensor_msgs/JointState", [max(0.025, 0.04 - t * 0.001)] * 2]
                                         for t in range(60)],
        "/gripper_width": [[t / 10, "std_msgs/Float32", 0.05] for t in range(60)],
        "/pub_force": [[t / 10, "std_msgs/Int16", min(700, t * 20)] for t in range(60)],
        "/force_mapped": [[t / 10, "std_msgs/Float32", min(1.0, t * 20 / 700)] for t in range(60)],
        "/teleoperation/rumble": [[t / 10, "std_msgs/Float32", min(1.0, t * 20 / 700)] for t in range(60)],
        "/lab_sim/object": [[5.9, "diagnostic_msgs/DiagnosticStatus", {"name": "sponge", "crushed": "false",
                                                                        "ever_lifted": "true"}]],
    }
    observation = {"supplied": [], "problem": "", "quit_in_time": True,
                   "messages": messages, "teleop_publications": [[twist, "geometry_msgs/Twist"]]}
    for key, value in changes.items():
        if key.startswith("/"):
            messages[key] = value
        else:
            observation[key] = value
    return TeleopLaunchSimObservation(**dict(
        observation, messages={t: _messages(rows) for t, rows in messages.items()},
        teleop_publications=[Topic(*x) for x in observation["teleop_publications"]],
        launch=ProcessFacts(**observation.get("launch", {}))))


def _messages(rows):
    return [Message(*row) for row in rows]


def _sim_part(observation, plot_dir=None):
    return compare_teleop_launch_sim(_launch(TELEOP_NODES, TELEOP_PARAMS), observation, launch_sim_case(),
                                             plot_dir)


def test_a_teleoperation_launch_that_works_in_simulation_passes_and_says_what_happened():
    part = _sim_part(_sim_observation())
    assert part.passed and part.points == TELEOP_LAUNCH["sim"][1]
    assert "rumbled up to 1.00" in part.note and "sponge was lifted" in part.note


@pytest.mark.parametrize("changes, words", [
    ({"/cartesian_velocity_controller/cmd_vel": [], "teleop_publications": [["/cmd_vel", "geometry_msgs/Twist"]]},
     "publishes its twist on /cmd_vel: a <remap>"),
    ({"/lab_sim/ee_pose": [[t / 10, "geometry_msgs/PoseStamped", [0.3, 0.0, 0.03]] for t in range(60)]},
     "the arm rose 0.0 cm"),
    ({"/franka_gripper/joint_states": [[0.0, "sensor_msgs/JointState", [0.04, 0.04]]], "/gripper_width": []},
     "gripper_manager got no /gripper_width"),
    ({"/franka_gripper/joint_states": [[0.0, "sensor_msgs/JointState", [0.04, 0.04]]]}, "is gripper_manager.py started"),
    ({"/pub_force": [], "/force_mapped": []}, "rosserial_python's serial_node.py"),
    ({"/force_mapped": []}, "is mapping_node.py started"),
    ({"/force_mapped": [[0.0, "std_msgs/Float32", 0.1]] * 10}, "stayed below 0.3"),
    ({"/force_mapped": [[0.0, "std_msgs/Float32", 1.4]] * 10}, "outside [0, 1]"),
])
def test_each_broken_link_in_simulation_fails_the_part_naming_it(changes, words, tmp_path):
    part = _sim_part(_sim_observation(**changes), tmp_path)
    assert not part.passed and words in part.message, part.message
    assert part.plots and Path(part.plots[0]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_launch_that_does_not_start_or_could_not_be_run_is_named():
    failed = _sim_part(_sim_observation(problem="exited with status 1 before starting /teleoperation",
                                        launch={"exit_code": 1, "output_tail": "RLException: unused args [x]"}))
    assert not failed.passed and "RLException" in failed.message
    skipped = _sim_part(TeleopLaunchSimObservation(session_error="the grading session did not finish within 120 s"))
    assert not skipped.passed and skipped.message.startswith("not judged: the grader could not run the simulation")
    nothing = compare_teleop_launch_sim(_launch(TELEOP_NODES[:2], TELEOP_PARAMS), None, launch_sim_case())
    assert nothing.message.startswith("not judged") and "no teleoperation.py" in nothing.message


def test_sensor_launch_accepts_the_handouts_ros_intro_package_and_reports_ex_7():
    parsed = _launch([("FSR_sensor", "ros_intro", "FSR_sensor.py"), ("mapping_node", "ros_intro", "mapping_node.py")],
                     {"/max_sensor_force": 700, "/robot_name": "FER"})
    observation = SensorLaunchObservation(force_mapped=_messages([[0.0, "std_msgs/Float32", 0.5]] * 5), supplied=[])
    parts = compare_sensor_launch(parsed, observation)
    assert all(p.passed for p in parts)
    assert "Ex. 7 done" in parts[3].note


def test_sensor_launch_values_outside_0_1_fail_the_flow():
    parsed = _launch([("FSR_sensor", "hri_lab", "FSR_sensor.py"), ("mapping_node", "hri_lab", "mapping_node.py")],
                     {"/max_sensor_force": 700})
    observation = SensorLaunchObservation(force_mapped=_messages([[0.0, "std_msgs/Float32", v] for v in (0.2, 1.46, 0.9)]),
                                          supplied=[])
    failed = _failed(compare_sensor_launch(parsed, observation))
    assert list(failed) == [SENSOR_LAUNCH["flow"][0]] and "outside [0, 1]" in failed[SENSOR_LAUNCH["flow"][0]]


def test_an_empty_launch_file_parses_but_earns_no_point():
    empty = _launch([], {})
    sensor = compare_sensor_launch(empty, SensorLaunchObservation(
        force_mapped=_messages([[0.0, "std_msgs/Float32", 0.5]] * 5),
        supplied=["/max_sensor_force", "FSR_sensor.py", "mapping_node.py"]))
    assert [p.score for p in sensor] == [0] * len(sensor)
    assert "starts no node" in sensor[0].message
    teleop = compare_teleop_launch(empty)
    assert teleop[0].score == 0 and "starts no node" in teleop[0].message
    one_param = compare_sensor_launch(_launch([], {"/max_sensor_force": 700}), None)
    assert one_param[0].passed  # something written: the parse part is earned


@pytest.mark.parametrize("supplied, flow_passes", [
    ([], True), (["FSR_sensor.py"], True), (["mapping_node.py"], True), (["/max_sensor_force"], True),
    (["FSR_sensor.py", "mapping_node.py"], False),
])
def test_the_flow_is_the_launch_files_only_when_it_started_a_node_of_the_pipeline(supplied, flow_passes):
    parsed = _launch([("FSR_sensor", "hri_lab", "FSR_sensor.py")], {"/max_sensor_force": 700})
    observation = SensorLaunchObservation(force_mapped=_messages([[0.0, "std_msgs/Float32", 0.5]] * 5), supplied=supplied)
    flow = compare_sensor_launch(parsed, observation)[-1]
    assert flow.passed is flow_passes
    if not flow_passes:
        assert "neither node" in flow.message


def test_launch_hints_name_the_element_and_exercise_not_the_answer_line():
    parts = compare_teleop_launch(_launch([("x", "hri_lab", "other.py")], {"/other": 1}))
    text = " ".join(p.message for p in parts)
    assert "<node name=" not in text and "<param name=" not in text and "<include file=" not in text
    assert "Ex. 12 e)" in text and "Ex. 13" in text


# -- Ex. 15 -----------------------------------------------------------------------------------------

LIVE = LiveGraphObservation(
    publishers={"/pub_force": ["/FSR_sensor"], "/force_mapped": ["/mapping_node"], "/gripper_width": ["/teleoperation"],
                "/cartesian_velocity_controller/cmd_vel": ["/teleoperation"], "/joy": ["/teleoperation"],
                "/rosout": ["/FSR_sensor", "/mapping_node", "/teleoperation", "/gripper_manager"]},
    subscribers={"/pub_force": ["/mapping_node"], "/force_mapped": ["/teleoperation"],
                 "/gripper_width": ["/gripper_manager"], "/rosout": ["/rosout"]},
    types={"/pub_force": "std_msgs/Int16", "/force_mapped": "std_msgs/Float32", "/gripper_width": "std_msgs/Float32",
           "/cartesian_velocity_controller/cmd_vel": "geometry_msgs/Twist", "/joy": "sensor_msgs/Joy",
           "/rosout": "rosgraph_msgs/Log"},
)
ANSWER = {
    "nodes": ["/serial_node", "/mapping_node", "/teleoperation", "/gripper_manager"],
    "topics": {
        "/pub_force": {"type": "std_msgs/Int16", "publishers": ["/serial_node"], "subscribers": ["/mapping_node"]},
        "/force_mapped": {"type": "std_msgs/Float32", "publishers": ["/mapping_node"], "subscribers": ["/teleoperation"]},
        "/gripper_width": {"type": "std_msgs/Float32", "publishers": ["/teleoperation"], "subscribers": ["/gripper_manager"]},
        "/cartesian_velocity_controller/cmd_vel": {"type": "geometry_msgs/Twist", "publishers": ["/teleoperation"],
                                                   "subscribers": ["/franka_control"]},
    },
}


def test_the_answer_graph_matches_the_live_one_with_serial_node_for_the_simulated_sensor():
    assert all(p.passed for p in compare_graph(ANSWER, LIVE))


@pytest.mark.parametrize("change, key, words", [
    (lambda a: a["nodes"].remove("/gripper_manager"), "nodes", "1 of the pipeline's 4 nodes is not listed"),
    (lambda a: a["nodes"].append("/force_node"), "nodes", "/force_node"),
    (lambda a: a["topics"]["/force_mapped"].update(type="std_msgs/Float64"), "types", "std_msgs/Float64 is not its type"),
    (lambda a: a["topics"]["/gripper_width"].update(subscribers=["/teleoperation"]), "links",
     "1 subscriber missing; /teleoperation does not subscribe it"),
])
def test_graph_mistakes_fail_their_part(change, key, words):
    answer = copy.deepcopy(ANSWER)
    change(answer)
    failed = _failed(compare_graph(answer, LIVE))
    assert list(failed) == [GRAPH[key][0]] and words in failed[GRAPH[key][0]]


def test_an_unreadable_graph_fails_the_format_part_first():
    parts = compare_graph(["not", "a", "mapping"], LIVE)
    assert not parts[0].passed and "nodes:" in parts[0].message


def test_the_grading_clock_is_the_graders_unless_real_time_is_asked_for(monkeypatch):
    from hri_teleop.grading.judge.harness import CLOCK_ENV, grading_clock
    from hri_teleop.grading.results import GradingError

    monkeypatch.delenv(CLOCK_ENV, raising=False)
    assert grading_clock() == "grader"
    monkeypatch.setenv(CLOCK_ENV, "real")
    assert grading_clock() == "real time"
    monkeypatch.setenv(CLOCK_ENV, "sim")
    with pytest.raises(GradingError, match="HRI_GRADE_CLOCK is 'sim'; use grader"):
        grading_clock()
