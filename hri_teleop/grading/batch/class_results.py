"""What ``make grade`` wrote into OUT, read back as report records, and written merged for one student.

The report and lms.csv are computed from OUT (summary.json, each student's results.json, nbgrader's
gradebook), never from a run's memory, so ``make grade STUDENT=id`` can regrade one student and
rebuild them over everyone's results; :func:`write_rows` and :func:`write_summary` keep every
other student's rows as they were.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Set, Tuple

from hri_teleop.grading.batch.late import Lateness
from hri_teleop.grading.batch.report_data import (
    FILES_JOB,
    FILES_ONLY,
    AssignmentScore,
    ClassResults,
    Job,
    PartResult,
    StudentRecord,
)
from hri_teleop.grading.points import assignment_points

__all__ = ["read_class", "notebook_parts", "score_columns", "write_rows", "update_rows", "write_summary",
           "read_summary"]


def read_summary(out: Path) -> List[Dict[str, Any]]:
    """OUT/summary.json's entries ([] when there is none or it is unreadable)."""
    try:
        data = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    return [d for d in data if isinstance(d, dict) and "student" in d] if isinstance(data, list) else []


def write_summary(out: Path, entries: Sequence[Dict[str, Any]], only: Optional[Set[str]] = None) -> None:
    """OUT/summary.json: ``entries``; with ``only`` (the students graded now) the earlier run's other entries stay."""
    kept = [e for e in read_summary(out) if e["student"] not in (only or set())] if only is not None else []
    merged = sorted(kept + list(entries), key=lambda e: str(e["student"]))
    (out / "summary.json").write_text(json.dumps(merged, indent=2), encoding="utf-8")


def _fmt(value: Optional[float]) -> str:
    return "" if value is None else f"{round(value, 6):g}"


def score_columns(jobs: Iterable[Mapping[str, Any]], assignments: Sequence[str]) -> Dict[str, str]:
    """grades.csv's points of one student in a course, from make grade's jobs: ``<assignment>_score``/``_max``
    (its notebooks' plus its files' points, :func:`~hri_teleop.grading.points.assignment_points`),
    ``notebooks_score``/``_max`` (nbgrader's: the check cells carry none) and ``files_score``/``_max``
    (hri-grade's); blank where nothing was graded. Each part counts once: the assignments add up to
    notebooks + files."""
    jobs = list(jobs)
    points = assignment_points(jobs)
    row: Dict[str, str] = {}
    for assignment in assignments:
        score, maximum = points.get(assignment, (None, None))
        row[f"{assignment}_score"], row[f"{assignment}_max"] = _fmt(score), _fmt(maximum)
    for kind in ("notebooks", "files"):
        graded = [j for j in jobs if j["kind"] == kind and j["status"] == "graded"]
        row[f"{kind}_score"] = _fmt(sum(float(j["score"]) for j in graded) if graded else None)
        row[f"{kind}_max"] = _fmt(sum(float(j["max_score"]) for j in graded) if graded else None)
    return row


def write_rows(path: Path, columns: Sequence[str], rows: Sequence[Dict[str, str]],
               only: Optional[Set[str]] = None) -> None:
    """A CSV with one row per student; with ``only`` the earlier file's other rows stay as they were.

    Columns: ``columns``, then any the earlier file had beyond them (its rows keep their values).
    """
    kept: List[Dict[str, str]] = []
    header = list(columns)
    if only is not None and path.is_file():
        with open(path, newline="", encoding="utf-8") as fh:
            reader = csv.DictReader(fh)
            header += [c for c in reader.fieldnames or () if c not in header]
            kept = [r for r in reader if r.get("student") not in only]
    merged = sorted(kept + list(rows), key=lambda r: r["student"])
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=header, restval="")
        writer.writeheader()
        writer.writerows(merged)


def update_rows(path: Path, updates: Sequence[Dict[str, str]], new_columns: Sequence[str] = ()) -> None:
    """grades.csv with the given cells of each student's row replaced (other cells and rows as they were);
    ``new_columns`` go last (added when missing)."""
    if not path.is_file():
        return
    with open(path, newline="", encoding="utf-8") as fh:
        reader = csv.DictReader(fh)
        header = [c for c in reader.fieldnames or () if c not in new_columns] + list(new_columns)
        rows = list(reader)
    by_student = {u["student"]: u for u in updates}
    for row in rows:
        row.update({k: v for k, v in by_student.get(row.get("student", ""), {}).items() if k in header})
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=header, restval="")
        writer.writeheader()
        writer.writerows(rows)


def _parts_of(results_json: Path) -> List[PartResult]:
    try:
        payload = json.loads(results_json.read_text(encoding="utf-8"))
        return [PartResult(str(t["name"]), float(t["score"]), float(t["max_score"])) for t in payload["tests"]]
    except (OSError, ValueError, KeyError, TypeError):
        return []


def notebook_parts(db_url: str, course_id: str,
                   pairs: Iterable[Tuple[str, str]]) -> Dict[Tuple[str, str], List[PartResult]]:
    """The autograded test cells of each graded (student, assignment) in nbgrader's gradebook, one query."""
    from nbgrader.api import (  # noqa: PLC0415 - optional (not on Python 3.8): courses only
        Assignment,
        BaseCell,
        Grade,
        Gradebook,
        Notebook,
        SolutionCell,
        SubmittedAssignment,
        SubmittedNotebook,
    )

    wanted = set(pairs)
    found: Dict[Tuple[str, str], List[PartResult]] = {p: [] for p in wanted}
    with Gradebook(db_url, course_id) as gb:
        written = {(n, c) for n, c in gb.db.query(SolutionCell.notebook_id, SolutionCell.name)}  # graded and a solution: by hand
        query = (gb.db.query(SubmittedAssignment.student_id, Assignment.name, Notebook.name, BaseCell.name,
                             Grade.auto_score, Grade.score, Grade.max_score, Grade.manual_score, Notebook.id)
                 .select_from(Grade)
                 .join(SubmittedNotebook, Grade.notebook_id == SubmittedNotebook.id)
                 .join(SubmittedAssignment, SubmittedNotebook.assignment_id == SubmittedAssignment.id)
                 .join(Assignment, SubmittedAssignment.assignment_id == Assignment.id)
                 .join(Notebook, SubmittedNotebook.notebook_id == Notebook.id)
                 .join(BaseCell, Grade.cell_id == BaseCell.id))
        for student, assignment, notebook, cell, auto, score, maximum, manual, notebook_id in query:
            if (student, assignment) not in wanted or not maximum:
                continue
            item = f"{assignment}/{notebook}: {cell}"
            if (notebook_id, cell) in written:  # a written answer: in the analysis once graded by hand
                found[(student, assignment)].append(PartResult(item, float(score or 0.0), float(maximum),
                                                               manual is not None, manual is None and auto is None))
            elif auto is not None:
                found[(student, assignment)].append(PartResult(item, float(score), float(maximum)))
    for parts in found.values():
        parts.sort(key=lambda p: p.item)
    return found


def _late(entry: Dict[str, Any]) -> Tuple[Lateness, ...]:
    return tuple(Lateness.from_dict(d) for d in entry.get("late", ()))


def _penalty(late: Sequence[Lateness], assignment: str, max_score: Optional[float]) -> float:
    return sum(lt.points(max_score) for lt in late if lt.assignment == assignment)


def _known(late: Sequence[Lateness], assignment: str) -> bool:
    """Whether the late policy knows when ``assignment`` was handed in (True without a policy)."""
    return all(lt.known for lt in late if lt.assignment == assignment)


def _folder_student(out: Path, entry: Dict[str, Any]) -> StudentRecord:
    student, status = str(entry["student"]), str(entry["status"])
    late = _late(entry)
    graded = status == "graded"
    maximum = float(entry["max_score"]) if graded else None
    score = AssignmentScore(FILES_ONLY, float(entry["score"]) if graded else None, maximum,
                            _penalty(late, FILES_ONLY, maximum) if graded else 0.0, _known(late, FILES_ONLY))
    job = Job(student, FILES_ONLY, status, float(entry.get("seconds", 0.0)), str(entry.get("message", "")),
              f"{student}/grader.log", bool(entry.get("sandboxed", True)))
    parts = tuple(_parts_of(out / student / "results.json")) if graded else ()  # none stale from a run before
    return StudentRecord(student, status, (score,), (job,), (job.message,) if not graded else (), parts, late)


def _course_student(out: Path, entry: Dict[str, Any], assignments: Sequence[str],
                    cells: Dict[Tuple[str, str], List[PartResult]]) -> StudentRecord:
    student = str(entry["student"])
    late = _late(entry)
    jobs, scores = [], []
    by_key = {(j["assignment"], j["kind"]): j for j in entry.get("jobs", ())}
    points = assignment_points(entry.get("jobs", ()))
    files_ok = all(j["status"] == "graded" for (_a, kind), j in by_key.items() if kind == "files")
    parts = _parts_of(out / student / "results.json") if files_ok else []  # none stale from a run before
    for assignment in assignments:
        for kind, label, log in (("files", f"{assignment}/{FILES_JOB}", "grader.log"),
                                 ("notebooks", assignment, "autograde.log")):
            j = by_key.get((assignment, kind))
            if j is not None:
                jobs.append(Job(student, label, str(j["status"]), float(j.get("seconds", 0.0)),
                                str(j.get("message", "")), f"{student}/{assignment}/{log}",
                                bool(j.get("sandboxed", True))))
        if assignment not in points:
            continue  # not handed in
        score, maximum = points[assignment]  # its notebooks' and its files' points, each part once
        if score is not None:
            scores.append(AssignmentScore(assignment, score, maximum, _penalty(late, assignment, maximum),
                                          _known(late, assignment)))
        else:
            scores.append(AssignmentScore(assignment, None, None))
        if by_key[(assignment, "notebooks")]["status"] == "graded":
            parts += cells.get((student, assignment), [])
    manual = tuple(a for (a, kind), j in sorted(by_key.items()) if kind == "notebooks" and j.get("needs_manual_grade"))
    return StudentRecord(student, str(entry["status"]), tuple(scores), tuple(jobs),
                         tuple(str(r) for r in entry.get("reasons", ())), tuple(parts), late, manual)


def read_class(out: Path, assignments: Sequence[str] = (), gradebook: Optional[Tuple[str, str]] = None,
               late_policy: str = "") -> ClassResults:
    """OUT read back: summary.json (both modes), each student's results.json, and in a course the
    gradebook's test cells (``gradebook``: nbgrader's database URL and course id)."""
    entries = read_summary(out)
    course = any("jobs" in e for e in entries) or gradebook is not None
    if not course:
        students = tuple(_folder_student(out, e) for e in entries)
        return ClassResults("folders", (FILES_ONLY,), students, late_policy)
    order = list(assignments) or sorted({j["assignment"] for e in entries for j in e.get("jobs", ())})
    cells: Dict[Tuple[str, str], List[PartResult]] = {}
    if gradebook is not None:
        graded = [(str(e["student"]), j["assignment"]) for e in entries for j in e.get("jobs", ())
                  if j["kind"] == "notebooks" and j["status"] == "graded"]
        cells = notebook_parts(gradebook[0], gradebook[1], graded)
    students = tuple(_course_student(out, e, order, cells) for e in entries)
    return ClassResults("course", tuple(order), students, late_policy)
