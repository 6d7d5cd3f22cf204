"""The end of ``make grade``: late.yaml applied, then grades.csv's totals, lms.csv and report.html.

Both modes (folders, nbgrader course) end here. The late policy is applied to every student in
OUT each time (a changed late.yaml takes effect with the next run, ``STUDENT=id`` included), its
line goes into the student's feedback, and grades.csv gains the points taken and the total.
"""

from __future__ import annotations

import html
import re
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

from hri_teleop.grading.batch.class_results import read_class, read_summary, update_rows, write_summary
from hri_teleop.grading.batch.late import (
    FEEDBACK_PREFIX,
    LATE_FILE,
    Lateness,
    LatePolicy,
    judge_lateness,
    late_line,
    read_late_policy,
    submission_time,
)
from hri_teleop.grading.batch.report_data import FILES_ONLY, ClassResults
from hri_teleop.grading.batch.student_feedback import add_files_feedback
from hri_teleop.grading.points import assignment_points
from hri_teleop.grading.run.jobs import Progress, print_line

__all__ = ["find_late_policy", "check_policy", "apply_late", "unknown_lines", "set_feedback_lines",
           "mark_feedback_html", "add_totals", "finish", "TOTAL_COLUMNS"]

#: The columns :func:`add_totals` writes at the end of grades.csv.
TOTAL_COLUMNS = ("late_penalty", "total")
#: Where a late line goes in nbgrader's HTML feedback: a block of ours, replaced on a rerun.
_HTML_BLOCK = re.compile(r'<div id="hri-late-policy".*?</div>\n?', re.S)


def find_late_policy(explicit: Optional[Path], home: Path) -> Optional[LatePolicy]:
    """``explicit`` (LATE=...; must exist), else ``home``/late.yaml when there is one, else no policy."""
    if explicit is not None:
        return read_late_policy(explicit)
    default = home / LATE_FILE
    return read_late_policy(default) if default.is_file() else None


def check_policy(policy: Optional[LatePolicy], assignments: Sequence[str]) -> None:
    """LateError before any grading when an assignment has no deadline in the policy."""
    if policy is not None:
        for assignment in assignments:
            policy.deadline_for("", assignment)


def set_feedback_lines(path: Path, lines: Sequence[str]) -> None:
    """``lines`` first in a feedback.txt, replacing the late policy's lines of an earlier run (file made if none)."""
    old = path.read_text(encoding="utf-8").splitlines() if path.is_file() else []
    kept = [line for line in old if not line.startswith(FEEDBACK_PREFIX)]
    while kept and not kept[0].strip():
        kept.pop(0)
    body = list(lines) + ([""] if lines and kept else []) + kept
    if body or path.is_file():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("\n".join(body) + "\n", encoding="utf-8")


def mark_feedback_html(path: Path, line: str) -> None:
    """The late line as the first block of an nbgrader HTML feedback page (escaped; an earlier one replaced)."""
    text = _HTML_BLOCK.sub("", path.read_text(encoding="utf-8"))
    block = (f'<div id="hri-late-policy" style="border:2px solid #c60;padding:.5em;margin:1em">'
             f"{html.escape(line)}</div>\n") if line else ""
    body = re.search(r"<body[^>]*>\n?", text)
    at = body.end() if body else 0
    path.write_text(text[:at] + block + text[at:], encoding="utf-8")


def apply_late(out: Path, policy: Optional[LatePolicy], folder_of: Callable[[str, str], Path],
               feedback_html: Optional[Callable[[str, str], Path]] = None,
               progress: Optional[Progress] = None) -> List[str]:
    """The policy over every student of OUT/summary.json: their ``late`` entries, feedback lines; the students.

    ``folder_of(student, assignment)``: what they handed in (only its timestamp.txt is looked at, to be
    shown; the time comes from the policy's LMS export: :func:`~hri_teleop.grading.batch.late.submission_time`);
    ``feedback_html``: nbgrader's feedback folder of a (student, assignment), whose pages get the line too;
    ``progress``: one line per student whose time is unknown or whose timestamp.txt could not be read.
    """
    entries = read_summary(out)
    for entry in entries:
        student = str(entry["student"])
        handed_in = _handed_in(entry)
        late: List[Lateness] = []
        lines: List[str] = []
        for assignment, max_score in handed_in:
            if policy is None:
                continue
            got = submission_time(policy, student, assignment, folder_of(student, assignment))
            lateness = judge_lateness(policy, student, assignment, got.when, got.shown_source, got.shown_problem,
                                      got.refused)
            late.append(lateness)
            line = late_line(lateness, max_score, with_assignment=assignment != FILES_ONLY)
            lines.append(line)
            if feedback_html is not None:
                for page in sorted(feedback_html(student, assignment).glob("*.html")):
                    mark_feedback_html(page, line)
        entry["late"] = [lt.to_dict() for lt in late]
        set_feedback_lines(out / student / "feedback.txt", lines)
        if progress is not None:
            for line in unknown_lines(student, late):
                progress(line)
    write_summary(out, entries)
    return [str(e["student"]) for e in entries]


def unknown_lines(student: str, late: Sequence[Lateness]) -> List[str]:
    """The run's line for a student whose submission time is unknown (their total left blank), or whose
    timestamp.txt could not be read; none when everything is known and readable."""
    unknown = [lt for lt in late if not lt.known]
    refused = [lt for lt in late if lt.known and lt.stamp_refused]
    lines = []
    if unknown:
        what = "; ".join(f"{lt.assignment}: {lt.problem}" for lt in unknown)
        lines.append(f"late policy: {student}: submission time unknown ({what}); their total stays blank in "
                     "grades.csv and lms.csv: add the time to the LMS export late.yaml's times: names, then "
                     "make grade REPORT=1")
    if refused:
        what = "; ".join(f"{lt.assignment}: {lt.source}" for lt in refused)
        lines.append(f"late policy: {student}: {what}")
    return lines


def _handed_in(entry: Dict[str, Any]) -> List[Tuple[str, Optional[float]]]:
    """(assignment, its points when graded: notebooks and files, each part once) of what one summary entry
    says was handed in."""
    jobs = entry.get("jobs")
    if not isinstance(jobs, list):  # folders mode: one submission
        graded = entry.get("status") == "graded"
        return [(FILES_ONLY, float(entry["max_score"]) if graded else None)]
    return [(assignment, maximum) for assignment, (_score, maximum) in assignment_points(jobs).items()]


def _number(value: Optional[float]) -> str:
    return "" if value is None else f"{round(value, 6):g}"


def add_totals(path: Path, results: ClassResults) -> None:
    """grades.csv's ``late_penalty`` (points taken; "unknown" when a submission time is) and ``total`` (after
    it; blank when not graded or when the penalty is unknown) per student."""
    rows = []
    for record in results.students:
        penalty = sum(a.penalty for a in record.assignments if a.score is not None)
        unknown = any(not lt.known for lt in record.late)
        shown = "unknown" if unknown else _number(penalty) if record.late else ""
        rows.append({"student": record.student, "late_penalty": shown, "total": _number(record.total)})
    update_rows(path, rows, TOTAL_COLUMNS)


def finish(out: Path, policy: Optional[LatePolicy], folder_of: Callable[[str, str], Path],
           assignments: Sequence[str] = (), gradebook: Optional[Tuple[str, str]] = None,
           feedback_html: Optional[Callable[[str, str], Path]] = None, progress: Progress = print_line) -> None:
    """After the jobs: the late policy, grades.csv's totals, lms.csv and report.html over everyone in OUT."""
    # matplotlib only here: every `hri-grade submission` process imports this module
    from hri_teleop.grading.batch.report import write_class_outputs  # noqa: PLC0415 - matplotlib only here

    apply_late(out, policy, folder_of, feedback_html, progress)
    if feedback_html is not None:  # the pages release_feedback ships: the files' points and feedback, no grader paths
        add_files_feedback(out, read_summary(out), folder_of, feedback_html, (out,))
    source = policy.source if policy is not None else ""
    results = read_class(out, assignments, gradebook, source)
    add_totals(out / "grades.csv", results)
    extended = sorted(policy.extensions) if policy is not None else []
    write_class_outputs(out, results, extended, progress)
