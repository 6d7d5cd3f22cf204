"""`make grade` on a folder of 20 small submissions: progress shown, every grade recorded."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess

import pytest
from grading_helpers import REPO, answer_text, grader_env, write_package

pytestmark = pytest.mark.ros


def _variant(i: int) -> str:
    good = answer_text("config/robot_params.yaml")
    if i % 4 == 1:
        return good.replace("robot_mass: 18.0 ", "robot_mass: 18   ")
    if i % 4 == 2:
        return good.replace("load_gripper: true ", 'load_gripper: "true"')
    if i % 4 == 3:
        return "robot_name: [unclosed\n"
    return good


def test_make_grade_grades_twenty_submissions_in_parallel_and_records_every_grade(tmp_path):
    submitted = tmp_path / "submitted"
    for i in range(20):
        # nbgrader's layout: submitted/<student>/<assignment>/...
        write_package(submitted / f"student{i:02d}" / "task4" / "hri_lab", {"config/robot_params.yaml": _variant(i)})
    out = tmp_path / "grades"
    # -o setup: the suite runs after `make setup` (make test does it); a concurrent re-setup must not time this out
    proc = subprocess.Popen(["make", "-s", "-o", "setup", "grade", f"DIR={submitted}", f"OUT={out}", "JOBS=2"],
                            cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=grader_env(),
                            start_new_session=True)
    try:
        stdout, stderr = proc.communicate(timeout=300)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)  # make and everything it started
        proc.communicate()
        raise
    assert proc.returncode == 0, stdout[-3000:] + stderr[-3000:]
    progress = [line for line in stdout.splitlines() if line.startswith("[")]
    assert len(progress) == 20 and progress[-1].startswith("[20/20]"), stdout
    with open(out / "grades.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["student"] for r in rows] == [f"student{i:02d}" for i in range(20)]
    assert all(r["status"] == "graded" for r in rows), rows
    maximum = float(rows[0]["max_score"])
    for i, row in enumerate(rows):
        want = {0: 10.0, 1: 8.0, 2: 8.0, 3: 0.0}[i % 4]  # robot-params only; the other files are missing
        assert float(row["score"]) == want, (row, (out / row["student"] / "feedback.txt").read_text())
        assert float(row["max_score"]) == maximum
        results = json.loads((out / row["student"] / "results.json").read_text())
        assert results["score"] == want and len(results["tests"]) > 20
        feedback = (out / row["student"] / "feedback.txt").read_text()
        assert "was not found" in feedback  # the missing deliverables are named
    assert "line 1" in (out / "student03" / "feedback.txt").read_text()
