"""``report.html`` and ``lms.csv`` of a ``make grade`` run: OUT read back, the numbers drawn and tabled.

A thin layer: :mod:`~hri_teleop.grading.batch.report_data` computes, :mod:`hri_teleop.plots.grades`
draws (PNG files beside the page), this writes one self-contained HTML page (no script, no style
sheet or font from the internet) an instructor can open from the results folder or mail to a TA.
"""

from __future__ import annotations

import html
import time
import urllib.parse
from datetime import datetime
from pathlib import Path
from typing import List, Sequence

from hri_teleop.grading.batch.late import duration_text, when_text
from hri_teleop.grading.batch.lms import write_lms
from hri_teleop.grading.batch.report_data import (
    ClassResults,
    distributions,
    histogram,
    item_rates,
    late_rows,
    not_judged,
    pending_items,
    score_stats,
    slowest,
    unused_extensions,
)
from hri_teleop.grading.run.jobs import Progress, print_line
from hri_teleop.plots.grades import pass_rate_chart, score_histogram

__all__ = ["REPORT", "LMS", "SCORES_PNG", "ITEMS_PNG", "write_report", "write_class_outputs", "unsandboxed_note"]

REPORT, LMS = "report.html", "lms.csv"
SCORES_PNG, ITEMS_PNG = "report-scores.png", "report-items.png"
_STYLE = ("body{font-family:sans-serif;margin:2em;max-width:70em}table{border-collapse:collapse;margin:.5em 0 1.5em}"
          "td,th{border:1px solid #ccc;padding:.2em .5em;text-align:left;vertical-align:top}"
          "th{background:#eee}td.n{text-align:right}img{max-width:100%;border:1px solid #ddd}")


def _e(value: object) -> str:
    return html.escape(str(value))


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], numeric: Sequence[int] = ()) -> str:
    """An HTML table; cells are HTML already (escape what comes from files with :func:`_e`)."""
    head = "".join(f"<th>{_e(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td class=n>{c}</td>" if i in numeric else f"<td>{c}</td>"
                                    for i, c in enumerate(row)) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _link(where: str) -> str:
    """A link to a log; a relative one starts with ./ so that a student id like ``javascript:...`` stays a path."""
    if not where:
        return ""
    href = urllib.parse.quote(where if where.startswith("/") else f"./{where}")
    return f'<a href="{_e(href)}">{_e(where)}</a>'


def _scores(results: ClassResults, out: Path) -> str:
    panels = distributions(results)
    score_histogram([(f"{title} (n={len(values)})", histogram(values, maximum), maximum)
                     for title, values, maximum in panels], out / SCORES_PNG)
    rows = []
    for title, values, maximum in panels:
        stats = score_stats(values)
        rows.append([_e(title), str(len(values)), f"{maximum:g}"] + (
            [f"{stats.mean:.1f}", f"{stats.median:g}", f"{stats.low:g}", f"{stats.high:g}"] if stats else [""] * 4))
    penalty = ", after late penalties" if results.late_policy else ""
    return (f"<h2>Score distribution</h2><p>Graded students only{penalty}.</p>"
            f'<img src="{SCORES_PNG}" alt="histogram of scores">'
            + _table(["", "students", "max", "mean", "median", "min", "max scored"], rows, range(1, 7)))


def _items(results: ClassResults, out: Path) -> str:
    rates = item_rates(results.students)
    pass_rate_chart([(r.item, r.rate) for r in rates], out / ITEMS_PNG, "Pass rate of every part, worst first")
    rows = [[_e(r.item), str(r.n), str(r.full), f"{100 * r.rate:.0f}%", f"{100 * r.mean_fraction:.0f}%"]
            for r in rates]
    waiting = pending_items(results.students)
    pending = (f"<p>{len(waiting)} written answer(s) nobody has graded by hand yet are left out until one is "
               f"(<code>make formgrader</code>): {_e(', '.join(waiting))}.</p>") if waiting else ""
    return ("<h2>Item analysis: which parts the class failed</h2><p>Every check's every part (the student files, "
            "<code>results.json</code>), every autograded notebook cell and every written answer graded by hand "
            "(nbgrader's gradebook; of a written answer, the students whose answer has its grade), "
            "worst first. Full points = passed.</p>" + pending +
            f'<img src="{ITEMS_PNG}" alt="pass rate per part">'
            + _table(["part", "students", "full points", "pass rate", "mean share of points"], rows, range(1, 5)))


def _not_judged(results: ClassResults) -> str:
    rows = [[_e(r.student), _e(r.what), _e(r.kind), _e(r.reason), _link(r.where)] for r in not_judged(results.students)]
    if not rows:
        return "<h2>Not judged</h2><p>Every submission was graded.</p>"
    return (f"<h2>Not judged ({len(rows)})</h2><p>Regrade one with <code>make grade STUDENT=id</code> once "
            "the cause is fixed.</p>" + _table(["student", "what", "kind", "reason", "where to look"], rows))


def _manual(results: ClassResults) -> str:
    waiting = [s for s in results.students if s.manual]
    if results.mode != "course" or not waiting:
        return ""
    rows = [[_e(s.student), _e(", ".join(s.manual))] for s in waiting]
    return (f"<h2>Waiting for grading by hand ({len(rows)})</h2><p>Written answers in nbgrader's formgrader "
            "(<code>make formgrader</code>); then <code>make feedback</code> puts those points into the students' "
            "feedback, this page and lms.csv.</p>" + _table(["student", "assignments"], rows))


def _slowest(results: ClassResults) -> str:
    rows = [[_e(j.student), _e(j.label), f"{j.seconds:.1f}", _e(j.status), _link(j.log)]
            for j in slowest(results.students)]
    return "<h2>Slowest submissions (wall time)</h2>" + _table(["student", "job", "seconds", "status", "log"],
                                                               rows, (2,))


def _late(results: ClassResults, extended: Sequence[str]) -> str:
    if not results.late_policy:
        return ("<h2>Late submissions</h2><p>No late policy (<code>make grade LATE=path/to/late.yaml</code>, "
                "or late.yaml beside the course: grading/README.md).</p>")
    rows = []
    for r in late_rows(results.students):
        lt = r.lateness
        zone = lt.deadline.tzinfo
        rows.append([_e(r.student), _e(r.assignment),
                     _e(when_text(lt.submitted, zone)) if lt.submitted else _e(f"unknown: {lt.problem}"), _e(lt.source),
                     _e(when_text(lt.deadline, zone)) + (" (extension)" if lt.extended else ""),
                     _e(duration_text(lt.late_s)) if lt.late else "", f"{lt.days:g}", f"{100 * lt.fraction:.0f}%",
                     f"{r.points:g}"])
    unused = unused_extensions(extended, [s.student for s in results.students])
    note = (f"<p>late.yaml gives an extension to {', '.join(_e(s) for s in unused)}, who handed nothing in here "
            "(a misspelt id?).</p>") if unused else ""
    body = _table(["student", "assignment", "submitted", "from", "deadline", "late by", "days counted", "penalty",
                   "points taken"], rows, (6, 7, 8)) if rows else "<p>Nobody was late.</p>"
    return f"<h2>Late submissions ({len(rows)})</h2><p>Policy: {_e(results.late_policy)}.</p>{note}{body}"


def unsandboxed_note(results: ClassResults) -> str:
    """The report's first line when some student's code ran without the sandbox (make grade UNSANDBOXED=1)."""
    jobs = [j for s in results.students for j in s.jobs if not j.sandboxed]
    if not jobs:
        return ""
    students = sorted({j.student for j in jobs})
    shown = ", ".join(students[:10]) + (f" and {len(students) - 10} more" if len(students) > 10 else "")
    return (f"UNSANDBOXED: the code of {len(students)} student(s) ran with the grader's rights, without "
            f"bubblewrap (make grade UNSANDBOXED=1): {shown} ({', '.join(sorted({j.label for j in jobs}))}). It could "
            "read and write the instructor's files and reach the network; regrade where the sandbox runs to be sure.")


def write_report(out: Path, results: ClassResults, extended: Sequence[str] = (), title: str = "") -> Path:
    """OUT/report.html and its PNG figures from ``results``; its first line says when code ran unsandboxed."""
    graded = sum(s.graded for s in results.students)
    note = unsandboxed_note(results)
    warning = f'<p style="border:2px solid #c00;padding:.5em"><strong>{_e(note)}</strong></p>' if note else ""
    head = warning + (f"<h1>{_e(title or 'make grade: class report')}</h1><p>{len(results.students)} student(s), "
            f"{graded} graded, {len(results.students) - graded} not; "
            f"{'nbgrader course' if results.mode == 'course' else 'student folders'}"
            f" ({_e(', '.join(results.assignments))}); written {datetime.now().isoformat(sep=' ', timespec='seconds')}."
            f" Grades: <a href=grades.csv>grades.csv</a>, for the LMS <a href={LMS}>{LMS}</a>.</p>")
    parts = [head, _scores(results, out), _items(results, out), _not_judged(results), _manual(results),
             _late(results, extended), _slowest(results)]
    page = (f"<!DOCTYPE html><html><head><meta charset=utf-8><title>{_e(title or 'class report')}</title>"
            f"<style>{_STYLE}</style></head><body>{''.join(parts)}</body></html>\n")
    path = out / REPORT
    path.write_text(page, encoding="utf-8")
    return path


def write_class_outputs(out: Path, results: ClassResults, extended: Sequence[str] = (),
                        progress: Progress = print_line) -> List[Path]:
    """lms.csv and report.html (with its figures) over ``results``, every student in OUT."""
    started = time.monotonic()
    lms = write_lms(out / LMS, results)
    report = write_report(out, results, extended)
    progress(f"report: {report} and {lms} ({len(results.students)} student(s), {time.monotonic() - started:.1f} s)")
    return [report, lms]
