"""The ErrorRecovery messages built at run time are the ones a catkin build of franka_msgs makes.

The pinned MD5 sums are computed here by the algorithm ROS documents (wiki.ros.org/ROS/Technical
Overview, "Message serialization and msg MD5 sums"): the .msg text without comments, constants
first, each field of a message type written as that type's MD5 sum; the texts are the ones
actionlib's genaction.py writes for ``ErrorRecovery.action`` (``---\\n---\\n``). The Action's sum,
d5a016b4..., is also the one in rosserial's generated header for franka_msgs/ErrorRecoveryAction.
A mismatch means franka_control_node would refuse lab_sim's or the teleoperation node's client.
"""

from __future__ import annotations

import hashlib
import io
from typing import Dict

import pytest

pytest.importorskip("genpy", reason="needs ROS 1's genpy (run 'make setup')")
pytest.importorskip("actionlib_msgs", reason="needs ROS 1's actionlib_msgs (run 'make setup')")

from actionlib_msgs.msg import GoalID, GoalStatus
from std_msgs.msg import Header

from hri_teleop.ros import action_msgs
from hri_teleop.ros import franka_msgs as fm

EXPECTED_MD5 = {
    "ErrorRecoveryAction": "d5a016b49f278075666fbc901debbd08",
    "ErrorRecoveryActionGoal": "4b30be6cd12b9e72826df56b481f40e0",
    "ErrorRecoveryActionResult": "1eb06eeff08fa7ea874431638cb52332",
    "ErrorRecoveryActionFeedback": "aae20e09065c3809e8a8e87c4c8953fd",
    "ErrorRecoveryGoal": "d41d8cd98f00b204e9800998ecf8427e",
    "ErrorRecoveryResult": "d41d8cd98f00b204e9800998ecf8427e",
    "ErrorRecoveryFeedback": "d41d8cd98f00b204e9800998ecf8427e",
}


def _md5(text: str) -> str:
    return hashlib.md5(text.encode()).hexdigest()


def _documented_md5s(goal: str, result: str, feedback: str) -> Dict[str, str]:
    """The seven sums by ROS's documented rule, from the three sections' MD5 texts (comments and
    blank lines already gone, fields of built-in types only)."""
    g, r, f = _md5(goal), _md5(result), _md5(feedback)
    action_goal = _md5(f"{Header._md5sum} header\n{GoalID._md5sum} goal_id\n{g} goal")
    action_result = _md5(f"{Header._md5sum} header\n{GoalStatus._md5sum} status\n{r} result")
    action_feedback = _md5(f"{Header._md5sum} header\n{GoalStatus._md5sum} status\n{f} feedback")
    return {
        "ErrorRecoveryAction": _md5(f"{action_goal} action_goal\n{action_result} action_result\n"
                                    f"{action_feedback} action_feedback"),
        "ErrorRecoveryActionGoal": action_goal, "ErrorRecoveryActionResult": action_result,
        "ErrorRecoveryActionFeedback": action_feedback,
        "ErrorRecoveryGoal": g, "ErrorRecoveryResult": r, "ErrorRecoveryFeedback": f,
    }


def test_the_pinned_sums_follow_from_the_documented_algorithm():
    assert _documented_md5s("", "", "") == EXPECTED_MD5


@pytest.mark.parametrize("name", sorted(EXPECTED_MD5))
def test_md5_sum_and_type_equal_franka_msgs(name):
    cls = getattr(fm, name)
    assert cls._type == f"franka_msgs/{name}"
    assert cls._md5sum == EXPECTED_MD5[name], f"{name}: definition differs from franka_msgs'"


def test_the_definition_is_franka_msgs_empty_action_verbatim():
    assert fm.ACTION_DEFINITIONS == {"ErrorRecovery": "---\n---\n"}


def test_a_changed_definition_gives_other_sums_than_the_pinned_ones():
    """The pins bite: a result with a field (as franka_gripper's actions have) changes the sums."""
    source, changed = action_msgs.load_action_messages(
        "franka_msgs_changed", {"ErrorRecovery": "---\nbool success\n---\n"}, "test")
    assert source == "generated"
    assert changed["ErrorRecoveryResult"]._md5sum == _md5("bool success")
    for name in ("ErrorRecoveryAction", "ErrorRecoveryActionResult", "ErrorRecoveryResult"):
        assert changed[name]._md5sum != EXPECTED_MD5[name], name
    assert changed["ErrorRecoveryActionResult"]._md5sum == _documented_md5s("", "bool success", "")[
        "ErrorRecoveryActionResult"]


def test_every_class_is_exported_with_the_action_parts():
    assert set(EXPECTED_MD5) <= set(fm.__all__)
    assert fm.ErrorRecoveryGoal.__slots__ == [] and fm.ErrorRecoveryResult.__slots__ == []
    assert fm.ErrorRecoveryAction.__slots__ == ["action_goal", "action_result", "action_feedback"]
    assert fm.ErrorRecoveryActionGoal.__slots__ == ["header", "goal_id", "goal"]
    assert fm.ErrorRecoveryActionResult.__slots__ == ["header", "status", "result"]


def test_an_action_goal_round_trips_with_the_header_and_goal_id_actionlib_passes():
    import genpy

    msg = fm.ErrorRecoveryActionGoal(header=Header(seq=7), goal_id=GoalID(stamp=genpy.Time(3, 4), id="r1"),
                                     goal=fm.ErrorRecoveryGoal())
    buff = io.BytesIO()
    msg.serialize(buff)
    back = fm.ErrorRecoveryActionGoal().deserialize(buff.getvalue())
    assert (back.header.seq, back.goal_id.id, back.goal_id.stamp.secs) == (7, "r1", 3)


def test_the_generated_text_is_genactions():
    if fm.SOURCE != "generated":
        pytest.skip("franka_msgs is installed: its own classes are used")
    autogen = "# ====== DO NOT MODIFY! AUTOGENERATED FROM AN ACTION DEFINITION ======\n"
    assert fm.ErrorRecoveryGoal._full_text == autogen
    assert fm.ErrorRecoveryFeedback._full_text == autogen + "\n"
    assert fm.ErrorRecoveryActionGoal._full_text.startswith(
        autogen + "\nHeader header\nactionlib_msgs/GoalID goal_id\nErrorRecoveryGoal goal\n")


def test_no_ros_messages_give_one_line_naming_the_fix(monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_std_msgs(name, *args, **kwargs):
        if name in ("std_msgs.msg", "actionlib_msgs.msg"):
            raise ImportError(f"No module named {name!r}")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_std_msgs)
    with pytest.raises(action_msgs.ActionMsgsError, match="cannot build the missing_pkg messages: .*make setup"):
        action_msgs.load_action_messages("missing_pkg", fm.ACTION_DEFINITIONS, "test")
