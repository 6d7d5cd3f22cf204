"""make check's points per cell follow nbgrader's autograde rule, case by case (compared with nbgrader itself)."""

from __future__ import annotations

import nbformat
import pytest

from hri_teleop.apps.selfcheck import cell_points, find_notebooks


def _cell(outputs, points=4):
    cell = nbformat.v4.new_code_cell("score(...)")
    cell.metadata["nbgrader"] = {"grade": True, "solution": False, "locked": True, "grade_id": "c", "points": points,
                                 "schema_version": 3}
    cell.outputs = [nbformat.from_dict(o) for o in outputs]
    return cell


def _result(text):
    return {"output_type": "execute_result", "execution_count": 1, "metadata": {}, "data": {"text/plain": text}}


CASES = [
    ([], 4.0),
    ([{"output_type": "error", "ename": "AssertionError", "evalue": "", "traceback": []}], 0.0),
    ([{"output_type": "stream", "name": "stderr", "text": "warning"}], 0.0),
    ([{"output_type": "stream", "name": "stdout", "text": "hello"}], 4.0),
    ([_result("2.5")], 2.5),
    ([_result("0.0")], 0.0),
    ([_result("4.0")], 4.0),
    ([_result("-1")], 4.0),
    ([_result("'text'")], 4.0),
    ([{"output_type": "display_data", "metadata": {}, "data": {"text/plain": "1.0"}}], 4.0),
    ([{"output_type": "stream", "name": "stdout", "text": "x"}, _result("1.0")], 1.0),
]


@pytest.mark.parametrize("outputs, expected", CASES)
def test_a_cell_gets_the_points_nbgrader_gives_it(outputs, expected):
    cell = _cell(outputs)
    assert cell_points(cell) == (expected, 4.0)
    nbgrader_utils = pytest.importorskip("nbgrader.utils")
    assert nbgrader_utils.determine_grade(cell) == (expected, 4.0)


def test_only_exercise_notebooks_of_the_assignments_are_checked(tmp_path):
    for name in ("preparation/ex01_a.ipynb", "preparation/ex05_b.ipynb", "lab/ex12_c.ipynb", "lab/notes.ipynb",
                 "lab/.ipynb_checkpoints/ex12_c.ipynb", "ex99_top.ipynb"):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text("{}")
    assert [p.name for p in find_notebooks(tmp_path)] == ["ex12_c.ipynb", "ex01_a.ipynb", "ex05_b.ipynb"]
    assert [p.name for p in find_notebooks(tmp_path, ["ex05", "ex12"])] == ["ex12_c.ipynb", "ex05_b.ipynb"]
