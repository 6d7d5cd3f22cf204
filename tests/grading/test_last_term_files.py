"""Files written against last term's templates (tests/grading/last_term/: hri_teleop.gamepad, hri_teleop.limits,
hri_teleop.mapping, ...) run and are graded as today's: full points, part by part the same as the answer key's.
Their provided nodes run on the old paths too; and a file that takes a reference rule through the student API
gets no points."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path
from typing import List, Tuple

import pytest
from grading_helpers import answer_text, hri_grade, write_package

pytestmark = pytest.mark.ros

LAST_TERM = Path(__file__).resolve().parent / "last_term"
SEED = "7"


def _grade_teleoperation(package: Path, out: Path) -> Tuple[float, List[Tuple[str, float, float]]]:
    """hri-grade teleoperation on ``package``, as the course runs it: (score, [(part, score, max)])."""
    proc = hri_grade("teleoperation", str(package), "--json", "--seed", SEED, "--out", str(out))
    assert proc.returncode in (0, 1), proc.stderr
    data = json.loads(proc.stdout)
    return data["score"], [(t["name"], t["score"], t["max_score"]) for t in data["tests"]]


def test_last_terms_teleoperation_gets_full_points_part_by_part_as_todays_answer_key(tmp_path):
    old = tmp_path / "last_term" / "hri_lab"
    (old / "scripts").mkdir(parents=True)
    shutil.copy2(LAST_TERM / "teleoperation.py", old / "scripts" / "teleoperation.py")
    today = write_package(tmp_path / "today" / "hri_lab", {"scripts/teleoperation.py": answer_text("scripts/teleoperation.py")})
    old_score, old_parts = _grade_teleoperation(old, tmp_path / "out-old")
    today_score, today_parts = _grade_teleoperation(today, tmp_path / "out-today")
    assert old_score == today_score == sum(points for _, _, points in today_parts) == 22
    assert old_parts == today_parts


def test_last_terms_sensor_node_runs_on_the_old_paths_and_says_once_what_to_import(ros_master):
    node = ros_master.run([sys.executable, str(LAST_TERM / "FSR_sensor.py"), "_rate_hz:=50"], "FSR_sensor")
    echo = ros_master.run(["rostopic", "echo", "-n", "1", "/pub_force/data"], "echo")
    assert echo.wait(timeout_s=60) == 0, echo.output()
    assert [line for line in echo.output().splitlines() if line.strip().isdigit()], echo.output()  # a count arrived
    assert node.running
    node.stop()
    said = [line for line in node.output().splitlines() if "DeprecationWarning" in line]
    assert [line.split("DeprecationWarning: ")[1] for line in said] == [
        "hri_teleop.mapping is deprecated: write 'from hri_teleop.student import ADC_MAX_COUNT' instead; it goes in 2.0",
        "hri_teleop.sensor_profile is deprecated: write 'from hri_teleop.student import FSR_SENSOR_RATE_HZ, "
        "press_profile_count' instead; it goes in 2.0"]


def test_last_terms_gripper_manager_runs_on_the_old_paths(ros_master):
    node = ros_master.run([sys.executable, str(LAST_TERM / "gripper_manager.py")], "gripper_manager")
    ros_master.wait_for(lambda: "/gripper_manager" in ros_master.subscribers("/gripper_width"), 60,
                        "last term's gripper_manager.py to subscribe /gripper_width")
    assert node.running
    node.stop()
    said = [line for line in node.output().splitlines() if "DeprecationWarning" in line]
    assert len(said) == 1 and "hri_teleop.gripper is deprecated: write 'from hri_teleop.student import " \
                              "GoalThrottle, usable_width_m'" in said[0]


def test_a_teleoperation_that_takes_the_reference_rule_through_the_student_api_scores_zero(tmp_path):
    from hri_teleop.grading.exercises.teleoperation.check import grade_teleoperation

    text = answer_text("scripts/teleoperation.py")
    delegated = text.replace("import rospy\n", "import rospy\nimport hri_teleop.student as api\n", 1).replace(
        "        self.rumble = min(1.0, max(0.0, self.force))\n",
        "        self.rumble = api.TeleopController.rumble_of(self.force)\n", 1)
    assert "api.TeleopController" in delegated
    package = write_package(tmp_path / "hri_lab", {"scripts/teleoperation.py": delegated})
    result = grade_teleoperation(package, seed=1, node=False)
    assert result.score == 0 and result.max_score == 22
    assert result.parts[0].message.startswith("teleoperation.py uses the lab's reference implementation (line ")
    assert "hri_teleop.student.TeleopController" in result.parts[0].message
