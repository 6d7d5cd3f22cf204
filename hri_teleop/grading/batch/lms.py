"""``lms.csv``: the class's grades as a grade-book CSV that both Canvas and Moodle import.

Canvas matches students by its identity columns and wants them first, in its export's order
(Student, ID, SIS User ID, SIS Login ID, Section); Moodle maps one column of the file to a user
field and each other column to a grade item, and aborts on a row without a user or a grade that is
not a number. So: Canvas's five columns (our student id as Student and SIS Login ID), then one
column per assignment (when there are several) and the total, numbers with a decimal point, a blank
cell for no grade, and no "Points Possible" row (Moodle would read it as a student). grading/README.md.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import List, Optional, Tuple

from hri_teleop.grading.batch.report_data import ClassResults

__all__ = ["IDENTITY_COLUMNS", "ID_COLUMN", "TOTAL_COLUMN", "assignment_column", "lms_table", "write_lms"]

#: Canvas's identity columns, in the order of its gradebook export.
IDENTITY_COLUMNS = ("Student", "ID", "SIS User ID", "SIS Login ID", "Section")
#: The column that holds the student id (Canvas matches on it; map it to Moodle's "username").
ID_COLUMN = "SIS Login ID"
TOTAL_COLUMN = "Task 4 total"


def assignment_column(assignment: str) -> str:
    return f"Task 4 {assignment}"


def _number(value: Optional[float]) -> str:
    """A grade as both import: plain decimal with a point, at most two decimals; blank for none."""
    if value is None:
        return ""
    text = f"{round(value, 2):.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def lms_table(results: ClassResults) -> Tuple[List[str], List[List[str]]]:
    """(header, one row per student by id): scores after late penalties; not graded is blank."""
    several = len(results.assignments) > 1
    header = list(IDENTITY_COLUMNS)
    if several:
        header += [assignment_column(a) for a in results.assignments]
    header.append(TOTAL_COLUMN)
    rows = []
    for student in sorted(results.students, key=lambda s: s.student):
        row = [student.student, "", "", student.student, ""]
        if several:
            finals = {a.assignment: a.final for a in student.assignments}
            row += [_number(finals.get(a)) for a in results.assignments]
        row.append(_number(student.total))
        rows.append(row)
    return header, rows


def write_lms(path: Path, results: ClassResults) -> Path:
    """Write :func:`lms_table` as UTF-8 CSV (no byte-order mark) to ``path``."""
    header, rows = lms_table(results)
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(header)
        writer.writerows(rows)
    return path
