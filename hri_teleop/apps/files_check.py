"""The files' half of ``make check`` in the student bundle: each assignment's hri_lab graded as the course grades it.

A deliverable's points are the files' (:mod:`hri_teleop.grading.points`). After the notebooks ran, this
grades ``<assignment>/hri_lab`` with the assignment's checks and prints the points per check, reusing the
check cells' results where the same files give the same parts (``HRI_GRADE_RESULTS``): a check runs once.

    python -m hri_teleop.apps.files_check FOLDER [--only ex05,ex12]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

from hri_teleop.grading.assignments import ASSIGNMENT_CHECKS, ASSIGNMENTS
from hri_teleop.grading.judge.checks import grade
from hri_teleop.grading.points import CHECK_CELLS, check_points
from hri_teleop.grading.results import CheckResult, GradingError
from hri_teleop.grading.run.sandbox import SandboxError
from hri_teleop.grading.run.workspace import WorkspaceError

__all__ = ["checks_for", "summary_lines", "main"]

PACKAGE = "hri_lab"


def checks_for(assignment: str, only: Sequence[str] = ()) -> Tuple[str, ...]:
    """The checks of ``assignment``'s files, or of those whose check cell is in a notebook named by ``only``
    (name prefixes, as ``make check ONLY=ex05,ex12``)."""
    wanted = {c.check for c in CHECK_CELLS if c.assignment == assignment
              and (not only or any(c.notebook.startswith(prefix) for prefix in only))}
    return tuple(c for c in ASSIGNMENT_CHECKS.get(assignment, ()) if c in wanted)


def _notebooks_of(assignment: str, check: str) -> str:
    return " / ".join(dict.fromkeys(f"{c.notebook}.ipynb" for c in CHECK_CELLS
                                    if c.assignment == assignment and c.check == check))


def summary_lines(assignment: str, results: Sequence[CheckResult], seconds: float) -> List[str]:
    """One line with each check's points and the assignment's, then one per check that lost points."""
    got, most = sum(r.score for r in results), sum(r.max_score for r in results)
    checks = ", ".join(f"{r.check} {r.score:g}/{r.max_score:g}" for r in results)
    lines = [f"  {assignment}/{PACKAGE}: {checks}: {got:g}/{most:g} points ({seconds:.0f} s)"]
    for r in results:
        if r.score < r.max_score:
            lines.append(f"      {r.check}: {r.score:g}/{r.max_score:g} -- open {_notebooks_of(assignment, r.check)} "
                         "and run its check cell to see why")
    return lines


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="make check", description=__doc__.split("\n")[0])
    parser.add_argument("folder", nargs="?", default=".")
    parser.add_argument("--only", default="", help="comma-separated notebook name prefixes, e.g. ex05,ex12")
    args = parser.parse_args(argv)
    folder = Path(args.folder).resolve()
    only = [p.strip() for p in args.only.split(",") if p.strip()]
    todo: Dict[str, Tuple[str, ...]] = {a: checks_for(a, only) for a in ASSIGNMENTS
                                        if (folder / a / PACKAGE).is_dir() and checks_for(a, only)}
    if not todo:
        return 0
    print("check: your hri_lab files, graded as the course grades them (a check's points are your files'; "
          "the notebooks' check cells show the same feedback and add none)", flush=True)
    got = most = 0.0
    for assignment, checks in todo.items():
        started = time.monotonic()
        results: List[CheckResult] = []
        for check in checks:
            try:
                results.append(grade(check, folder / assignment / PACKAGE))
            except (GradingError, SandboxError, WorkspaceError, OSError) as exc:
                print(f"  {assignment}/{PACKAGE}: {check} not graded: {exc}", flush=True)
                most += check_points(check)
        for line in summary_lines(assignment, results, time.monotonic() - started):
            print(line, flush=True)
        got, most = got + sum(r.score for r in results), most + sum(r.max_score for r in results)
    print(f"check: {got:g}/{most:g} points for your files, beside the notebooks' autograded points above", flush=True)
    return 0

if __name__ == "__main__":
    sys.exit(main())
