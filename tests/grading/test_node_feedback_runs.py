"""Realistic mistakes in the nodes, graded for real: the feedback names the cause, one mistake costs one place.

Each is a change of the answer key (issue 43): a callback that raises NameError, the template left in
the lab package, a subscriber typed Float32, no clip, rospy.Rate(10), the twist on another topic.
tests/unit/test_node_feedback.py judges the same observations without ROS.
"""

from __future__ import annotations

from pathlib import Path
from typing import Dict

import pytest
from grading_helpers import SOLUTIONS, answer_text, open_folder, write_corpus_entry, write_package

from hri_teleop.grading import feedback_text, grade
from hri_teleop.grading.cases.templates import make_template
from hri_teleop.grading.exercises.mapping_node.judge import PARTS as MAPPING
from hri_teleop.grading.exercises.teleoperation.parts import PARTS as TELEOP

pytestmark = pytest.mark.ros


@pytest.fixture
def folder():
    yield from open_folder("hri-node-feedback-")


def _package(root: Path, name: str, relative: str, old: str, new: str) -> Path:
    text = answer_text(relative)
    assert text.count(old) == 1, f"{old!r} is no longer in the answer key's {relative}: update this test"
    return write_package(root / name, {relative: text.replace(old, new)})


def _messages(result) -> Dict[str, str]:
    return {p.name: p.message for p in result.parts if not p.passed}


def test_a_callback_that_raises_is_shown_as_a_crash_in_the_students_file(folder):
    result = grade("mapping-node", write_corpus_entry("mapping_callback_nameerror", folder), out_dir=folder / "out")
    failed = _messages(result)
    pub = failed[MAPPING["pub"][0]]
    assert "scripts/mapping_node.py, line" in pub and "in callback" in pub, feedback_text([result])
    assert "NameError: name 'Float64' is not defined" in pub
    assert str(folder) not in pub and "/tmp/" not in pub and "published nothing" not in pub
    for key in ("values", "clip", "hidden"):
        assert failed[MAPPING[key][0]] == "not judged: the node crashed (see above)"


def test_the_template_left_in_the_lab_package_is_named_as_the_template(folder):
    template = make_template((SOLUTIONS / "scripts" / "mapping_node.py").read_text(), "python")
    package = write_package(folder / "template", {"scripts/mapping_node.py": template})
    result = grade("mapping-node", package, out_dir=folder / "out")
    first = result.parts[0]
    assert not first.passed and "template as handed out" in first.message and "Ex. 12 d)" in first.message, \
        feedback_text([result])
    assert all(p.message.startswith("not judged: the node is the template") for p in result.parts[1:])


def test_the_template_left_in_the_lab_package_is_named_by_the_launch_check_that_runs_the_labs_in_its_place(folder):
    template = make_template((SOLUTIONS / "scripts" / "mapping_node.py").read_text(), "python")
    files = {name: answer_text(name) for name in ("launch/teleoperation.launch", "scripts/teleoperation.py")}
    package = write_package(folder / "lab", {**files, "scripts/mapping_node.py": template})
    result = grade("teleoperation-launch", package, out_dir=folder / "out")
    assert any("template as handed out" in n and "Ex. 12 d)" in n for n in result.notes), feedback_text([result])
    answer_key = grade("teleoperation-launch", write_package(folder / "key", {
        **files, "scripts/mapping_node.py": answer_text("scripts/mapping_node.py")}), out_dir=folder / "out2")
    assert not any("template" in n for n in answer_key.notes), feedback_text([answer_key])


def test_a_subscriber_typed_float32_costs_its_part_only_and_the_type_is_not_given_away(folder):
    result = grade("mapping-node", write_corpus_entry("mapping_subscriber_float32", folder), out_dir=folder / "out")
    failed = _messages(result)
    assert list(failed) == [MAPPING["sub"][0]], feedback_text([result])
    assert result.score == result.max_score - MAPPING["sub"][1]
    assert "rostopic type /pub_force" in failed[MAPPING["sub"][0]]
    assert "Int16" not in feedback_text([result])


def test_no_clip_costs_the_clip_part_only(folder):
    result = grade("mapping-node", write_corpus_entry("mapping_no_clipping", folder), out_dir=folder / "out")
    assert list(_messages(result)) == [MAPPING["clip"][0]], feedback_text([result])
    assert result.score == result.max_score - MAPPING["clip"][1]


def test_a_loop_at_a_rate_of_its_own_is_told_about_rate_and_no_false_clock_note(folder):
    package = _package(folder, "rate10", "scripts/teleoperation.py", "rate = rospy.Rate(self.rate)",
                       "rate = rospy.Rate(10)")
    result = grade("teleoperation", package, out_dir=folder / "out")
    failed = _messages(result)
    width = failed.get(TELEOP["node_width"][0], "")
    assert "twists per second" in width and "the grader set ~rate to" in width, feedback_text([result])
    assert not any("time.sleep" in n for n in result.notes)
    assert all("~rate" in n for n in result.notes if "real time" in n)


def test_a_twist_on_another_topic_is_named_and_there_is_no_clock_note(folder):
    package = _package(folder, "cmd_vel", "scripts/teleoperation.py",
                       'rospy.Publisher("/cartesian_velocity_controller/cmd_vel"', 'rospy.Publisher("/cmd_vel"')
    result = grade("teleoperation", package, out_dir=folder / "out")
    failed = _messages(result)
    assert list(failed) == [TELEOP["node_twist_topic"][0]], feedback_text([result])
    assert "/cmd_vel" in failed[TELEOP["node_twist_topic"][0]]
    assert not any("clock" in n for n in result.notes)


def test_a_force_subscriber_on_a_misspelt_topic_costs_the_start_part_only(folder):
    package = _package(folder, "force_topic", "scripts/teleoperation.py", 'rospy.Subscriber("/force_mapped", Float32,',
                       'rospy.Subscriber("/force_maped", Float32,')
    result = grade("teleoperation", package, out_dir=folder / "out")
    failed = _messages(result)
    assert list(failed) == [TELEOP["node_start"][0]], feedback_text([result])
    assert "/force_maped, not /force_mapped" in failed[TELEOP["node_start"][0]]


def test_a_force_subscriber_of_another_type_fails_the_start_part_not_the_rumbles_advice(folder):
    text = answer_text("scripts/teleoperation.py")
    for old, new in (("from std_msgs.msg import Float32", "from std_msgs.msg import Float32, Float64"),
                     ('rospy.Subscriber("/force_mapped", Float32,', 'rospy.Subscriber("/force_mapped", Float64,')):
        assert text.count(old) == 1, f"{old!r} is no longer in the answer key's teleoperation.py: update this test"
        text = text.replace(old, new)
    result = grade("teleoperation", write_package(folder / "force_type", {"scripts/teleoperation.py": text}),
                   out_dir=folder / "out")
    failed = _messages(result)
    assert set(failed) == {TELEOP["node_start"][0], TELEOP["node_rumble"][0]}, feedback_text([result])
    assert "took no connection" in failed[TELEOP["node_start"][0]]
    assert failed[TELEOP["node_rumble"][0]].startswith("not judged")
    assert "Float32" not in failed[TELEOP["node_start"][0]]
