"""Where a deliverable's points live: one rule, read by every way of grading (docs/instructors.md, Points).

A file the handout has the students write is judged by a check of the grader, and **its points live in
the files** (make grade's files job, ``hri-grade submission``, Gradescope). A notebook's check cell runs
the same check and shows the same feedback, but it is read-only and worth no nbgrader points, so no part
counts twice and no student kernel produces the files' points. A course's autograded total is its
notebooks' other autograded cells plus its files' checks (:func:`assignment_points`).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.grading.assignments import ASSIGNMENT_CHECKS
from hri_teleop.grading.exercises import registry
from hri_teleop.grading.judge.notebook_answers import has_rule

__all__ = ["POINTS_LIVE_IN", "CheckCell", "CHECK_CELLS", "CHECK_CALL", "part_tables", "check_points",
           "files_points", "is_check_cell", "check_cell_problems", "assignment_points"]

#: The rule: a check's points are counted with the student's files, never in a notebook's cell.
POINTS_LIVE_IN = "files"
#: A line of a notebook cell that runs a check of the grader (``check.mapping_node(PACKAGE)``).
CHECK_CALL = re.compile(r"^\s*check\.\w+\(", re.M)


@dataclass(frozen=True)
class CheckCell:
    """A notebook cell that runs a check on the student's files: read-only, worth no nbgrader points."""

    assignment: str
    notebook: str
    grade_id: str
    check: str
    #: the keys of the check's parts the cell shows (empty: all of them)
    parts: Tuple[str, ...] = ()


#: Every check cell of the course (the notebooks' metadata follows this table: a test says so).
CHECK_CELLS: Tuple[CheckCell, ...] = (
    CheckCell("preparation", "ex04_robot_params", "ex4_file", "robot-params"),
    CheckCell("preparation", "ex05_mapping_node", "ex5_node", "mapping-node"),
    CheckCell("preparation", "ex06_07_sensor_launch", "ex6_launch", "sensor-launch"),
    CheckCell("lab", "ex08_gamepad_commands", "ex8_parts", "teleoperation",
              ("import", "gripper", "twist", "toggle", "rumble")),
    CheckCell("lab", "ex09_teleoperation_node", "ex9_package", "catkin-package", ("teleop_executable", "teleop_cmake")),
    CheckCell("lab", "ex09_teleoperation_node", "ex9_node", "teleoperation",
              ("node_start", "node_twist_topic", "node_width_topic", "node_twist", "node_width", "node_rumble",
               "node_quit")),
    CheckCell("lab", "ex12_13_teleoperation_launch", "ex12_package", "catkin-package", ("gm_executable", "gm_cmake")),
    CheckCell("lab", "ex12_13_teleoperation_launch", "ex12_launch", "teleoperation-launch"),
    CheckCell("lab", "ex15_computation_graph", "ex15_graph", "graph"),
)


def part_tables() -> Dict[str, Dict[str, Tuple[str, float]]]:
    """check -> part key -> (part name as students see it, points), for every check."""
    return {check: dict(table) for check, table in registry.part_tables().items()}


def check_points(check: str) -> float:
    """The points of one check: the sum of its parts'."""
    return float(sum(points for _name, points in part_tables()[check].values()))


def files_points(assignment: str, checks: Optional[Sequence[str]] = None) -> float:
    """The points an assignment's files carry: its checks' (``checks``: only these of them, as CHECKS=a,b)."""
    return sum(check_points(c) for c in ASSIGNMENT_CHECKS.get(assignment, ()) if checks is None or c in checks)


def is_check_cell(grade_id: str) -> bool:
    """True for a notebook cell that runs a check (its points are the files')."""
    return any(cell.grade_id == grade_id for cell in CHECK_CELLS)


def check_cell_problems(source: Path) -> List[str]:
    """Where the notebooks under ``source`` (``source/<assignment>/*.ipynb``) break the rule: a cell that runs
    a check and carries nbgrader points (those points would count a second time), or an autograded test cell
    the grader holds no rule for (only the grader's rules give a notebook's points:
    :mod:`hri_teleop.grading.judge.notebook_answers`). One line each, with the fix."""
    problems = []
    for path in sorted(Path(source).glob("*/*.ipynb")):
        try:
            cells = json.loads(path.read_text(encoding="utf-8")).get("cells", [])
        except (OSError, ValueError, AttributeError):
            continue  # not a notebook nbgrader could read either: nbgrader says so
        for cell in cells:
            meta = cell.get("metadata", {}).get("nbgrader", {})
            text = "".join(cell.get("source", "")) if isinstance(cell.get("source"), list) else str(cell.get("source"))
            if meta.get("grade") and (is_check_cell(str(meta.get("grade_id"))) or CHECK_CALL.search(text)):
                problems.append(f"{path.parent.name}/{path.name}: cell {meta.get('grade_id')} runs a check and carries "
                                f"{meta.get('points', 0)} nbgrader points, which the files carry already; make it a "
                                "read-only cell (nbgrader: grade off, locked on; docs/instructors.md, Points)")
            elif meta.get("grade") and not meta.get("solution") and cell.get("cell_type") == "code" \
                    and not has_rule(str(meta.get("grade_id"))):
                problems.append(f"{path.parent.name}/{path.name}: autograded cell {meta.get('grade_id')} has no rule "
                                f"in the grader, so its {meta.get('points', 0)} points could not be given; hand its "
                                "values in with hand_in and write its rule (docs/instructors.md, A new autograded "
                                "cell)")
    return problems


def _number(job: Mapping[str, Any], key: str) -> float:
    return float(job.get(key) or 0.0)


def assignment_points(jobs: Iterable[Mapping[str, Any]]) -> Dict[str, Tuple[Optional[float], Optional[float]]]:
    """assignment -> (score, max) of one student in a course, from make grade's jobs (``kind`` "notebooks" or
    "files", ``status``, ``score``, ``max_score``): the notebooks' points (nbgrader's; the check cells carry none)
    plus the files' (hri-grade), so each part counts once. (None, None) when a job of the assignment was not
    graded; an assignment without a notebooks job (not handed in) is left out."""
    by_assignment: Dict[str, Dict[str, Mapping[str, Any]]] = {}
    for job in jobs:
        by_assignment.setdefault(str(job["assignment"]), {})[str(job["kind"])] = job
    points: Dict[str, Tuple[Optional[float], Optional[float]]] = {}
    for assignment, kinds in by_assignment.items():
        if "notebooks" not in kinds:
            continue
        if any(job["status"] != "graded" for job in kinds.values()):
            points[assignment] = (None, None)
            continue
        points[assignment] = (sum(_number(j, "score") for j in kinds.values()),
                              sum(_number(j, "max_score") for j in kinds.values()))
    return points
