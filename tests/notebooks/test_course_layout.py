"""The nbgrader course in notebooks/: one notebook per exercise, nbgrader metadata, no outputs, config."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.course.release import (
    COURSE_DIR,
    exclude_overwriting,
    notebook_output_problems,
    solution_texts,
    source_notebooks,
    strip_outputs,
    student_files,
)
from hri_teleop.grading.assignments import ASSIGNMENTS

NOTEBOOKS = source_notebooks()
EXERCISES = {"preparation": set(range(1, 8)), "lab": set(range(8, 16))}


def _cells(path: Path) -> list:
    return json.loads(path.read_text(encoding="utf-8"))["cells"]


def _nbgrader(cell: dict) -> dict:
    return cell.get("metadata", {}).get("nbgrader", {})


def _exercises(path: Path) -> set:
    """ex06_07_sensor_launch -> {6, 7}: the exercises a notebook covers, from its name."""
    numbers = re.match(r"ex(\d\d)(?:_(\d\d))?_", path.name)
    assert numbers, f"{path.name}: name it exNN_topic.ipynb (or exNN_MM_topic for two exercises done as one step)"
    first, last = int(numbers.group(1)), int(numbers.group(2) or numbers.group(1))
    return set(range(first, last + 1))


def test_every_handout_exercise_has_a_notebook_in_its_assignment():
    for assignment in ASSIGNMENTS:
        covered = set()
        for path in NOTEBOOKS:
            if path.parent.name == assignment:
                covered |= _exercises(path)
        assert covered == EXERCISES[assignment], f"{assignment}: notebooks cover Ex. {sorted(covered)}"


def test_a_notebook_for_two_exercises_says_so_in_its_first_cell():
    for path in NOTEBOOKS:
        numbers = sorted(_exercises(path))
        if len(numbers) > 1:
            first = "".join(_cells(path)[0]["source"])
            assert "covers Ex. {}".format(numbers[0]) in first, f"{path.name}: say which exercises it covers"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_committed_notebook_has_no_outputs_or_execution_counts(path):
    assert notebook_output_problems([path]) == []


def test_output_check_finds_outputs_and_strip_removes_them(tmp_path):
    nb = json.loads(NOTEBOOKS[0].read_text(encoding="utf-8"))
    code = next(c for c in nb["cells"] if c["cell_type"] == "code")
    code["outputs"] = [{"output_type": "stream", "name": "stdout", "text": "hello\n"}]
    code["execution_count"] = 3
    dirty = tmp_path / "dirty.ipynb"
    dirty.write_text(json.dumps(nb), encoding="utf-8")
    assert len(notebook_output_problems([dirty])) == 2
    assert strip_outputs([dirty]) == [dirty]
    assert notebook_output_problems([dirty]) == []


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_nbgrader_cells_are_well_formed(path):
    ids = []
    for cell in _cells(path):
        meta = _nbgrader(cell)
        if not meta:
            assert cell["cell_type"] == "code", f"{path.name}: a markdown cell without nbgrader metadata"
            continue
        assert meta["schema_version"] == 3
        ids.append(meta["grade_id"])
        source = "".join(cell["source"])
        if meta["grade"] and not meta["solution"]:  # autograded test
            assert cell["cell_type"] == "code" and meta["locked"] and meta["points"] > 0, meta["grade_id"]
            assert "BEGIN SOLUTION" not in source
        elif meta["grade"] and meta["solution"]:  # manually graded answer
            assert cell["cell_type"] == "markdown" and meta["points"] > 0 and not meta["locked"], meta["grade_id"]
        elif meta["solution"]:  # the student's code
            assert cell["cell_type"] == "code" and not meta["locked"], meta["grade_id"]
            assert "### BEGIN SOLUTION" in source and "### END SOLUTION" in source, meta["grade_id"]
    assert len(ids) == len(set(ids)), f"{path.name}: grade_ids repeat"
    assert any(_nbgrader(c).get("grade") or "".join(c["source"]).startswith("check.") for c in _cells(path)), \
        f"{path.name}: nothing is graded or checked"


@pytest.mark.parametrize("exercise,question", [(3, "ex3_stop"), (15, "ex15_flowchart")])
def test_handout_questions_are_manually_graded_answers(exercise, question):
    path = next(p for p in NOTEBOOKS if exercise in _exercises(p))
    answers = [_nbgrader(c)["grade_id"] for c in _cells(path) if _nbgrader(c).get("grade") and _nbgrader(c).get("solution")]
    assert question in answers


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_autograded_cells_call_the_toolkit_and_carry_no_logic(path):
    for cell in _cells(path):
        meta = _nbgrader(cell)
        if meta.get("grade") and not meta.get("solution"):
            lines = [line for line in "".join(cell["source"]).splitlines() if line.strip() and not line.startswith("#")]
            assert len(lines) <= 3, f"{path.name} {meta['grade_id']}: a test cell calls a check, it does not compute"
            assert not any(re.match(r"\s*(def|class|for|while|with|import|from)\b", line) for line in lines), \
                f"{path.name} {meta['grade_id']}: no definitions, loops or imports in a test cell"


def test_check_cells_show_each_part_of_the_grader_once_and_carry_no_points():
    """What the check cells show adds up to the checks' points (Ex. 8/9 and 9/12 split a check in two);
    those points are the files' (hri_teleop.grading.points), so the cells carry none."""
    from hri_teleop.grading.checks import CHECKS
    from hri_teleop.grading.exercises.catkin_package import EXERCISE_PARTS
    from hri_teleop.grading.exercises.catkin_package import PARTS as CATKIN_PACKAGE
    from hri_teleop.grading.exercises.graph.judge import PARTS as GRAPH
    from hri_teleop.grading.exercises.mapping_node.judge import PARTS as MAPPING
    from hri_teleop.grading.exercises.robot_params import POINTS
    from hri_teleop.grading.exercises.sensor_launch.judge import PARTS as SENSOR_LAUNCH
    from hri_teleop.grading.exercises.teleoperation.parts import PARTS as TELEOP
    from hri_teleop.grading.exercises.teleoperation_launch.judge import PARTS as TELEOP_LAUNCH
    from hri_teleop.grading.points import check_points

    def total(table, node=None):
        return sum(points for key, (_n, points) in table.items() if node is None or key.startswith("node_") == node)

    expected = {"ex4_file": 1 + sum(POINTS.values()), "ex5_node": total(MAPPING), "ex6_launch": total(SENSOR_LAUNCH),
                "ex8_parts": total(TELEOP, node=False), "ex9_node": total(TELEOP, node=True),
                "ex12_launch": total(TELEOP_LAUNCH), "ex15_graph": total(GRAPH),
                "ex9_package": sum(CATKIN_PACKAGE[k][1] for k in EXERCISE_PARTS[9]),
                "ex12_package": sum(CATKIN_PACKAGE[k][1] for k in EXERCISE_PARTS[12])}
    assert sum(expected.values()) == sum(check_points(c) for c in CHECKS)
    cells = {_nbgrader(c)["grade_id"]: _nbgrader(c) for p in NOTEBOOKS for c in _cells(p) if _nbgrader(c)}
    assert {k: (cells[k]["grade"], cells[k].get("points")) for k in expected} == {k: (False, None) for k in expected}


def test_source_assignments_link_to_the_answer_key():
    for assignment in ASSIGNMENTS:
        link = COURSE_DIR / "source" / assignment / "hri_lab"
        assert link.is_symlink(), f"{link}: must be a link to solutions/hri_lab (python -m hri_teleop.apps.course link)"
        assert link.resolve() == SOLUTIONS.resolve()
        assert not os.path.isabs(os.readlink(link)), "a relative link, so the repository can move"


def test_nbgrader_config_keeps_the_students_files_and_sets_timeouts():
    from traitlets.config import Config

    config = Config()
    namespace = {"get_config": lambda: config, "__file__": str(COURSE_DIR / "nbgrader_config.py")}
    exec(compile((COURSE_DIR / "nbgrader_config.py").read_text(), "nbgrader_config.py", "exec"), namespace)
    assert config.CourseDirectory.course_id
    assert config.Execute.timeout >= 120
    excluded = config.Autograde.exclude_overwriting
    for assignment in ASSIGNMENTS:
        assert set(excluded[assignment]) == set(student_files()) | {"hri_lab/CMakeLists.txt"}
    assert "hri_lab/scripts/mapping_node.py" in excluded["preparation"]
    assert "hri_lab/launch/teleoperation.launch" in excluded["lab"]
    assert exclude_overwriting() == dict(excluded)


def test_nbgrader_ignores_the_scratch_files_notebooks_write_but_not_the_students_files():
    import fnmatch

    from traitlets.config import Config

    config = Config()
    namespace = {"get_config": lambda: config, "__file__": str(COURSE_DIR / "nbgrader_config.py")}
    exec(compile((COURSE_DIR / "nbgrader_config.py").read_text(), "nbgrader_config.py", "exec"), namespace)
    ignore = config.CourseDirectory.ignore

    def ignored(name):
        return any(fnmatch.fnmatch(name, pattern) for pattern in ignore)

    for scratch in ("new_robot_params.yaml", "ex09_pad_script.yaml", "ex10_drive.yaml", "ex14_mine.png", "catkin_ws"):
        assert ignored(scratch), scratch
    for kept in ("robot_params.yaml", "graph.yaml", "mapping_node.py", "teleoperation.launch", "hri_lab"):
        assert not ignored(kept), kept


def test_solution_texts_hold_the_answer_key_and_the_notebook_solutions():
    texts = solution_texts()
    assert any(where.endswith("scripts/mapping_node.py") for where in texts)
    assert any("ex03_parameter_server.ipynb#cell" in where for where in texts)
    flat = [line for lines in texts.values() for line in lines]
    assert any("rospy.get_param" in line for line in flat)


def _points_in(cell_text: str) -> int:
    """Points a README table cell lists: '(2)' each, '(3 × 1)' as 3; the first number of '(10; ...)'."""
    total = 0
    for group in re.findall(r"\(([^()]*)\)", cell_text):
        product = re.match(r"\s*(\d+)\s*×\s*(\d+)", group)
        first = re.match(r"\s*(\d+)\b", group)
        total += int(product.group(1)) * int(product.group(2)) if product else int(first.group(1)) if first else 0
    return total


def test_the_readme_table_gives_each_notebook_the_points_its_cells_carry():
    """The autograded and manual columns are the cells' nbgrader points; the check-cell column names the
    checks a notebook's read-only check cells run, whose points (the files') add up to the checks'.
    The guide's totals per assignment: tests/grading/test_points.py."""
    from hri_teleop.grading.checks import CHECKS
    from hri_teleop.grading.points import CHECK_CELLS, check_points

    readme = (COURSE_DIR / "README.md").read_text(encoding="utf-8")
    rows, shown = {}, {}
    for line in readme.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 6 and cells[0].startswith("`") and "/ex" in cells[0]:
            name = cells[0].strip("`").split("/")[-1]
            rows[name] = (_points_in(cells[3]), _points_in(cells[4]))
            shown[name] = (re.findall(r"`([a-z-]+)`", cells[5]), _points_in(cells[5]))
    actual = {}
    for path in NOTEBOOKS:
        graded = [_nbgrader(c) for c in _cells(path) if _nbgrader(c).get("grade")]
        actual[path.stem] = (sum(m["points"] for m in graded if not m.get("solution")),
                             sum(m["points"] for m in graded if m.get("solution")))
    assert rows == actual
    assert {name: checks for name, (checks, _p) in shown.items()} == {
        path.stem: [c.check for c in CHECK_CELLS if c.notebook == path.stem] for path in NOTEBOOKS}
    assert sum(points for _c, points in shown.values()) == sum(check_points(c) for c in CHECKS)


def test_the_rubric_covers_every_answer_graded_by_hand():
    guide = (COURSE_DIR.parent / "docs" / "instructors.md").read_text(encoding="utf-8")
    rubric = dict(re.findall(r"^\| `(\w+)`[^|]*\| (\d+) \|", guide, re.M))
    manual = {_nbgrader(c)["grade_id"]: str(_nbgrader(c)["points"]) for p in NOTEBOOKS for c in _cells(p)
              if _nbgrader(c).get("grade") and _nbgrader(c).get("solution")}
    assert rubric == manual
