"""Where a deliverable's points live, rule by rule: a graded cell that runs a check is refused whatever its
grade_id, the files carry their checks' points, and an assignment's total counts each job once.

The points are the documented ones (docs/instructors.md, Points), written as numbers.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, List

import pytest

from hri_teleop.grading.points import assignment_points, check_cell_problems, check_points, files_points, is_check_cell


def _notebook(source: Path, assignment: str, name: str, cells: List[Dict[str, Any]]) -> Path:
    path = source / assignment / f"{name}.ipynb"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5}))
    return path


def _cell(grade_id: str, source: Any, grade: bool = True, points: float = 0.0, solution: bool = False,
          cell_type: str = "code") -> Dict[str, Any]:
    meta = {"grade": grade, "grade_id": grade_id, "locked": True, "points": points, "solution": solution}
    return {"cell_type": cell_type, "metadata": {"nbgrader": meta}, "source": source, "outputs": []}


@pytest.mark.parametrize("source", [
    "check.mapping_node(PACKAGE)",
    ["x = 1\n", "  check.teleoperation(PACKAGE)\n"],
    "result = 2\ncheck.graph(PACKAGE, verbose=True)",
])
def test_a_graded_cell_that_runs_a_check_under_a_new_grade_id_is_refused_its_points_count_twice(tmp_path, source):
    """The table of check cells does not know the id: the call to check.x() in the cell is what counts."""
    _notebook(tmp_path, "lab", "ex99_new", [_cell("ex99_my_new_check", source, points=5)])
    problems = check_cell_problems(tmp_path)
    assert len(problems) == 1
    assert problems[0].startswith("lab/ex99_new.ipynb: cell ex99_my_new_check runs a check and carries 5 nbgrader")


def test_a_known_check_cell_with_points_is_refused_though_it_calls_no_check(tmp_path):
    _notebook(tmp_path, "preparation", "ex05_mapping_node", [_cell("ex5_node", "print('hello')", points=3)])
    problems = check_cell_problems(tmp_path)
    assert len(problems) == 1
    assert problems[0].startswith("preparation/ex05_mapping_node.ipynb: cell ex5_node runs a check and carries 3 ")


def test_a_check_cell_that_is_read_only_and_worth_nothing_is_the_rule(tmp_path):
    _notebook(tmp_path, "lab", "ex09_teleoperation_node", [
        _cell("ex9_node", "check.teleoperation(PACKAGE)", grade=False),
        _cell("ex9_package", "check.catkin_package(PACKAGE)", grade=False),
    ])
    assert check_cell_problems(tmp_path) == []


@pytest.mark.parametrize("source", ["mycheck.mapping_node(PACKAGE)", "# check.mapping_node later\nx = 1",
                                    "print('check.graph(PACKAGE)')"])
def test_a_graded_cell_that_only_names_check_elsewhere_on_a_line_is_judged_as_any_autograded_cell(tmp_path, source):
    """Not a call at the start of a line: an autograded cell, refused only for want of a rule of its own."""
    _notebook(tmp_path, "lab", "ex99_new", [_cell("ex99_other", source, points=2)])
    problems = check_cell_problems(tmp_path)
    assert len(problems) == 1 and "autograded cell ex99_other has no rule in the grader" in problems[0]


def test_an_autograded_cell_with_a_rule_of_the_grader_is_accepted_and_a_solution_or_markdown_cell_is_not_judged(tmp_path):
    _notebook(tmp_path, "preparation", "ex01", [
        _cell("ex1a_rate", "hand_in('ex1a_rate', rate)", points=2),
        _cell("ex99_written", "your answer", points=2, solution=True),
        _cell("ex99_text", "Explain.", points=2, cell_type="markdown"),
        _cell("ex99_ungraded", "x = 1", grade=False),
    ])
    assert check_cell_problems(tmp_path) == []


def test_a_file_that_is_not_a_notebook_is_left_to_nbgrader(tmp_path):
    (tmp_path / "lab").mkdir()
    (tmp_path / "lab" / "broken.ipynb").write_text("{not json")
    (tmp_path / "lab" / "list.ipynb").write_text("[1, 2]")
    assert check_cell_problems(tmp_path) == []


@pytest.mark.parametrize("grade_id, check_cell", [("ex9_node", True), ("ex15_graph", True), ("ex4_file", True),
                                                  ("ex9_nod", False), ("ex1a_rate", False), ("", False)])
def test_a_check_cell_is_known_by_its_exact_grade_id(grade_id, check_cell):
    assert is_check_cell(grade_id) is check_cell


@pytest.mark.parametrize("check, points", [("robot-params", 10), ("mapping-node", 20), ("sensor-launch", 10),
                                           ("teleoperation", 22), ("teleoperation-launch", 14), ("graph", 9),
                                           ("catkin-package", 4)])
def test_each_check_carries_its_documented_points(check, points):
    assert check_points(check) == pytest.approx(points)


@pytest.mark.parametrize("assignment, checks, points", [
    ("preparation", None, 40), ("lab", None, 49), ("lab", ["graph"], 9), ("lab", ["graph", "mapping-node"], 9),
    ("lab", [], 0), ("nothing", None, 0),
])
def test_an_assignments_files_carry_the_points_of_its_checks(assignment, checks, points):
    assert files_points(assignment, checks) == pytest.approx(points)


def test_an_assignments_total_is_its_notebooks_plus_its_files_each_once():
    jobs = [
        {"assignment": "lab", "kind": "notebooks", "status": "graded", "score": 8, "max_score": 10},
        {"assignment": "lab", "kind": "files", "status": "graded", "score": 40.5, "max_score": 49},
        {"assignment": "preparation", "kind": "notebooks", "status": "graded", "score": None, "max_score": 10},
        {"assignment": "preparation", "kind": "files", "status": "failed", "score": 0, "max_score": 40},
        {"assignment": "extra", "kind": "files", "status": "graded", "score": 3, "max_score": 3},
    ]
    assert assignment_points(jobs) == {"lab": (48.5, 59.0), "preparation": (None, None)}


def test_a_graded_notebooks_job_alone_is_its_assignments_total():
    jobs = [{"assignment": "lab", "kind": "notebooks", "status": "graded", "score": None, "max_score": None}]
    assert assignment_points(jobs) == {"lab": (0.0, 0.0)}


def test_a_notebook_nbgrader_cannot_read_does_not_hide_the_next_ones_problems(tmp_path):
    (tmp_path / "lab").mkdir()
    (tmp_path / "lab" / "a_broken.ipynb").write_text("{not json")
    (tmp_path / "lab" / "b_list.ipynb").write_text("[1, 2]")
    _notebook(tmp_path, "lab", "c_new", [_cell("ex99_new", "check.graph(PACKAGE)", points=1)])
    assert [p.split(":")[0] for p in check_cell_problems(tmp_path)] == ["lab/c_new.ipynb"]


def test_cells_without_nbgrader_metadata_source_or_cells_at_all_are_not_graded_cells(tmp_path):
    (tmp_path / "lab").mkdir()
    (tmp_path / "lab" / "a_empty.ipynb").write_text(json.dumps({"metadata": {}, "nbformat": 4}))
    _notebook(tmp_path, "lab", "b_plain", [
        {"cell_type": "markdown", "source": "# Ex. 9"},
        {"cell_type": "code", "metadata": {}, "source": ["check.graph(PACKAGE)\n"], "outputs": []},
        {"cell_type": "code", "metadata": {"nbgrader": {"grade": False}}, "outputs": []},
        _cell("ex99_bad", ["x = 1\n", "check.graph(PACKAGE)\n"], points=4),
    ])
    problems = check_cell_problems(tmp_path)
    assert len(problems) == 1 and problems[0].startswith("lab/b_plain.ipynb: cell ex99_bad runs a check")


def test_each_assignment_is_counted_whatever_comes_before_it():
    jobs = [
        {"assignment": "extra", "kind": "files", "status": "graded", "score": 3, "max_score": 3},
        {"assignment": "preparation", "kind": "notebooks", "status": "failed", "score": 0, "max_score": 10},
        {"assignment": "preparation", "kind": "files", "status": "graded", "score": 40, "max_score": 40},
        {"assignment": "lab", "kind": "notebooks", "status": "graded", "score": 10, "max_score": 10},
        {"assignment": "lab", "kind": "files", "status": "graded", "score": 49, "max_score": 49},
    ]
    assert assignment_points(jobs) == {"preparation": (None, None), "lab": (59.0, 59.0)}


def test_a_problem_names_the_points_at_stake_zero_when_the_cell_names_none(tmp_path):
    check = _cell("ex99_check", "check.graph(PACKAGE)")
    del check["metadata"]["nbgrader"]["points"]
    no_rule = _cell("ex99_other", "x = 1")
    del no_rule["metadata"]["nbgrader"]["points"]
    _notebook(tmp_path, "lab", "ex99", [check, no_rule, _cell("ex99_third", "y = 2", points=2.5)])
    problems = check_cell_problems(tmp_path)
    assert "carries 0 nbgrader points" in problems[0]
    assert "so its 0 points could not be given" in problems[1]
    assert "so its 2.5 points could not be given" in problems[2]
