"""The franka_gripper messages built at run time are the ones franka_ros generates.

The MD5 sums below are franka_gripper's, as found in code generated from franka_ros by
others (rosserial headers for franka_gripper/MoveAction, MoveGoal, MoveActionGoal,
MoveActionResult, GraspAction, GraspGoal, GraspActionGoal, GraspEpsilon, HomingAction,
StopAction), and for the messages with no franka-specific text by identical definitions
in other packages (``bool success / string error`` = 45872d25..., an ActionGoal of an empty
goal = nav_msgs/GetMapActionGoal 4b30be6c..., an ActionFeedback of an empty feedback =
nav_msgs/GetMapActionFeedback aae20e09..., an empty message = md5("")). A ROS 1
connection between two ends is refused unless these agree, so a mismatch here means the
gripper simulation could not talk to gripper_manager.py, or the real gripper could not.
"""

from __future__ import annotations

import io

import pytest

pytest.importorskip("genpy", reason="needs ROS 1's genpy (run 'make setup')")
pytest.importorskip("actionlib_msgs", reason="needs ROS 1's actionlib_msgs (run 'make setup')")

from hri_teleop.ros import franka_gripper_msgs as fgm

RESULT = "45872d25d65c97743cc71afc6d4e884d"          # bool success / string error
EMPTY = "d41d8cd98f00b204e9800998ecf8427e"           # md5 of the empty string
ACTION_RESULT = "89dbc4e75593b525bbbea3a150532ed6"   # Header, GoalStatus, {bool success, string error}
ACTION_FEEDBACK_EMPTY = "aae20e09065c3809e8a8e87c4c8953fd"
ACTION_GOAL_EMPTY = "4b30be6cd12b9e72826df56b481f40e0"
ACTION_EMPTY_GOAL = "f37964fcdec026d9507d088d32b65b38"  # HomingAction == StopAction

EXPECTED_MD5 = {
    "MoveAction": "85e8e11f508e446b706022926779afee",
    "MoveActionGoal": "f8907a1e7bb902f2e4c7db8e1cf3d24f",
    "MoveActionResult": ACTION_RESULT,
    "MoveActionFeedback": ACTION_FEEDBACK_EMPTY,
    "MoveGoal": "d16050a0fe85f1c2cb8347c99678362e",
    "MoveResult": RESULT,
    "MoveFeedback": EMPTY,
    "GraspAction": "6f89449359949eaf1f0fef57b7e0db2a",
    "GraspActionGoal": "7bd1a6e7f94ef15bb6dd05cb170e7909",
    "GraspActionResult": ACTION_RESULT,
    "GraspActionFeedback": ACTION_FEEDBACK_EMPTY,
    "GraspGoal": "627a0f0b10ad0c919fbd62b0b3427e63",
    "GraspResult": RESULT,
    "GraspFeedback": EMPTY,
    "GraspEpsilon": "95b2c5464a6f679bd1dacaf86414f095",
    "HomingAction": ACTION_EMPTY_GOAL,
    "HomingActionGoal": ACTION_GOAL_EMPTY,
    "HomingActionResult": ACTION_RESULT,
    "HomingActionFeedback": ACTION_FEEDBACK_EMPTY,
    "HomingGoal": EMPTY,
    "HomingResult": RESULT,
    "HomingFeedback": EMPTY,
    "StopAction": ACTION_EMPTY_GOAL,
    "StopActionGoal": ACTION_GOAL_EMPTY,
    "StopActionResult": ACTION_RESULT,
    "StopActionFeedback": ACTION_FEEDBACK_EMPTY,
    "StopGoal": EMPTY,
    "StopResult": RESULT,
    "StopFeedback": EMPTY,
}


@pytest.mark.parametrize("name", sorted(EXPECTED_MD5))
def test_md5_sum_and_type_equal_franka_gripper(name):
    cls = getattr(fgm, name)
    assert cls._type == f"franka_gripper/{name}"
    assert cls._md5sum == EXPECTED_MD5[name], f"{name}: definition differs from franka_gripper's"


def test_every_class_is_exported():
    for name in EXPECTED_MD5:
        assert name in fgm.__all__


def test_goal_fields_match_the_franka_hand_interface():
    assert fgm.MoveGoal.__slots__ == ["width", "speed"]
    assert fgm.GraspGoal.__slots__ == ["width", "epsilon", "speed", "force"]
    assert fgm.GraspEpsilon.__slots__ == ["inner", "outer"]
    assert fgm.HomingGoal.__slots__ == [] and fgm.StopGoal.__slots__ == []
    assert fgm.MoveResult.__slots__ == ["success", "error"]
    assert fgm.MoveAction.__slots__ == ["action_goal", "action_result", "action_feedback"]
    assert fgm.MoveActionGoal.__slots__ == ["header", "goal_id", "goal"]
    assert fgm.MoveActionResult.__slots__ == ["header", "status", "result"]


def test_standard_parts_have_the_standard_md5_sums():
    from actionlib_msgs.msg import GoalID, GoalStatus
    from std_msgs.msg import Header

    goal = fgm.MoveActionGoal()
    result = fgm.MoveActionResult()
    assert type(goal.header)._md5sum == Header._md5sum
    assert type(goal.goal_id)._md5sum == GoalID._md5sum
    assert type(result.status)._md5sum == GoalStatus._md5sum


def test_grasp_goal_round_trips_through_serialisation():
    goal = fgm.GraspGoal(width=0.03, epsilon=fgm.GraspEpsilon(inner=0.005, outer=0.004), speed=0.1, force=5.0)
    buff = io.BytesIO()
    goal.serialize(buff)
    assert len(buff.getvalue()) == 5 * 8
    back = fgm.GraspGoal().deserialize(buff.getvalue())
    assert (back.width, back.epsilon.inner, back.epsilon.outer, back.speed, back.force) == (0.03, 0.005, 0.004, 0.1, 5.0)


def test_action_goal_accepts_the_real_header_and_goal_id_actionlib_passes():
    # actionlib's ActionClient builds ActionGoal(header=std_msgs Header, goal_id=actionlib_msgs GoalID).
    import genpy
    from actionlib_msgs.msg import GoalID
    from std_msgs.msg import Header

    msg = fgm.MoveActionGoal(header=Header(seq=3), goal_id=GoalID(stamp=genpy.Time(1, 2), id="g1"),
                             goal=fgm.MoveGoal(width=0.02, speed=0.1))
    buff = io.BytesIO()
    msg.serialize(buff)
    back = fgm.MoveActionGoal().deserialize(buff.getvalue())
    assert back.goal_id.id == "g1" and back.goal.width == 0.02 and back.header.seq == 3


def test_expand_action_follows_genaction():
    texts = fgm.expand_action("Move", fgm.ACTION_DEFINITIONS["Move"])
    autogen = "# ====== DO NOT MODIFY! AUTOGENERATED FROM AN ACTION DEFINITION ======\n"
    assert texts["MoveGoal"] == autogen + "float64 width  # [m]\nfloat64 speed  # [m/s]\n"
    assert texts["MoveResult"] == autogen + "bool success\nstring error\n"
    assert texts["MoveFeedback"] == autogen + "\n"
    assert texts["MoveActionGoal"] == autogen + "\nHeader header\nactionlib_msgs/GoalID goal_id\nMoveGoal goal\n"
    assert set(texts) == {"MoveAction", "MoveActionGoal", "MoveActionResult", "MoveActionFeedback",
                          "MoveGoal", "MoveResult", "MoveFeedback"}


def test_a_definition_without_three_sections_is_refused_in_one_line():
    with pytest.raises(fgm.FrankaGripperMsgsError, match="Bad.action has 2 sections"):
        fgm.expand_action("Bad", "float64 x\n---\nbool ok\n")


def test_source_is_reported():
    assert fgm.SOURCE in ("franka_gripper", "generated")
