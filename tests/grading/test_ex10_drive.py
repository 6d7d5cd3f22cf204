"""Ex. 10 is judged on a drive the grader makes itself: the student's teleoperation.py, boxed, beside the grader's
lab_sim on the grader's clock, the notebook's drive on the scripted pad, the hand's height from lab_sim
(hri_teleop.grading.batch.drive_check). The kernel's own reading of the hand (a patched ``lab.hand_z_m`` could
say anything) counts for nothing."""

from __future__ import annotations

import ast
import json
from pathlib import Path
from typing import Any, Dict

import pytest
from grading_helpers import SOLUTIONS

from hri_teleop.grading.batch.drive_check import EX10_DRIVE, ex10_values
from hri_teleop.grading.batch.notebook_judge import judge_notebook
from hri_teleop.grading.judge.notebook_answers import EX10_DROP_M, MIME, expectations

NOTEBOOK = Path(__file__).resolve().parents[2] / "notebooks" / "source" / "lab" / "ex10_teleoperate_robot.ipynb"
pytestmark = pytest.mark.ros


def _package(folder: Path, replace: Dict[str, str] = None) -> Path:
    from hri_teleop.grading.cases.templates import generate_answers

    generate_answers(SOLUTIONS, folder / "hri_lab")
    node = folder / "hri_lab" / "scripts" / "teleoperation.py"
    text = node.read_text()
    for old, new in (replace or {}).items():
        assert old in text
        text = text.replace(old, new)
    node.write_text(text)
    return folder


def _notebook_drive() -> list:
    nb = json.loads(NOTEBOOK.read_text())
    start = next(c for c in nb["cells"] if c.get("metadata", {}).get("nbgrader", {}).get("grade_id") == "start")
    tree = ast.parse("".join(start["source"]))
    assign = next(n for n in tree.body if isinstance(n, ast.Assign) and getattr(n.targets[0], "id", "") == "drive")
    return ast.literal_eval(assign.value)


def test_the_graders_drive_is_the_notebooks_without_its_quit():
    drive = _notebook_drive()
    assert drive[-1].get("tap") == "west"
    assert [dict(step) for step in EX10_DRIVE] == drive[:-1]


def test_the_answer_keys_node_drives_the_hand_down_past_the_rule(tmp_path):
    values = ex10_values(_package(tmp_path))
    assert set(values) == {"z_start_m", "z_m"}, values
    assert values["z_start_m"] - values["z_m"] > EX10_DROP_M  # 4.4 cm, as in real time


def test_a_node_that_reads_the_wrong_stick_leaves_the_hand_where_it_was(tmp_path):
    values = ex10_values(_package(tmp_path, {"z = self.normalize_analog_input(self.right_y)":
                                             "z = self.normalize_analog_input(0.0 * self.right_y)"}))
    assert abs(values["z_start_m"] - values["z_m"]) < 1e-3, values


def test_a_node_that_publishes_the_arms_pose_itself_is_not_judged(tmp_path):
    forged = ("    rospy.init_node(", "    import geometry_msgs.msg as _g\n    rospy.init_node(")
    folder = _package(tmp_path)
    node = folder / "hri_lab" / "scripts" / "teleoperation.py"
    text = node.read_text()
    assert text.count(forged[0]) == 1
    text = text.replace(forged[0], forged[1]).replace(
        "    node.open_pad(", "    _p = rospy.Publisher('/lab_sim/ee_pose', _g.PoseStamped, queue_size=1)\n    node.open_pad(")
    node.write_text(text)
    values = ex10_values(folder)
    assert "not_judged" in values and "only the simulated arm may" in values["not_judged"], values


def test_a_missing_node_is_not_judged(tmp_path):
    assert ex10_values(tmp_path)["not_judged"].startswith("the grader found no teleoperation.py")


def test_the_judge_takes_the_graders_drive_not_what_the_kernel_handed_in(tmp_path):
    nb: Dict[str, Any] = json.loads(NOTEBOOK.read_text())
    cell = next(c for c in nb["cells"] if c.get("metadata", {}).get("nbgrader", {}).get("grade_id") == "ex10_drives")
    cell["outputs"] = [{"output_type": "display_data", "metadata": {},  # a hook's forged reading
                        "data": {MIME: {"grade_id": "ex10_drives", "values": {"z_start_m": 0.5, "z_m": 0.1}}}}]
    folder = _package(tmp_path, {"z = self.normalize_analog_input(self.right_y)":
                                 "z = self.normalize_analog_input(0.0 * self.right_y)"})
    [verdict] = judge_notebook("ex10", nb, [("ex10_drives", 2.0)], {"ex10_drives": expectations("ex10_drives")},
                               folder=folder)
    assert verdict.score == 0.0 and verdict.source.startswith("measured by the grader"), verdict
    assert verdict.message.startswith("the hand is at z = 0.487 m, it started at 0.487 m"), verdict.message
