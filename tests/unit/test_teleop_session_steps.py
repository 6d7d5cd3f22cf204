"""Which topics each step of the grader's clock waits for in Ex. 9's session: a twist the node sends to a topic
of its own is waited for like the expected one, so a loaded machine drops none of it in the node's
queue_size=1 publisher (a dropped twist made the loop seem slower than ~rate: 50.9 of 60 Hz)."""

from __future__ import annotations

from hri_teleop.grading.exercises.teleoperation.session import stepped_topics

TWIST = "/cartesian_velocity_controller/cmd_vel"
RECORD = [TWIST, "/gripper_width"]


def test_the_expected_topics_heard_at_tick_zero_are_waited_for():
    assert stepped_topics(RECORD, lambda t: True, []) == RECORD


def test_an_expected_topic_the_node_never_published_is_not_waited_for():
    assert stepped_topics(RECORD, lambda t: t == "/gripper_width", []) == ["/gripper_width"]


def test_a_twist_on_the_nodes_own_topic_is_waited_for_after_the_expected_ones():
    assert stepped_topics(RECORD, lambda t: t == "/gripper_width", ["/cmd_vel"]) == ["/gripper_width", "/cmd_vel"]


def test_a_twist_topic_already_recorded_is_waited_for_once():
    assert stepped_topics(RECORD, lambda t: True, [TWIST]) == RECORD


def test_a_node_that_published_nothing_still_has_its_steps_timed_on_the_twist():
    assert stepped_topics(RECORD, lambda t: False, []) == [TWIST]
    assert stepped_topics([], lambda t: False, []) == []
