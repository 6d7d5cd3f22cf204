"""The class report's item analysis and written answers nobody has graded by hand yet (issue 43, item 8).

A real nbgrader gradebook (nbgrader's own API, no autograde needed): an assignment with an autograded
test cell and two written answers, three students. A written answer counts in the item analysis once it
is graded by hand for one student at least; graded for none, it stays out and the report says it is
pending. Of a counted answer, the students whose answer has its grade are counted (graded by hand, or
blank: nbgrader gives a blank answer 0 without grading); one still waiting is not.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from hri_teleop.grading.batch.class_results import notebook_parts
from hri_teleop.grading.batch.report import write_report
from hri_teleop.grading.batch.report_data import (
    AssignmentScore,
    ClassResults,
    StudentRecord,
    item_rates,
    pending_items,
)

pytest.importorskip("nbgrader")
#: nbgrader's own add_submission warns about its session; not ours to fix
pytestmark = pytest.mark.filterwarnings("ignore:Object of type")

COURSE_ID = "hri-task4-teleoperation"
ASSIGNMENT, NOTEBOOK = "preparation", "ex01_fsr_and_arduino"
AUTO, BUG, NONLINEAR = "ex1_rate", "ex1b_bug", "ex1c_nonlinear"
STUDENTS = ("alice", "bob", "carl")


def _item(cell: str) -> str:
    return f"{ASSIGNMENT}/{NOTEBOOK}: {cell}"


@pytest.fixture()
def gradebook(tmp_path: Path) -> str:
    """ex1_rate autograded (everyone 1/1); ex1b_bug: alice graded by hand 1/1, bob blank (0 without grading),
    carl waiting; ex1c_nonlinear: nobody graded by hand (alice and carl waiting, bob blank)."""
    from nbgrader.api import Gradebook

    url = f"sqlite:///{tmp_path / 'gradebook.db'}"
    with Gradebook(url, COURSE_ID) as gb:
        gb.add_assignment(ASSIGNMENT)
        gb.add_notebook(NOTEBOOK, ASSIGNMENT)
        gb.add_grade_cell(AUTO, NOTEBOOK, ASSIGNMENT, max_score=1, cell_type="code")
        for cell in (BUG, NONLINEAR):
            gb.add_grade_cell(cell, NOTEBOOK, ASSIGNMENT, max_score=1, cell_type="markdown")
            gb.add_solution_cell(cell, NOTEBOOK, ASSIGNMENT)
        for student in STUDENTS:
            gb.add_student(student)
            gb.add_submission(ASSIGNMENT, student)
            gb.find_grade(AUTO, NOTEBOOK, ASSIGNMENT, student).auto_score = 1.0
        gb.find_grade(BUG, NOTEBOOK, ASSIGNMENT, "alice").manual_score = 1.0
        for cell in (BUG, NONLINEAR):
            gb.find_grade(cell, NOTEBOOK, ASSIGNMENT, "bob").auto_score = 0.0  # left blank: nbgrader's 0
        gb.db.commit()
    return url


def _class(url: str) -> ClassResults:
    parts = notebook_parts(url, COURSE_ID, [(s, ASSIGNMENT) for s in STUDENTS])
    students = tuple(StudentRecord(s, "graded", (AssignmentScore(ASSIGNMENT, 1.0, 3.0),), (), (),
                                   tuple(parts[(s, ASSIGNMENT)])) for s in STUDENTS)
    return ClassResults("course", (ASSIGNMENT,), students)


def _grade_by_hand(url: str, cell: str, student: str, score: float) -> None:
    from nbgrader.api import Gradebook

    with Gradebook(url, COURSE_ID) as gb:
        gb.find_grade(cell, NOTEBOOK, ASSIGNMENT, student).manual_score = score
        gb.db.commit()


def test_a_written_answer_graded_by_hand_for_nobody_stays_out_of_the_item_analysis(gradebook, tmp_path):
    results = _class(gradebook)
    rates = {r.item: r for r in item_rates(results.students)}
    assert _item(NONLINEAR) not in rates  # bob's blank 0 alone would have listed it as 0 %, worst first
    assert pending_items(results.students) == [_item(NONLINEAR)]
    assert (rates[_item(AUTO)].n, rates[_item(AUTO)].full) == (3, 3)
    page = write_report(tmp_path, results).read_text()
    assert "1 written answer(s) nobody has graded by hand yet are left out" in page
    assert f"{_item(NONLINEAR)}</td>" not in page and f"{_item(BUG)}</td>" in page


def test_a_written_answer_graded_by_hand_for_one_student_counts_with_the_graded_answers(gradebook, tmp_path):
    rates = {r.item: r for r in item_rates(_class(gradebook).students)}
    # alice's grade by hand and bob's blank answer count; carl's answer still waits and does not
    assert (rates[_item(BUG)].n, rates[_item(BUG)].full) == (2, 1)
    assert rates[_item(BUG)].mean_fraction == pytest.approx(0.5)

    _grade_by_hand(gradebook, NONLINEAR, "carl", 0.5)  # the threshold: one student graded by hand
    results = _class(gradebook)
    rates = {r.item: r for r in item_rates(results.students)}
    assert pending_items(results.students) == []
    assert (rates[_item(NONLINEAR)].n, rates[_item(NONLINEAR)].full) == (2, 0)  # carl 0.5, bob's blank 0
    assert rates[_item(NONLINEAR)].mean_fraction == pytest.approx(0.25)
    page = write_report(tmp_path, results).read_text()
    assert "nobody has graded by hand yet" not in page and f"{_item(NONLINEAR)}</td>" in page
