"""The functions a notebook's autograded cell calls: an AssertionError a student can act on, or the result."""

from __future__ import annotations

import pytest
from grading_helpers import SOLUTIONS, answer_text, write_package

from hri_teleop.grading import check
from hri_teleop.grading.exercises.robot_params import grade_robot_params


def test_check_returns_the_result_when_every_part_passes():
    result = check("robot-params", SOLUTIONS)
    assert result.passed and result.score == result.max_score == 10


def test_check_raises_with_the_feedback_when_a_part_fails(tmp_path):
    bad = answer_text("config/robot_params.yaml").replace("load_gripper: true ", 'load_gripper: "true"')
    write_package(tmp_path / "hri_lab", {"config/robot_params.yaml": bad})
    with pytest.raises(AssertionError) as info:
        check("robot-params", tmp_path / "hri_lab")
    text = str(info.value)
    assert "[FAIL] load_gripper" in text and "without quotes" in text and "total: 8/10" in text
    assert grade_robot_params(tmp_path / "hri_lab").score == 8  # grade_* never raises for a student's mistake
