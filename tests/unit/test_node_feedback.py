"""The node checks' feedback names the cause (issue 43): a crash as a crash, the template as the template,
a loop off ~rate, a topic used instead; one mistake costs in the part that judges it.

No ROS here: observations are built by hand the way the sessions report them
(tests/grading/test_node_feedback_runs.py runs the same mistakes for real).
"""

from __future__ import annotations

import dataclasses

import pytest

from hri_teleop.grading.exercises.mapping_node.cases import hidden_mapping_cases, public_mapping_case
from hri_teleop.grading.exercises.mapping_node.judge import PARTS as MAPPING
from hri_teleop.grading.exercises.mapping_node.judge import compare_mapping
from hri_teleop.grading.exercises.mapping_node.session import MappingNodeObservation, MappingRun
from hri_teleop.grading.exercises.teleoperation.cases import hidden_teleop_node_case
from hri_teleop.grading.exercises.teleoperation.judge_node import (
    RATE_TOLERANCE,
    compare_teleop_node,
    keeps_rate,
    loop_rate_hz,
    real_time_note,
)
from hri_teleop.grading.exercises.teleoperation.parts import PARTS as TELEOP
from hri_teleop.grading.exercises.teleoperation.session import TeleopNodeObservation
from hri_teleop.grading.judge.tracebacks import crash_text, find_crash, is_template
from hri_teleop.grading.run.records import Message, NodeFacts, Response, Topic

PACKAGE = "/tmp/hri-grade-mapping-node-abc/ws/hri_lab"

CALLBACK_CRASH = f"""[ERROR] [1795940281.184588]: bad callback: <bound method MappingNode.callback of <__main__.MappingNode object at 0x7f4>>
Traceback (most recent call last):
  File "/usr/lib/python3/dist-packages/rospy/topics.py", line 750, in _invoke_callback
    cb(msg)
  File "{PACKAGE}/scripts/mapping_node.py", line 35, in callback
    self.publisher.publish(Float64(self.map_force(msg.data)))
                           ^^^^^^^
NameError: name 'Float64' is not defined

"""

START_CRASH = f"""Traceback (most recent call last):
  File "{PACKAGE}/scripts/mapping_node.py", line 39, in <module>
    MappingNode()
  File "{PACKAGE}/scripts/mapping_node.py", line 22, in __init__
    self.max_sensor_force = rospy.get_param("/max_force")
  File "/opt/ros/noetic/lib/python3/dist-packages/rospy/client.py", line 467, in get_param
    return _param_server[param_name] #MasterProxy does all the magic for us
  File "/opt/ros/noetic/lib/python3/dist-packages/rospy/msproxy.py", line 123, in __getitem__
    raise KeyError(key)
KeyError: '/max_force'
"""


def _failed(parts):
    return {p.name: p.message for p in parts if not p.passed}


def _score(parts):
    return sum(p.score for p in parts)


# -- tracebacks ---------------------------------------------------------------------------------

def test_a_callback_crash_shows_the_students_frame_relative_to_the_package_and_the_error_line():
    crash = find_crash("earlier output\n" + CALLBACK_CRASH, PACKAGE)
    assert crash is not None and crash.callback == "MappingNode.callback"
    text = crash_text(crash, "mapping_node.py")
    assert "scripts/mapping_node.py, line 35, in callback" in text
    assert "self.publisher.publish(Float64(self.map_force(msg.data)))" in text
    assert text.splitlines()[-1].strip() == "NameError: name 'Float64' is not defined"
    assert "/tmp/" not in text and "rospy/topics.py" not in text and "^^^" not in text


def test_a_crash_keeps_only_the_students_frames_and_finds_them_without_the_package_path():
    crash = find_crash(START_CRASH, "")  # the workspace's layout names the package when no path is given
    assert crash is not None and not crash.callback
    assert [(f.file, f.line, f.function) for f in crash.frames] == [
        ("scripts/mapping_node.py", 39, "<module>"), ("scripts/mapping_node.py", 22, "__init__")]
    assert crash.error == "KeyError: '/max_force'"
    assert "rospy.get_param(\"/max_force\")" in crash_text(crash, "mapping_node.py")


def test_only_the_last_three_of_the_students_frames_are_shown():
    frames = "".join(f'  File "{PACKAGE}/scripts/deep.py", line {n}, in f{n}\n    f{n + 1}()\n' for n in range(1, 6))
    text = crash_text(find_crash(f"Traceback (most recent call last):\n{frames}RecursionError: deep\n", PACKAGE), "x")
    assert "line 3, in f3" in text and "line 5, in f5" in text and "line 2, in f2" not in text


@pytest.mark.parametrize("output", [
    "",
    "[INFO] all fine\n",
    "Traceback (most recent call last):\n  File \"/x/ws/hri_lab/scripts/a.py\", line 1, in <module>\n",  # cut short
])
def test_output_without_a_whole_traceback_is_no_crash(output):
    assert find_crash(output, PACKAGE) is None


def test_an_error_raised_outside_the_students_files_says_so():
    text = crash_text(find_crash('Traceback (most recent call last):\n  File "/usr/lib/x.py", line 1, in f\n'
                                 "    g()\nValueError: bad\n", PACKAGE), "mapping_node.py")
    assert "outside your files" in text and "ValueError: bad" in text


def test_a_template_part_left_unfilled_is_named():
    crash = find_crash(f'Traceback (most recent call last):\n  File "{PACKAGE}/scripts/m.py", line 24, in __init__\n'
                       "    raise NotImplementedError()\nNotImplementedError\n", PACKAGE)
    assert crash.unfilled and "YOUR CODE HERE" in crash_text(crash, "m.py")


HOLE = "    # YOUR CODE HERE\n    raise NotImplementedError()\n"


@pytest.mark.parametrize("holes, template_holes, expected", [
    (3, 3, True), (2, 3, False), (4, 3, True), (0, 0, False), (1, 0, False)])
def test_a_file_is_the_template_when_it_keeps_every_unfilled_part_of_it(holes, template_holes, expected):
    assert is_template("def f():\n" + HOLE * holes, "def f():\n" + HOLE * template_holes) is expected


# -- mapping_node.py -------------------------------------------------------------------------------

def _cases():
    return [public_mapping_case()] + hidden_mapping_cases(3)


def _run(case, outputs, in_type="std_msgs/Int16", connected=True, tail="", exited=False):
    return MappingRun(label=case.label, max_sensor_force=case.max_sensor_force, counts=list(case.counts),
                      input_topic="/pub_force", input_type=in_type, output_topic="/force_mapped",
                      output_type="std_msgs/Float32", connected=connected,
                      responses=[[Response("std_msgs/Float32", v)] if v is not None else [] for v in outputs],
                      node=NodeFacts(started=True, subscriptions=[Topic("/pub_force", in_type)],
                                     publications=[Topic("/force_mapped", "std_msgs/Float32")], output_tail=tail,
                                     exited_by_itself=exited, exit_code=1 if exited else None))


def test_a_callback_that_crashes_fails_the_publish_part_with_its_traceback_and_the_values_are_not_judged():
    cases = _cases()
    run = _run(cases[0], [None] * len(cases[0].counts), tail=CALLBACK_CRASH * 3)
    parts = compare_mapping(MappingNodeObservation(runs=[run]), cases, package_dir=PACKAGE)
    failed = _failed(parts)
    assert list(failed) == [MAPPING[k][0] for k in ("pub", "values", "clip", "hidden")]
    assert "scripts/mapping_node.py, line 35" in failed[MAPPING["pub"][0]]
    assert "NameError: name 'Float64' is not defined" in failed[MAPPING["pub"][0]]
    assert "publish the mapped value" not in failed[MAPPING["pub"][0]]  # no advice about the symptom
    for key in ("values", "clip", "hidden"):
        assert failed[MAPPING[key][0]] == "not judged: the node crashed (see above)"


def test_a_node_that_crashes_before_it_subscribes_shows_its_traceback_and_nothing_else_is_judged():
    cases = _cases()
    run = dataclasses.replace(_run(cases[0], [], tail=START_CRASH, exited=True), input_topic="", input_type="")
    parts = compare_mapping(MappingNodeObservation(runs=[run]), cases, package_dir=PACKAGE)
    assert "scripts/mapping_node.py, line 22, in __init__" in parts[0].message and "KeyError" in parts[0].message
    assert all(p.message == "not judged: the node crashed (see above)" for p in parts[1:])


def test_the_template_left_in_place_is_named_as_the_template():
    cases = _cases()
    tail = (f'Traceback (most recent call last):\n  File "{PACKAGE}/scripts/mapping_node.py", line 24, in __init__\n'
            "    raise NotImplementedError()\nNotImplementedError\n")
    run = dataclasses.replace(_run(cases[0], [], tail=tail, exited=True), input_topic="", input_type="")
    parts = compare_mapping(MappingNodeObservation(runs=[run]), cases, package_dir=PACKAGE, template=True)
    assert "template as handed out" in parts[0].message and "Ex. 12 d)" in parts[0].message
    assert all("not judged: the node is the template" in p.message for p in parts[1:])


def test_a_subscriber_of_another_type_costs_its_part_only_and_the_type_to_use_is_not_named():
    cases = _cases()
    runs = [_run(c, c.expected, in_type="std_msgs/Float32") for c in cases]
    parts = compare_mapping(MappingNodeObservation(runs=runs), cases)
    failed = _failed(parts)
    assert list(failed) == [MAPPING["sub"][0]] and _score(parts) == 20 - MAPPING["sub"][1]
    message = failed[MAPPING["sub"][0]]
    assert "std_msgs/Float32" in message and "rostopic type /pub_force" in message and "rostopic info" in message
    assert "Int16" not in message and "Int16" not in MAPPING["sub"][0]


def test_a_subscriber_type_the_counts_cannot_be_sent_in_costs_its_part_and_the_rest_is_not_judged():
    cases = _cases()
    run = _run(cases[0], [], in_type="std_msgs/String", connected=False)
    parts = compare_mapping(MappingNodeObservation(runs=[run]), cases)
    assert not parts[0].passed and "Int16" not in parts[0].message
    assert all(p.message.startswith("not judged: the grader cannot send counts as std_msgs/String") for p in parts[1:])


def _unclipped(case):
    return [c / case.max_sensor_force for c in case.counts]


def _integer_division(case):
    return [min(1.0, float(c // case.max_sensor_force)) for c in case.counts]


def test_no_clip_costs_the_clip_part_only_and_the_hidden_inputs_judge_the_counts_up_to_the_maximum():
    cases = _cases()
    parts = compare_mapping(MappingNodeObservation(runs=[_run(c, _unclipped(c)) for c in cases]), cases)
    assert list(_failed(parts)) == [MAPPING["clip"][0]] and _score(parts) == 20 - MAPPING["clip"][1]
    hidden = parts[-1]
    assert hidden.passed and "counts above /max_sensor_force left out" in hidden.note


def test_integer_division_costs_the_values_part_only_and_the_hidden_inputs_judge_the_counts_above_it():
    cases = _cases()
    parts = compare_mapping(MappingNodeObservation(runs=[_run(c, _integer_division(c)) for c in cases]), cases)
    assert list(_failed(parts)) == [MAPPING["values"][0]] and _score(parts) == 20 - MAPPING["values"][1]
    assert "counts up to /max_sensor_force left out" in parts[-1].note


def test_hidden_inputs_are_not_judged_when_the_public_values_and_clip_are_both_wrong():
    cases = _cases()
    runs = [_run(c, [0.5] * len(c.counts)) for c in cases]
    hidden = compare_mapping(MappingNodeObservation(runs=runs), cases)[-1]
    assert hidden.message.startswith("not judged: the values of the public trace are wrong")


def test_clipping_at_a_written_700_still_fails_the_hidden_inputs_when_the_public_trace_clips_right():
    cases = _cases()
    runs = [_run(c, [min(c_ / c.max_sensor_force, 700 / c.max_sensor_force) if c.max_sensor_force < 700
                     else min(1.0, c_ / c.max_sensor_force) for c_ in c.counts]) for c in cases]
    parts = compare_mapping(MappingNodeObservation(runs=runs), cases)
    low = [c for c in cases[1:] if c.max_sensor_force < 700]
    assert low, "the hidden cases have a /max_sensor_force below 700"
    assert list(_failed(parts)) == [MAPPING["hidden"][0]] and not parts[-1].note


# -- teleoperation.py as a node ------------------------------------------------------------------------

def _messages(rate_hz, n=40, start=0.0):
    return [Message(round(start + i / rate_hz, 4), "geometry_msgs/Twist", [0.0] * 6) for i in range(n)]


@pytest.mark.parametrize("factor, keeps", [(1.0, True), (1 - RATE_TOLERANCE + 0.001, True),
                                           (1 - RATE_TOLERANCE - 0.001, False), (1 + RATE_TOLERANCE - 0.001, True),
                                           (1 + RATE_TOLERANCE + 0.001, False), (0.1, False)])
def test_a_loop_keeps_rate_within_the_tolerance_and_not_beyond(factor, keeps):
    assert keeps_rate(100.0 * factor, 100.0) is keeps


def test_the_loop_rate_counts_each_instant_once_and_needs_ten_of_them():
    doubled = sorted(_messages(50.0) + _messages(50.0))  # two messages per tick: one instant each
    assert loop_rate_hz(doubled) == pytest.approx(50.0, rel=1e-3)
    assert loop_rate_hz(_messages(50.0, n=10)) == pytest.approx(50.0, rel=1e-3)
    assert loop_rate_hz(_messages(50.0, n=9)) is None and keeps_rate(None, 50.0)


def _teleop_observation(case, twist_rate_hz, twist_topic="/cartesian_velocity_controller/cmd_vel",
                        width_topic="/gripper_width", clock="grader"):
    pubs = [Topic(twist_topic, "geometry_msgs/Twist"), Topic(width_topic, "std_msgs/Float32"),
            Topic("/teleoperation/rumble", "std_msgs/Float32")]
    n = int(case.quit_s * twist_rate_hz)
    widths = [Message(m.t_s, "std_msgs/Float32", 0.08) for m in _messages(twist_rate_hz, n)]
    rumbles = [Message(m.t_s, "std_msgs/Float32", case.rumble) for m in _messages(twist_rate_hz, n)]
    return TeleopNodeObservation(
        clock=clock, quit_in_time=True, exit_code=0,
        node=NodeFacts(started=True, exited_by_itself=True, exit_code=0, publications=pubs,
                       subscriptions=[Topic("/force_mapped", "std_msgs/Float32")]),
        messages={twist_topic: _messages(twist_rate_hz, n), width_topic: widths, "/teleoperation/rumble": rumbles})


def test_a_loop_off_rate_fails_the_width_part_naming_rate_and_the_parts_it_explains_are_not_judged():
    case = hidden_teleop_node_case(7)
    parts = compare_teleop_node(_teleop_observation(case, 10.0), case)
    failed = _failed(parts)
    width = failed[TELEOP["node_width"][0]]
    assert "~rate" in width and f"{case.gains.rate:g} Hz" in width and "10 twists per second" in width
    assert failed[TELEOP["node_twist"][0]] == "not judged: the loop does not keep ~rate (see the gripper width part)"
    note = real_time_note(_teleop_observation(case, 10.0, clock="real time"), case)
    assert "did not keep ~rate" in note and "time.sleep" not in note


def test_a_loop_at_rate_is_not_told_about_rate_and_the_real_time_note_names_what_the_run_shows():
    case = hidden_teleop_node_case(7)
    parts = compare_teleop_node(_teleop_observation(case, case.gains.rate), case)
    assert not any("~rate" in p.message for p in parts)
    note = real_time_note(_teleop_observation(case, case.gains.rate, clock="real time"), case)
    assert "every tick" in note and "time.sleep" not in note


def test_a_gripper_width_on_another_topic_is_named_and_the_rumble_topic_is_never_taken_for_it():
    case = hidden_teleop_node_case(7)
    named = _failed(compare_teleop_node(_teleop_observation(case, case.gains.rate, width_topic="/gripper"), case))
    assert "the gripper width goes to /gripper" in named[TELEOP["node_width_topic"][0]]
    observation = _teleop_observation(case, case.gains.rate)
    observation = dataclasses.replace(observation, node=dataclasses.replace(
        observation.node, publications=[p for p in observation.node.publications if p.name != "/gripper_width"]))
    failed = _failed(compare_teleop_node(observation, case))
    assert "nothing publishes /gripper_width" in failed[TELEOP["node_width_topic"][0]]
    assert failed[TELEOP["node_width"][0]] == "not judged: no gripper width was recorded"


def test_a_teleoperation_node_that_crashes_shows_its_traceback_once():
    case = hidden_teleop_node_case(7)
    observation = _teleop_observation(case, case.gains.rate)
    tail = (f'Traceback (most recent call last):\n  File "{PACKAGE}/scripts/teleoperation.py", line 150, in publish\n'
            "    self.twist_pub.publish(twist)\nAttributeError: 'Teleoperation' object has no attribute 'twist_pub'\n")
    observation = dataclasses.replace(observation, quit_in_time=True, exit_code=1, messages={},
                                      node=dataclasses.replace(observation.node, output_tail=tail, exit_code=1))
    failed = _failed(compare_teleop_node(observation, case, package_dir=PACKAGE))
    crashes = [m for m in failed.values() if "scripts/teleoperation.py, line 150, in publish" in m]
    assert len(crashes) == 1 and "AttributeError" in crashes[0]
    assert all(m.startswith("not judged") for m in failed.values() if m not in crashes)


def test_a_process_last_output_names_the_students_files_from_their_package_not_the_graders_folder():
    from hri_teleop.grading.judge.compare_common import explain_process

    facts = NodeFacts(exit_code=1, output_tail=f'  File "{PACKAGE}/scripts/mapping_node.py", line 39, in <module>\n'
                                                "SystemExit: 3\n")
    message = explain_process(facts, "mapping_node.py")
    assert 'File "scripts/mapping_node.py", line 39' in message and "/tmp/" not in message


def test_a_callback_that_crashes_for_some_counts_shows_the_crash_where_the_answers_are_missing():
    cases = _cases()
    outputs = [None if c > cases[0].max_sensor_force else e for c, e in zip(cases[0].counts, cases[0].expected)]
    tail = CALLBACK_CRASH.replace("NameError: name 'Float64' is not defined", "ValueError: count above the maximum")
    runs = [_run(cases[0], outputs, tail=tail)] + [_run(c, c.expected) for c in cases[1:]]
    failed = _failed(compare_mapping(MappingNodeObservation(runs=runs), cases, package_dir=PACKAGE))
    clip = failed[MAPPING["clip"][0]]
    assert "got no message back" in clip and "ValueError: count above the maximum" in clip
    assert "publish one message for every count" not in clip and MAPPING["values"][0] not in failed


def test_a_teleoperation_node_that_crashes_at_start_shows_its_traceback_and_nothing_else_is_judged():
    case = hidden_teleop_node_case(7)
    tail = (f'Traceback (most recent call last):\n  File "{PACKAGE}/scripts/teleoperation.py", line 250, in main\n'
            "    rospy.init_node(teleoperation)\nNameError: name 'teleoperation' is not defined\n")
    observation = TeleopNodeObservation(problem="exited with status 1 before advertising a topic", node=NodeFacts(
        started=False, exited_by_itself=True, exit_code=1, output_tail=tail))
    parts = compare_teleop_node(observation, case, package_dir=PACKAGE)
    assert "scripts/teleoperation.py, line 250, in main" in parts[0].message
    assert all(p.message == "not judged: the node crashed (see above)" for p in parts[1:])


def test_a_force_callback_that_crashes_is_shown_in_the_rumble_part():
    case = hidden_teleop_node_case(7)
    observation = _teleop_observation(case, case.gains.rate)
    tail = ("[ERROR] [1.0]: bad callback: <bound method Teleoperation.on_force of <__main__.Teleoperation object>>\n"
            f'Traceback (most recent call last):\n  File "{PACKAGE}/scripts/teleoperation.py", line 160, in on_force\n'
            "    self.force = msg.value\nAttributeError: 'Float32' object has no attribute 'value'\n")
    messages = dict(observation.messages)
    messages["/teleoperation/rumble"] = [Message(m.t_s, m.kind, 0.0) for m in messages["/teleoperation/rumble"]]
    observation = dataclasses.replace(observation, messages=messages,
                                      node=dataclasses.replace(observation.node, output_tail=tail))
    failed = _failed(compare_teleop_node(observation, case, package_dir=PACKAGE))
    rumble = failed[TELEOP["node_rumble"][0]]
    assert "Teleoperation.on_force()" in rumble and "line 160, in on_force" in rumble and "AttributeError" in rumble


def test_a_node_that_takes_no_connection_is_not_said_to_be_ended_by_the_signal_the_grader_sent():
    cases = _cases()
    run = _run(cases[0], [], connected=False)
    run = dataclasses.replace(run, node=dataclasses.replace(run.node, exit_code=-2))
    failed = _failed(compare_mapping(MappingNodeObservation(runs=[run]), cases))
    message = failed[MAPPING["pub"][0]]
    assert "took no connection" in message and "SIGINT" not in message
    ended = dataclasses.replace(run, node=dataclasses.replace(run.node, exit_code=3, exited_by_itself=True))
    assert "status 3" in _failed(compare_mapping(MappingNodeObservation(runs=[ended]), cases))[MAPPING["pub"][0]]


@pytest.mark.parametrize("subs, fed, words", [
    ([Topic("/force_mapped", "std_msgs/Float64")], [Topic("/force_mapped", "std_msgs/Float64")],
     "subscribes /force_mapped as std_msgs/Float64"),
    ([Topic("/force_maped", "std_msgs/Float32")], [Topic("/force_maped", "std_msgs/Float32")],
     "subscribes /force_maped, not /force_mapped"),
])
def test_a_force_subscriber_of_another_type_or_topic_costs_the_start_part_only(subs, fed, words):
    case = hidden_teleop_node_case(7)
    observation = _teleop_observation(case, case.gains.rate)
    observation = dataclasses.replace(observation, fed_force=fed,
                                      node=dataclasses.replace(observation.node, subscriptions=subs))
    failed = _failed(compare_teleop_node(observation, case))
    start = failed[TELEOP["node_start"][0]]
    assert words in start and f"the grader sent the force to {fed[0].name} as {fed[0].type}" in start
    assert TELEOP["node_rumble"][0] not in failed


def test_a_force_subscriber_that_took_no_connection_all_run_fails_the_start_part_and_the_rumble_is_not_judged():
    case = hidden_teleop_node_case(7)
    observation = _teleop_observation(case, case.gains.rate)
    silent = {**observation.messages,
              "/teleoperation/rumble": [Message(m.t_s, m.kind, 0.0) for m in observation.messages["/teleoperation/rumble"]]}
    unconnected = dataclasses.replace(observation, force_connected=False, messages=silent)
    failed = _failed(compare_teleop_node(unconnected, case))
    assert "took no connection" in failed[TELEOP["node_start"][0]] and "Float" not in failed[TELEOP["node_start"][0]]
    assert failed[TELEOP["node_rumble"][0]].startswith("not judged: the node's force subscriber got nothing")
    connected = _failed(compare_teleop_node(dataclasses.replace(observation, messages=silent), case))
    assert TELEOP["node_start"][0] not in connected and "keep the value" in connected[TELEOP["node_rumble"][0]]


def test_a_node_that_ran_too_short_to_tell_is_not_said_to_have_taken_no_connection():
    case = hidden_teleop_node_case(7)
    observation = _teleop_observation(case, case.gains.rate)
    twist = "/cartesian_velocity_controller/cmd_vel"
    short = dataclasses.replace(observation, force_connected=False,
                                messages={**observation.messages, twist: observation.messages[twist][:9]})
    assert not any("took no connection" in m for m in _failed(compare_teleop_node(short, case)).values())


SHUTDOWN = (f'Traceback (most recent call last):\n  File "{PACKAGE}/scripts/mapping_node.py", line 50, in <module>\n'
            "    rate.sleep()\nrospy.exceptions.ROSInterruptException: ROS shutdown request\n")


@pytest.mark.parametrize("output, error", [
    (SHUTDOWN, None),
    (SHUTDOWN.replace("rospy.exceptions.ROSInterruptException: ROS shutdown request", "KeyboardInterrupt"), None),
    (START_CRASH + SHUTDOWN, "KeyError: '/max_force'"),
    (SHUTDOWN + START_CRASH, "KeyError: '/max_force'"),
])
def test_a_shutdown_is_no_crash_and_the_crash_before_it_is_found(output, error):
    crash = find_crash(output, PACKAGE)
    assert (crash.error if crash is not None else None) == error


def test_a_crash_as_the_node_ends_is_shown_in_the_quit_part_only():
    case = hidden_teleop_node_case(7)
    observation = _teleop_observation(case, case.gains.rate)  # twists until square
    tail = (f'Traceback (most recent call last):\n  File "{PACKAGE}/scripts/teleoperation.py", line 230, in stop\n'
            "    self.pad.close()\nAttributeError: 'NoneType' object has no attribute 'close'\n")
    widths = [Message(m.t_s, m.kind, 0.05) for m in observation.messages["/gripper_width"]]
    ended = dataclasses.replace(observation, exit_code=1, messages={**observation.messages, "/gripper_width": widths},
                                node=dataclasses.replace(observation.node, output_tail=tail, exit_code=1))
    failed = _failed(compare_teleop_node(ended, case, package_dir=PACKAGE))
    assert "line 230, in stop" in failed[TELEOP["node_quit"][0]]
    assert "crashed" not in failed[TELEOP["node_width"][0]] and "width should be" in failed[TELEOP["node_width"][0]]
