"""Benchmark 4 (grading throughput) in smoke sizes: it runs, its rows add up, and what it timed was real grading.

Smoke sizes (benchmarks.grading): one ``hri-grade submission --checks robot-params``
on the answer key, and an nbgrader course of Ex. 1 with two submissions (the
answer key and the untouched release) graded three times: nbgrader's autograde one after
another, ``hri-grade batch --jobs 1`` and ``--jobs 2``.
"""

from __future__ import annotations

import csv
import json
import math

import pytest

from benchmarks.grading import (
    ASSIGNMENT,
    SMOKE_NOTEBOOKS,
    SUBMISSIONS_ENV,
    Student,
    autograded_points,
    check_grades_csv,
    run,
    student_plan,
    submission_count,
)
from benchmarks.report import BenchError, BenchOptions, format_row

pytestmark = pytest.mark.ros


def _finite_positive(value: float) -> bool:
    return math.isfinite(value) and value > 0


def test_grading_benchmark_smoke_measures_real_grading(tmp_path):
    messages = []
    rows = run(BenchOptions(out_dir=tmp_path, smoke=True, jobs=2), messages.append)
    for row in rows:
        print(format_row(row))

    assert [r.benchmark for r in rows] == ["hri-grade submission", "hri-grade submission, real time",
                                           "make grade, 1 worker", "make grade, 2 workers"]
    for row in rows:
        assert _finite_positive(row.ratio), row
        assert all(_finite_positive(v) for v in row.values.values()), row
        assert row.figure and row.reference and row.ratio_means, row

    submission, real_time, one, two = rows
    # Before and after in one run: the real-time row's reference is the grader's-clock row.
    assert real_time.values["grader_clock_s"] == submission.values["per_submission_s"]
    assert real_time.ratio == pytest.approx(real_time.values["per_submission_s"] / submission.values["per_submission_s"])
    assert (tmp_path / "grading" / "submission-real-time" / "run1" / "checks.json").is_file()
    v = submission.values
    assert v["runs"] == 1 and v["checks"] == 1 and set(v) >= {"per_submission_s", "checks_sum_s", "check_robot_params_s"}
    assert submission.ratio == pytest.approx(v["per_submission_s"] / v["checks_sum_s"], rel=1e-9)
    assert v["per_submission_s"] >= v["checks_sum_s"]  # the run's wall time holds the checks' own time
    checks = json.loads((tmp_path / "grading" / "submission" / "run1" / "checks.json").read_text())
    assert [(c["check"], c["score"]) for c in checks] == [("robot-params", c["max_score"]) for c in checks]
    assert v["checks_sum_s"] == pytest.approx(sum(c["duration_s"] for c in checks), abs=1e-3)

    for row, jobs in ((one, 1), (two, 2)):
        v = row.values
        assert v["submissions"] == 2 and v["jobs"] == jobs
        assert row.ratio == pytest.approx(v["total_s"] / v["reference_total_s"], rel=1e-9)
        assert v["per_submission_s"] == pytest.approx(v["total_s"] / 2, abs=1e-3)
        assert v["reference_per_submission_s"] == pytest.approx(v["reference_total_s"] / 2, abs=1e-3)
        assert 0 < v["autograde_jobs_s"] <= v["total_s"] * jobs
        with open(tmp_path / "grading" / "make_grade" / f"jobs{jobs}" / "grades" / "grades.csv") as fh:
            grades = {r["student"]: r for r in csv.DictReader(fh)}
        assert sorted(grades) == ["s01", "s02"] and {r["status"] for r in grades.values()} == {"graded"}
        assert float(grades["s01"]["notebooks_score"]) > float(grades["s02"]["notebooks_score"])  # key vs release
        assert float(grades["s01"]["files_score"]) == float(grades["s01"]["files_max"]) > 0
    assert one.reference == two.reference and one.values["reference_total_s"] == two.values["reference_total_s"]
    assert two.values["speedup_vs_1_worker"] == pytest.approx(one.values["total_s"] / two.values["total_s"], rel=1e-3)

    # the reference really autograded both students (nbgrader's own output folders)
    autograded = tmp_path / "grading" / "make_grade" / "nbgrader" / "course" / "autograded"
    for student in ("s01", "s02"):
        assert sorted(p.stem for p in (autograded / student / ASSIGNMENT).glob("*.ipynb")) == sorted(SMOKE_NOTEBOOKS)
    assert any("make grade JOBS=1: [" in m for m in messages) and any("nbgrader autograde" in m for m in messages)


def test_submission_count_smoke_default_and_override():
    assert submission_count(True, {SUBMISSIONS_ENV: "7"}) == 2
    assert submission_count(False, {}) == 20
    assert submission_count(False, {SUBMISSIONS_ENV: " 4 "}) == 4
    for bad in ("0", "-3", "four", "2.5"):
        with pytest.raises(BenchError, match=SUBMISSIONS_ENV):
            submission_count(False, {SUBMISSIONS_ENV: bad})


def test_student_plan_alternates_answer_key_and_release():
    assert student_plan(3) == [Student("s01", True), Student("s02", False), Student("s03", True)]
    assert [s.name for s in student_plan(120)][-1] == "s120" and student_plan(120)[0].name == "s001"
    with pytest.raises(BenchError):
        student_plan(0)


def _notebook(path, cells):
    path.write_text(json.dumps({"cells": [{"cell_type": "code", "metadata": {"nbgrader": m}, "source": ""}
                                          for m in cells] + [{"cell_type": "markdown", "metadata": {}}]}))
    return path


def test_autograded_points_leave_manual_answers_out_of_the_autograded_sum(tmp_path):
    a = _notebook(tmp_path / "a.ipynb", [{"grade": True, "solution": False, "points": 3},
                                         {"grade": True, "solution": True, "points": 2},  # graded by hand
                                         {"grade": False, "solution": True}])
    b = _notebook(tmp_path / "b.ipynb", [{"grade": True, "solution": False, "points": 1.5}])
    assert autograded_points([a, b]) == (4.5, 6.5)


def _grades(path, rows):
    columns = ["student", "notebooks_score", "notebooks_max", "files_score", "files_max", "status", "message"]
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow(dict(zip(columns, row)))
    return path


def test_check_grades_csv_accepts_a_real_grading_and_names_what_is_not(tmp_path):
    plan = student_plan(2)
    good = [("s01", "4", "6", "10", "10", "graded", ""), ("s02", "0", "6", "2", "10", "graded", "")]
    assert set(check_grades_csv(_grades(tmp_path / "g.csv", good), plan, 4, 6, True)) == {"s01", "s02"}
    cases = [
        ([good[0]], "1 row"),                                                     # a submission missing
        ([good[0], ("s02", "", "", "", "", "not graded", "Kernel died")], "s02 was not graded"),
        ([("s01", "3", "6", "10", "10", "graded", ""), good[1]], "not the full 4/6"),
        ([("s01", "4", "6", "7", "10", "graded", ""), good[1]], "hri_lab files"),
    ]
    for rows, words in cases:
        with pytest.raises(BenchError, match=words):
            check_grades_csv(_grades(tmp_path / "g.csv", rows), plan, 4, 6, True)
    # files not checked: their columns do not matter
    check_grades_csv(_grades(tmp_path / "g.csv", [("s01", "4", "6", "", "", "graded", ""), good[1]]), plan, 4, 6, False)
    with pytest.raises(BenchError, match="no grades.csv"):
        check_grades_csv(tmp_path / "missing.csv", plan, 4, 6, True)
