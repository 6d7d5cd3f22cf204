"""What the student-bundle tests share (tests/integration/test_student_bundle.py, tests/container/):
the answer key copied into a bundle, and the points `make check` prints."""

from __future__ import annotations

import json
from pathlib import Path

from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.course.bundle import answer_files
from hri_teleop.course.nodes import STUDENT_PACKAGE
from hri_teleop.course.release import STUDENT_MAKES_EXECUTABLE
from hri_teleop.grading.assignments import ASSIGNMENTS


def copy_answer_key(bundle: Path, course: Path) -> None:
    """What a student who knows every answer hands in: the answer key's files and solution cells."""
    for assignment in ASSIGNMENTS:
        package = bundle / assignment / STUDENT_PACKAGE
        for where, text in answer_files().items():
            relative = Path(where).relative_to(SOLUTIONS)
            if (package / relative).is_file():
                (package / relative).write_text(text)
                if relative.suffix == ".py":
                    (package / relative).chmod(0o755)
        for script in STUDENT_MAKES_EXECUTABLE:  # the handout's chmod +x (Ex. 9, Ex. 12 c)
            if (package / script).is_file():
                (package / script).chmod(0o755)
        for notebook in (bundle / assignment).glob("ex*.ipynb"):
            source = json.loads((course / "source" / assignment / notebook.name).read_text())
            answers = {c["metadata"]["nbgrader"]["grade_id"]: c["source"] for c in source["cells"]
                       if c.get("metadata", {}).get("nbgrader", {}).get("solution")}
            student = json.loads(notebook.read_text())
            for cell in student["cells"]:
                grade_id = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")
                if grade_id in answers:
                    cell["source"] = answers[grade_id]
            notebook.write_text(json.dumps(student))


def notebook_points(output: str) -> dict:
    """notebook -> (points, possible) of make check's notebook lines."""
    scores = {}
    for line in output.splitlines():
        if line.strip().endswith(")") and "points (" in line and ".ipynb ... " in line:
            name = line.split("/")[1].split(".ipynb")[0]
            got, most = line.split(" ... ")[1].split(" points")[0].split("/")
            scores[name.strip()] = (float(got), float(most))
    return scores


def files_points(output: str) -> tuple:
    """(points, possible) of make check's line for the files (the checks' points are the files')."""
    line = next(line for line in output.splitlines() if line.endswith("points for your files, beside the "
                                                                        "notebooks' autograded points above"))
    got, most = line.split("check: ")[1].split(" points")[0].split("/")
    return float(got), float(most)
