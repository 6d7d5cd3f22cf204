"""`make grade` on a folder of 20 small submissions: progress shown, every grade recorded, the class report,
lms.csv and the late policy written; then `make grade STUDENT=id` regrades one student in place."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import time

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


#: Handed in (the LMS export late.yaml's times: names; nbgrader's timestamp.txt says the same and is only shown)
#: against the deadline 2026-12-01 23:59 +01:00: per student, else on time.
SUBMITTED = {4: "2026-12-02 00:00:00 +0100",    # one minute late: a day started, 10 % of the 89 points
             5: "2026-12-02 23:59:00 +0100",    # a day late, but their extension is 2 days: on time
             8: "2026-12-11 23:59:01 +0100"}    # 11 days started: the 50 % cap, and the total floored at 0
ON_TIME = "2026-12-01 23:59:00 +0100"
LATE_YAML = ('deadline: "2026-12-01 23:59 +01:00"\nper_day: 10%\ncap: 50%\ntimes: submitted-at.csv\n'
             "extensions:\n  student05: 2\n")


def _make_grade(submitted, out, *variables: str):
    # -o setup: the suite runs after `make setup` (make test does it); a concurrent re-setup must not time this out
    proc = subprocess.Popen(["make", "-s", "-o", "setup", "grade", f"DIR={submitted}", f"OUT={out}", *variables],
                            cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=grader_env(),
                            start_new_session=True)
    try:
        stdout, stderr = proc.communicate(timeout=300)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)  # make and everything it started
        proc.communicate()
        raise
    return proc.returncode, stdout, stderr


def test_make_grade_grades_twenty_submissions_in_parallel_and_records_every_grade(tmp_path):
    submitted = tmp_path / "submitted"
    for i in range(20):
        # nbgrader's layout: submitted/<student>/<assignment>/...
        write_package(submitted / f"student{i:02d}" / "task4" / "hri_lab", {"config/robot_params.yaml": _variant(i)})
        (submitted / f"student{i:02d}" / "task4" / "timestamp.txt").write_text(SUBMITTED.get(i, ON_TIME))
    # plain folders: one submission per student, so * (all of the student's assignments) holds for it
    (submitted / "submitted-at.csv").write_text("student,assignment,submitted_at\n" + "".join(
        f"student{i:02d},*,{SUBMITTED.get(i, ON_TIME)}\n" for i in range(20)))
    (submitted / "late.yaml").write_text(LATE_YAML)
    out = tmp_path / "grades"
    started = time.monotonic()
    code, stdout, stderr = _make_grade(submitted, out, "JOBS=2")
    print(f"make grade: {time.monotonic() - started:.1f} s")
    assert code == 0, stdout[-3000:] + stderr[-3000:]
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

    # the late policy: grades.csv's points taken and total, the student's feedback, lms.csv, the report
    rows = {r["student"]: r for r in csv.DictReader(open(out / "grades.csv"))}
    assert [(rows[s]["late_penalty"], rows[s]["total"]) for s in ("student00", "student04", "student05", "student08")] \
        == [("0", "10"), ("8.9", "1.1"), ("0", "8"), ("44.5", "0")]
    feedback = (out / "student04" / "feedback.txt").read_text().splitlines()
    assert feedback[0].startswith("late policy: submitted 2026-12-02 00:00:00+01:00 (submitted-at.csv, the LMS export; "
                                  "the submission's a sub-folder's timestamp.txt says 2026-12-01 23:00:00+00:00 "
                                  "(not used)), 1 min after"), feedback[0]
    assert "your extension" in (out / "student05" / "feedback.txt").read_text()
    lms = list(csv.reader(open(out / "lms.csv")))
    assert lms[0] == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "Task 4 total"]
    assert lms[5] == ["student04", "", "", "student04", "", "1.1"] and len(lms) == 21
    report = (out / "report.html").read_text()
    for words in ("Score distribution", "Item analysis", "Every submission was graded", "Late submissions (2)",
                  '<img src="report-scores.png"', "robot-params: robot_mass"):
        assert words in report, words
    assert (out / "report-scores.png").stat().st_size > 5000 and (out / "report-items.png").stat().st_size > 5000

    # STUDENT=id: student03 fixed their file and is regraded; everyone else's rows stay as they were
    write_package(submitted / "student03" / "task4" / "hri_lab", {"config/robot_params.yaml": _variant(0)})
    started = time.monotonic()
    code, stdout, stderr = _make_grade(submitted, out, "STUDENT=student03")
    print(f"make grade STUDENT=student03: {time.monotonic() - started:.1f} s")
    assert code == 0, stdout[-3000:] + stderr[-3000:]
    assert [line for line in stdout.splitlines() if line.startswith("[")] == [
        line for line in stdout.splitlines() if line.startswith("[1/1] student03")]
    again = {r["student"]: r for r in csv.DictReader(open(out / "grades.csv"))}
    assert list(again) == list(rows) and again["student03"]["total"] == "10"
    assert all(again[s] == rows[s] for s in rows if s != "student03")
    assert "student03,,,student03,,10" in (out / "lms.csv").read_text()

    # REPORT=1 grades nothing: student04's new extension reaches grades.csv, lms.csv and the feedback
    (submitted / "late.yaml").write_text(LATE_YAML + "  student04: 1\n")
    code, stdout, stderr = _make_grade(submitted, out, "REPORT=1")
    assert code == 0 and not [line for line in stdout.splitlines() if line.startswith("[")], stdout + stderr
    refreshed = {r["student"]: r for r in csv.DictReader(open(out / "grades.csv"))}
    assert (refreshed["student04"]["late_penalty"], refreshed["student04"]["total"]) == ("0", "10")
    assert "your extension" in (out / "student04" / "feedback.txt").read_text()

    code, stdout, stderr = _make_grade(submitted, out, "STUDENT=student3")
    mine = [line for line in stderr.splitlines() if line.startswith("hri-grade")]
    assert code == 2 and len(mine) == 1 and "did you mean student13, student03" in mine[0], stderr
    assert "ls " in stderr and "grades.csv" in stderr
