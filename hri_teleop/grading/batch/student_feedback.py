"""What a student receives: nbgrader's feedback pages with their files' points and feedback, no grader paths.

A notebook whose check cell shows a check's parts gets "Score: 0.0 / 0.0" from nbgrader (the points are
the files': :mod:`hri_teleop.grading.points`), and ``release_feedback`` ships only those pages. So each
page of an assignment gets a block of the grader's (the files' points, and the feedback of the parts the
notebook's check cells show, from the files job), its score counts those parts (an assignment's pages
add up to its points in grades.csv), and no path of the grading machine is left in it.
"""

from __future__ import annotations

import dataclasses
import functools
import html
import json
import os
import re
import tempfile
from pathlib import Path
from typing import Any, Callable, Dict, FrozenSet, Iterable, List, Mapping, Optional, Sequence, Set, Tuple

from hri_teleop.core.paths import REPO
from hri_teleop.grading.points import CHECK_CELLS, CheckCell, part_tables
from hri_teleop.grading.results import CheckResult, feedback_text

__all__ = ["BLOCK_ID", "shown_parts", "notebook_results", "without_grader_paths", "files_block", "mark_page",
           "add_files_feedback"]

#: The id of the grader's block in a page (replaced on every run).
BLOCK_ID = "hri-files-feedback"
_BLOCK = re.compile(rf'<div id="{BLOCK_ID}".*?</div>\n?', re.S)
#: nbgrader's heading, and ours after it (the notebook's own score kept in it, so a rerun starts from it).
_HEADING = re.compile(r"<h4>(?P<name>[^<(]*?) \(Score: (?P<a>-?[\d.]+) / (?P<b>-?[\d.]+)"
                      r"(?:: this notebook's cells (?P<na>-?[\d.]+) / (?P<nb>-?[\d.]+)[^)<]*)?\)</h4>")
#: Folders of a grading machine that a student must not see, besides the course, OUT and the toolkit.
_GENERIC_ROOTS = ("/tmp", "/var/tmp", "/home", "/root", "/srv", "/mnt", "/media", "/run/user", "/work")
_END = r"\s'\"<>&,;:()\[\]{}|`"


def shown_parts(cell: CheckCell) -> Optional[FrozenSet[str]]:
    """The names of the parts a check cell shows (None: all of its check's), as hri_teleop.course.check splits them."""
    if not cell.parts:
        return None
    table = part_tables()[cell.check]
    return frozenset(table[key][0] for key in cell.parts)


def notebook_results(assignment: str, results: Sequence[CheckResult],
                     notebooks: Sequence[str]) -> Tuple[Dict[str, List[CheckResult]], List[CheckResult]]:
    """({notebook: the parts its check cells show, per check}, the parts no notebook of ``notebooks`` shows)."""
    by_notebook: Dict[str, List[CheckResult]] = {}
    claimed: Dict[str, Set[str]] = {}
    for cell in CHECK_CELLS:
        result = next((r for r in results if r.check == cell.check), None)
        if cell.assignment != assignment or cell.notebook not in notebooks or result is None:
            continue
        wanted = shown_parts(cell)
        parts = [p for p in result.parts if wanted is None or p.name in wanted]
        if parts:
            by_notebook.setdefault(cell.notebook, []).append(dataclasses.replace(result, parts=parts))
            claimed.setdefault(cell.check, set()).update(p.name for p in parts)
    rest = [dataclasses.replace(r, parts=[p for p in r.parts if p.name not in claimed.get(r.check, set())])
            for r in results]
    return by_notebook, [r for r in rest if r.parts]


def _short(path: str, submissions: Sequence[str]) -> str:
    """What a student may see of a path of the grading machine."""
    for folder in submissions:
        if path == folder or path.startswith(folder + "/"):
            return path[len(folder) + 1:] or "."
    at = path.rfind("/hri_lab/")
    if at >= 0 or path.endswith("/hri_lab"):
        return path[at + 1:] if at >= 0 else "hri_lab"
    repo = str(REPO)
    if path.startswith(repo + "/"):
        return path[len(repo) + 1:]
    return os.path.basename(path.rstrip("/")) or "."


def without_grader_paths(text: str, submissions: Iterable[Path] = (), roots: Iterable[Path] = ()) -> str:
    """``text`` with every path of the grading machine cut short: a student's own file from its submission
    folder on (``hri_lab/scripts/mapping_node.py``), anything else to its name. ``submissions``: the student's
    submission folders; ``roots``: more folders of the grader's (the course, OUT). ROS names (/force_mapped)
    and system paths (/usr, /opt/ros) stay."""
    subs = sorted({str(p) for s in submissions for p in (Path(s), Path(s).resolve())}, key=len, reverse=True)
    known = {*subs, *(str(p) for r in roots for p in (Path(r), Path(r).resolve())), str(REPO), str(REPO.resolve()),
             tempfile.gettempdir(), str(Path.home()), *_GENERIC_ROOTS}
    pattern = _pattern(tuple(sorted({k.rstrip("/") for k in known if k.rstrip("/").startswith("/")}, key=len,
                                    reverse=True)))

    def cut(m: "re.Match[str]") -> str:
        if m.start() and re.match(r"[\w/.+=-]", text[m.start() - 1]):  # inside a word, a URL or base64 data
            return m.group(0)
        return _short(m.group(0).rstrip("."), subs) + ("." if m.group(0).endswith(".") else "")

    return pattern.sub(cut, text)


@functools.lru_cache(maxsize=32)
def _pattern(roots: Tuple[str, ...]) -> "re.Pattern[str]":
    # "/" first, so that the search skips to each slash (a page is up to megabytes of HTML)
    return re.compile("/(?:" + "|".join(re.escape(k[1:]) for k in roots) + rf")(?=/|[{_END}]|$)[^{_END}]*")


def _text(results: Sequence[CheckResult]) -> str:
    """The feedback of some parts as the files' feedback gives it, without plots (they stay on the grader)."""
    bare = [dataclasses.replace(r, parts=[dataclasses.replace(p, plots=()) for p in r.parts]) for r in results]
    return feedback_text(bare)


def _points(results: Sequence[CheckResult]) -> str:
    return ", ".join(f"{r.check} {r.score:g} / {r.max_score:g}" for r in results)


def files_block(assignment: str, results: Optional[Sequence[CheckResult]], mine: Sequence[CheckResult],
                homeless: Sequence[CheckResult], where: Dict[str, List[str]], not_graded: str = "") -> str:
    """The grader's block of one page (escaped): the assignment's files' points; ``mine``: the parts this page's
    notebook shows, with their feedback; ``homeless``: parts no page shows (given in full here); ``where``: check ->
    the notebooks that show it; ``not_graded``: why the files have no points (their job failed)."""
    e = html.escape
    style = "border:2px solid #36c;padding:.5em;margin:1em"
    if results is None:
        return (f'<div id="{BLOCK_ID}" style="{style}"><p><strong>Your hri_lab files ({e(assignment)}) were not '
                f"graded</strong>: {e(not_graded or 'no result')}. Ask your instructor.</p></div>\n")
    total = sum(r.score for r in results)
    maximum = sum(r.max_score for r in results)
    lines = [f"<p><strong>Your hri_lab files ({e(assignment)}): {total:g} / {maximum:g} points</strong> "
             f"({e(_points(results))}). They count once, with your files, beside the notebooks' points.</p>"]
    if mine:
        lines.append(f"<p>This notebook's check cells show {e(_points(mine))}; the score above counts them. "
                     "The grader's feedback on them:</p>")
        lines.append(f"<pre>{e(_text(mine))}</pre>")
    else:
        shown = [f"{check} in {', '.join(notebooks)}" for check, notebooks in sorted(where.items())]
        if shown:
            lines.append(f"<p>Their feedback is in the pages of the notebooks that check them: {e('; '.join(shown))}."
                         "</p>")
    if homeless:
        lines.append("<p>Parts no notebook of yours shows:</p>")
        lines.append(f"<pre>{e(_text(homeless))}</pre>")
    return f'<div id="{BLOCK_ID}" style="{style}">' + "".join(lines) + "</div>\n"


def _score_heading(text: str, mine: Sequence[CheckResult]) -> str:
    def heading(m: "re.Match[str]") -> str:
        own_a = float(m.group("na") if m.group("na") is not None else m.group("a"))
        own_b = float(m.group("nb") if m.group("nb") is not None else m.group("b"))
        if not mine:
            return f"<h4>{m.group('name')} (Score: {own_a} / {own_b})</h4>"
        got, of = sum(r.score for r in mine), sum(r.max_score for r in mine)
        return (f"<h4>{m.group('name')} (Score: {round(own_a + got, 2)} / {round(own_b + of, 2)}: this notebook's "
                f"cells {own_a} / {own_b}, your hri_lab files' parts it checks {got:g} / {of:g})</h4>")

    return _HEADING.sub(heading, text, count=1)


def mark_page(path: Path, block: str, mine: Sequence[CheckResult], submissions: Sequence[Path],
              roots: Sequence[Path]) -> None:
    """One feedback page: the grader's block (an earlier one replaced), its score, no grader paths."""
    text = _BLOCK.sub("", path.read_text(encoding="utf-8"))
    text = without_grader_paths(_score_heading(text, mine), submissions, roots)
    body = re.search(r'<div class="panel-body">\n?', text) or re.search(r"<body[^>]*>\n?", text)
    at = body.end() if body else 0
    path.write_text(text[:at] + block + text[at:], encoding="utf-8")


def _results(out: Path, student: str, assignment: str) -> Optional[List[CheckResult]]:
    path = out / student / assignment / "checks.json"
    try:
        return [CheckResult.from_dict(d) for d in json.loads(path.read_text(encoding="utf-8"))]
    except (OSError, ValueError, KeyError, TypeError):
        return None


def add_files_feedback(out: Path, entries: Sequence[Mapping[str, Any]], folder_of: Callable[[str, str], Path],
                       feedback_of: Callable[[str, str], Path], roots: Sequence[Path] = ()) -> int:
    """Every feedback page of every student in ``entries`` (make grade's summary.json): the files' block, the
    score, no grader paths. ``folder_of``/``feedback_of``: a (student, assignment)'s submission and nbgrader
    feedback folder; ``roots``: the grader's folders besides (the course, OUT). The pages marked."""
    marked = 0
    roots = list(roots)
    for entry in entries:
        student = str(entry["student"])
        jobs = {(str(j["assignment"]), str(j["kind"])): j for j in entry.get("jobs") or ()}
        submissions = [folder_of(student, a) for a, _k in jobs]
        roots += [c for c in {feedback_of(student, a).parent.parent.parent for a, _k in jobs} if c not in roots]
        for assignment, kind in sorted(jobs):
            handed_in = folder_of(student, assignment)  # a page of a notebook (nbgrader copies other .html too)
            pages = sorted(p for p in feedback_of(student, assignment).glob("*.html")
                           if (handed_in / f"{p.stem}.ipynb").is_file()) if kind == "notebooks" else []
            if not pages:
                continue
            files = jobs.get((assignment, "files"))
            results = _results(out, student, assignment) if files and files["status"] == "graded" else None
            why = without_grader_paths(str(files.get("message", "")), submissions, roots) if files else ""
            notebooks = [p.stem for p in pages]
            by_notebook, homeless = notebook_results(assignment, results or [], notebooks)
            where: Dict[str, List[str]] = {}
            for notebook, shown in sorted(by_notebook.items()):
                for r in shown:
                    where.setdefault(r.check, []).append(notebook)
            for i, page in enumerate(pages):
                mine = by_notebook.get(page.stem, [])
                if files is None:  # no files job (CHECKS without this assignment's): the notebook's score only
                    mark_page(page, "", [], submissions, roots)
                else:
                    block = files_block(assignment, results, mine, homeless if i == 0 else [], where, why)
                    mark_page(page, without_grader_paths(block, submissions, roots), mine, submissions, roots)
                marked += 1
    return marked
