"""The pipeline's start, without ROS: when its graph has settled, and how a node that ended is told."""

from __future__ import annotations

from pathlib import Path

from hri_teleop.course.pipeline_start import crash_lines, settled, template_exercise, without_terminal_titles

WIRED = [
    [["/pub_force", ["/FSR_sensor"]], ["/force_mapped", ["/mapping_node"]], ["/gripper_width", ["/teleoperation"]]],
    [["/pub_force", ["/mapping_node"]], ["/force_mapped", ["/teleoperation"]], ["/gripper_width", ["/gripper_manager"]]],
    [],
]


def test_the_graph_is_settled_only_with_every_registration_of_the_labs_nodes():
    assert settled(WIRED)
    without_gripper_manager = [WIRED[0], WIRED[1][:2], []]
    assert not settled(without_gripper_manager)


def test_a_students_node_counts_once_it_has_a_publisher_and_a_subscriber_whatever_their_topics():
    elsewhere = [[["/pub_force", ["/FSR_sensor"]], ["/force", ["/mapping_node"]], ["/gripper_width", ["/teleoperation"]]],
                 [["/pub_force", ["/mapping_node"]], ["/force_mapped", ["/teleoperation"]],
                  ["/gripper_width", ["/gripper_manager"]]], []]
    assert settled(elsewhere, ["/mapping_node", "/teleoperation"])
    only_subscribed = [[["/pub_force", ["/FSR_sensor"]], ["/gripper_width", ["/teleoperation"]]], WIRED[1], []]
    assert not settled(only_subscribed, ["/mapping_node", "/teleoperation"])


def test_terminal_title_escapes_are_removed_and_colours_kept():
    text = "\x1b]2;sensor.launch http://127.0.0.1:40000\x07started\n\x1b[33mwarning\x1b[0m"
    assert without_terminal_titles(text) == "started\n\x1b[33mwarning\x1b[0m"


OUTPUT = """[INFO] [1.0]: started
Traceback (most recent call last):
  File "/home/s/lab/hri_lab/scripts/teleoperation.py", line 7, in <module>
    main()
  File "/home/s/lab/hri_lab/scripts/teleoperation.py", line 5, in main
    raise NotImplementedError()
NotImplementedError
"""


def test_the_crash_lines_are_the_nodes_own_frames_and_the_exception(tmp_path):
    lines = crash_lines(OUTPUT, Path("teleoperation.py"))
    assert lines == ['  File "teleoperation.py", line 7, in <module>', "    main()",
                     '  File "teleoperation.py", line 5, in main', "    raise NotImplementedError()",
                     "NotImplementedError"]


def test_a_template_names_the_exercise_its_unfinished_part_belongs_to(tmp_path):
    script = tmp_path / "teleoperation.py"
    script.write_text("def main():\n    # Ex. 9: initialise the node\n    # YOUR CODE HERE\n    raise NotImplementedError()\n"
                      "\nmain()\n")
    assert template_exercise(OUTPUT.replace("line 5", "line 4"), script) == "Ex. 9"
    assert template_exercise(OUTPUT.replace("NotImplementedError\n", "NameError: x\n"), script) is None
    plain = tmp_path / "mapping_node.py"
    plain.write_text("def main():\n    raise NotImplementedError()\n")
    assert template_exercise(OUTPUT.replace("teleoperation.py", "mapping_node.py").replace("line 5", "line 2"),
                             plain) == "Ex. 5"


def test_the_lab_nodes_settle_apart_from_the_students_nodes():
    from hri_teleop.course.pipeline_start import lab_nodes_settled, students_registered

    deaf_teleoperation = [WIRED[0], [WIRED[1][0], WIRED[1][2]], []]  # /teleoperation subscribes nothing
    students = ["/mapping_node", "/teleoperation"]
    assert lab_nodes_settled(deaf_teleoperation, students)
    assert not students_registered(deaf_teleoperation, students)
