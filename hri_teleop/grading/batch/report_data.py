"""The numbers of the class report: typed records of what ``make grade`` wrote, and pure functions over them.

Score distribution, the pass rate of every graded part (worst first), the submissions not judged
with their reason and log, the slowest jobs and the late ones. Nothing here reads a file or draws:
:mod:`~hri_teleop.grading.batch.class_results` reads OUT into these records and
:mod:`~hri_teleop.grading.batch.report` writes the page, so every number is tested here alone.
"""

from __future__ import annotations

import math
import statistics
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

from hri_teleop.grading.batch.late import Lateness

__all__ = ["Job", "AssignmentScore", "PartResult", "StudentRecord", "ClassResults", "Bin", "Stats", "ItemRate",
           "NotJudged", "LateRow", "FILES_ONLY", "FILES_JOB", "histogram", "score_stats", "distributions", "item_rates",
           "pending_items",
           "classify_reason", "not_judged", "slowest", "late_rows", "unused_extensions"]

#: The one "assignment" of a folder graded files-only (no nbgrader course).
FILES_ONLY = "files"
#: A course's files job is labelled "<assignment>/hri_lab" (the student package it grades).
FILES_JOB = "hri_lab"
_EPS = 1e-9


@dataclass(frozen=True)
class Job:
    """One job of a student: ``label`` "files" (plain folders), "<assignment>" (nbgrader) or "<assignment>/hri_lab"."""

    student: str
    label: str
    status: str          # "graded" | "not graded"
    seconds: float
    message: str = ""
    log: str = ""        # where to look, relative to OUT
    sandboxed: bool = True  # the student's code ran in bubblewrap (make grade UNSANDBOXED=1: not)


@dataclass(frozen=True)
class AssignmentScore:
    """A student's points in one assignment (None: not graded) and the late penalty taken from them."""

    assignment: str
    score: Optional[float]
    max_score: Optional[float]
    penalty: float = 0.0
    late_known: bool = True   # False: the late policy holds but the submission time is unknown

    @property
    def final(self) -> Optional[float]:
        """The score after the penalty, never below 0; None when not graded or the penalty is unknown."""
        if self.score is None or not self.late_known:
            return None
        return max(0.0, round(self.score - self.penalty, 6))


@dataclass(frozen=True)
class PartResult:
    """One graded item of one student: a check's part ("robot-params: loads") or a notebook's test cell."""

    item: str
    score: float
    points: float
    #: A written answer (graded by hand in nbgrader): True once graded by hand, False while not (None: autograded).
    by_hand: Optional[bool] = None
    #: A written answer that waits for its grade (no score yet; a blank one scores 0 without grading).
    pending: bool = False

    @property
    def full(self) -> bool:
        return self.score >= self.points - _EPS


@dataclass(frozen=True)
class StudentRecord:
    """Everything the report needs of one student. ``reasons``: why not graded, as make grade recorded it."""

    student: str
    status: str
    assignments: Tuple[AssignmentScore, ...] = ()
    jobs: Tuple[Job, ...] = ()
    reasons: Tuple[str, ...] = ()
    parts: Tuple[PartResult, ...] = ()
    late: Tuple[Lateness, ...] = ()
    manual: Tuple[str, ...] = ()    # assignments with answers still to grade by hand (nbgrader)

    @property
    def graded(self) -> bool:
        return self.status == "graded"

    @property
    def total(self) -> Optional[float]:
        """The sum of the assignments after penalties; None unless the student was graded."""
        finals = [a.final for a in self.assignments]
        if not self.graded or not finals or any(f is None for f in finals):
            return None
        return round(sum(f for f in finals if f is not None), 6)

    @property
    def max_total(self) -> Optional[float]:
        maxima = [a.max_score for a in self.assignments if a.max_score is not None]
        return sum(maxima) if maxima else None


@dataclass(frozen=True)
class ClassResults:
    """A whole batch: ``mode`` "course" (nbgrader) or "folders"; ``late_policy``: its file, "" when none."""

    mode: str
    assignments: Tuple[str, ...]
    students: Tuple[StudentRecord, ...]
    late_policy: str = ""
    notes: Tuple[str, ...] = field(default=())


#: (lower edge, upper edge, students) of one histogram bar.
Bin = Tuple[float, float, int]


@dataclass(frozen=True)
class Stats:
    n: int
    mean: float
    median: float
    low: float
    high: float


@dataclass(frozen=True)
class ItemRate:
    """The class on one item: how many had it, how many got full points, the mean share of its points."""

    item: str
    n: int
    full: int
    mean_fraction: float

    @property
    def rate(self) -> float:
        return self.full / self.n if self.n else 0.0


@dataclass(frozen=True)
class NotJudged:
    student: str
    what: str            # the job's label, or "submission"
    kind: str            # classify_reason
    reason: str
    where: str           # relative to OUT, or an absolute path


@dataclass(frozen=True)
class LateRow:
    student: str
    assignment: str
    lateness: Lateness
    points: float        # taken


def histogram(values: Sequence[float], maximum: float, bins: int = 10) -> List[Bin]:
    """``bins`` equal bars over 0..maximum; a value at the maximum falls in the last bar, outside ones are clipped."""
    if maximum <= 0 or bins <= 0:
        return []
    width = maximum / bins
    counts = [0] * bins
    for value in values:
        counts[min(bins - 1, max(0, int(math.floor(value / width + _EPS))))] += 1
    return [(round(i * width, 9), round((i + 1) * width, 9), counts[i]) for i in range(bins)]


def score_stats(values: Sequence[float]) -> Optional[Stats]:
    if not values:
        return None
    return Stats(len(values), statistics.fmean(values), statistics.median(values), min(values), max(values))


def distributions(results: ClassResults) -> List[Tuple[str, List[float], float]]:
    """(title, scores after penalties of the graded, maximum): one per assignment when there are several,
    then the total. A student counts in an assignment where that assignment was graded."""
    panels: List[Tuple[str, List[float], float]] = []
    if len(results.assignments) > 1:
        for name in results.assignments:
            scores = [a for s in results.students for a in s.assignments if a.assignment == name and a.final is not None]
            maximum = max((a.max_score or 0.0 for a in scores), default=0.0)
            panels.append((name, [a.final for a in scores if a.final is not None], maximum))
    totals = [s for s in results.students if s.total is not None]
    panels.append(("total", [s.total for s in totals if s.total is not None],
                   max((s.max_total or 0.0 for s in totals), default=0.0)))
    return panels


def _items(students: Sequence[StudentRecord]) -> Dict[str, List[PartResult]]:
    seen: Dict[str, List[PartResult]] = {}
    for student in students:
        for part in student.parts:
            seen.setdefault(part.item, []).append(part)
    return seen


def pending_items(students: Sequence[StudentRecord]) -> List[str]:
    """The written answers nobody has graded by hand yet: not in the item analysis until one student's is."""
    return sorted(item for item, parts in _items(students).items()
                  if any(p.by_hand is not None for p in parts) and not any(p.by_hand for p in parts))


def item_rates(students: Sequence[StudentRecord]) -> List[ItemRate]:
    """Every item any student has, with the class's pass rate; worst first (then by name). A written answer
    counts once graded by hand for one student at least (:func:`pending_items`), with the students whose
    answer has its grade (graded by hand, or blank: 0)."""
    waiting = set(pending_items(students))
    rates = []
    for item, parts in _items(students).items():
        graded = [p for p in parts if not p.pending]
        if item in waiting or not graded:
            continue
        rates.append(ItemRate(item, len(graded), sum(p.full for p in graded),
                              statistics.fmean(p.score / p.points if p.points else 1.0 for p in graded)))
    return sorted(rates, key=lambda r: (r.rate, r.mean_fraction, r.item))


#: (words in a reason, its kind): the first that matches.
_KINDS = (
    (("took longer than",), "timeout"),
    (("Kernel didn't respond", "kernel did not start", "Kernel does not exist"), "kernel never started"),
    (("DeadKernelError", "Kernel died", "kernel died"), "kernel died"),
    (("links outside",), "refused (link outside the submission)"),
    (("no assignment folder", "no such file", "was not found", "no submission"), "nothing found"),
    (("generate_feedback failed",), "feedback not generated"),
    (("CellTimeoutError", "CellExecutionError"), "notebook error"),
    (("printed no JSON", "internal error", "Error", "Exception", "Traceback", "killed", "signal"), "crash"),
)


def classify_reason(message: str) -> str:
    """The kind of a not-graded reason as make grade words it (timeout, kernel never started, crash, ...)."""
    for words, kind in _KINDS:
        if any(w in message for w in words):
            return kind
    return "other"


def not_judged(students: Sequence[StudentRecord]) -> List[NotJudged]:
    """Every job that was not graded, and every other recorded reason, with where to look; by student."""
    rows: List[NotJudged] = []
    for student in students:
        messages = set()
        for job in student.jobs:
            if job.status != "graded":
                messages.add(job.message)
                rows.append(NotJudged(student.student, job.label, classify_reason(job.message), job.message,
                                      job.log))
        for reason in student.reasons:
            if any(m and m in reason for m in messages):
                continue  # the job's own row says it
            where = reason.split("(see ", 1)[1].rstrip(")") if "(see " in reason else student.student
            rows.append(NotJudged(student.student, "submission", classify_reason(reason), reason, where))
    return rows


def slowest(students: Sequence[StudentRecord], n: int = 10) -> List[Job]:
    """The ``n`` jobs that took the longest wall time, longest first."""
    jobs = [job for s in students for job in s.jobs]
    return sorted(jobs, key=lambda j: (-j.seconds, j.student, j.label))[:n]


def late_rows(students: Sequence[StudentRecord]) -> List[LateRow]:
    """Every late (student, assignment), with the points taken; latest first. Unknown times are listed too,
    and so is a submission whose own timestamp.txt could not be read (a link, garbage)."""
    rows = []
    for student in students:
        maxima = {a.assignment: a for a in student.assignments}
        for lateness in student.late:
            if lateness.late or lateness.submitted is None or lateness.stamp_refused:
                score = maxima.get(lateness.assignment)
                rows.append(LateRow(student.student, lateness.assignment, lateness,
                                    score.penalty if score is not None else 0.0))
    return sorted(rows, key=lambda r: (-r.lateness.late_s, r.student, r.assignment))


def unused_extensions(extended: Sequence[str], students: Sequence[str]) -> List[str]:
    """Students late.yaml gives an extension to who handed nothing in here (a typo in a name, most likely)."""
    known = set(students)
    return sorted(s for s in extended if s not in known)
