"""The files' half of ``make check`` in the student bundle: each assignment's hri_lab graded as the course grades it.

Points per check and, for a check that lost points, each failing part with its feedback (what the
notebook's check cell shows). It reuses the check cells' results where the same files give the same parts
(``HRI_GRADE_RESULTS``), so a check runs once; ``make check`` grades a copy of each assignment folder.

    python -m hri_teleop.apps.files_check FOLDER [--only ex05,ex12]
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import threading
import time
from pathlib import Path
from typing import AbstractSet, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.grading.assignments import ASSIGNMENT_CHECKS, ASSIGNMENTS
from hri_teleop.grading.checks import default_check_jobs, grade
from hri_teleop.grading.judge.reuse import REUSED_NOTE
from hri_teleop.grading.points import CHECK_CELLS, check_points
from hri_teleop.grading.results import CheckResult, GradingError
from hri_teleop.grading.run.jobs import run_all
from hri_teleop.grading.run.sandbox import SandboxError
from hri_teleop.grading.run.workspace import WorkspaceError

__all__ = ["scratch_copy", "checks_for", "summary_lines", "check_lines", "FilesHalf", "check_files", "main"]

PACKAGE = "hri_lab"

#: What a copy of an assignment folder leaves out: the catkin workspace (its build holds the
#: original's absolute paths; the build cells make it again), editor and Python caches, git.
_NOT_COPIED = shutil.ignore_patterns("catkin_ws", ".ipynb_checkpoints", "__pycache__", ".git")
#: What a check that cannot run at all raises (said in one line, its points counted as lost).
_NOT_GRADED = (GradingError, SandboxError, WorkspaceError, OSError)


def scratch_copy(folder: Path, assignment: str, scratch: Path) -> Path:
    """``folder/assignment`` copied to ``scratch/<folder's name>/assignment`` (links kept as links, less
    :data:`_NOT_COPIED`); the folder's entries that are no assignment (the toolkit) linked beside it.
    Returns the copy."""
    top = scratch / folder.name
    top.mkdir(parents=True)
    for entry in folder.iterdir():
        if entry.name not in ASSIGNMENTS:
            os.symlink(entry, top / entry.name)
    shutil.copytree(folder / assignment, top / assignment, symlinks=True, ignore=_NOT_COPIED)
    return top / assignment


def checks_for(assignment: str, only: Sequence[str] = ()) -> Tuple[str, ...]:
    """The checks of ``assignment``'s files, or of those whose check cell is in a notebook named by ``only``
    (name prefixes, as ``make check ONLY=ex05,ex12``)."""
    wanted = {c.check for c in CHECK_CELLS if c.assignment == assignment
              and (not only or any(c.notebook.startswith(prefix) for prefix in only))}
    return tuple(c for c in ASSIGNMENT_CHECKS.get(assignment, ()) if c in wanted)


def _notebooks_of(assignment: str, check: str) -> str:
    return " / ".join(dict.fromkeys(f"{c.notebook}.ipynb" for c in CHECK_CELLS
                                    if c.assignment == assignment and c.check == check))


def check_lines(result: CheckResult, shown_target: str = "") -> List[str]:
    """A check that lost points: its score, then each failing part with its feedback, as its check cell
    shows them (``hri_teleop.grading.results.feedback_text``, the passed parts left out)."""
    lines = [f"      {result.check}: {result.score:g}/{result.max_score:g}"
             + (f" ({shown_target})" if shown_target else "")]
    for part in result.parts:
        if part.passed:
            continue
        lines.append(f"        [FAIL] {part.name} ({part.score:g}/{part.points:g})")
        for text in ([part.note] if part.note else []) + (part.message.splitlines() if part.message else []) \
                + [f"plot: {plot}" for plot in part.plots]:
            lines.append(f"               {text}")
    if result.seed is not None:
        lines.append(f"        (hidden inputs from seed {result.seed}; rerun with --seed {result.seed})")
    lines += [f"        note: {note}" for note in dict.fromkeys(result.notes) if note != REUSED_NOTE]
    return lines


def summary_lines(assignment: str, results: Sequence[CheckResult], seconds: float,
                  shown: Optional[Dict[str, str]] = None) -> List[str]:
    """One line with each check's points and the assignment's, then each check that lost points with its
    failing parts' feedback (``shown``: check -> the file's path as the student knows it)."""
    got, most = sum(r.score for r in results), sum(r.max_score for r in results)
    checks = ", ".join(f"{r.check} {r.score:g}/{r.max_score:g}" for r in results)
    lines = [f"  {assignment}/{PACKAGE}: {checks}: {got:g}/{most:g} points ({seconds:.0f} s)"]
    for r in results:
        if r.score < r.max_score:
            lines += check_lines(r, (shown or {}).get(r.check, ""))
            lines.append(f"        (the same in {_notebooks_of(assignment, r.check)}, check cell; in a terminal: "
                         f"hri-grade {r.check} {assignment}/{PACKAGE})")
    return lines


def _shown_target(result: CheckResult, package: Path, assignment: str) -> str:
    """``<assignment>/hri_lab/<file>`` for a result's target inside ``package`` (a copy or the folder)."""
    if not result.target:
        return ""
    try:
        return f"{assignment}/{PACKAGE}/{Path(result.target).resolve().relative_to(package.resolve())}"
    except ValueError:
        return ""


def _grade_all(package: Path, checks: Sequence[str]) -> Tuple[Dict[str, CheckResult], Dict[str, str]]:
    """Every check of ``checks`` on ``package``, side by side (a stored result is taken at once)."""
    done: Dict[str, CheckResult] = {}
    failed: Dict[str, str] = {}

    def collect(check: str, result: Optional[CheckResult], error: Optional[BaseException]) -> None:
        if result is not None:
            done[check] = result
        elif isinstance(error, _NOT_GRADED):
            failed[check] = str(error)
        elif error is not None:
            raise error

    def one(check: str) -> Callable[[], CheckResult]:
        return lambda: grade(check, package)

    run_all([(check, one(check)) for check in checks], default_check_jobs(os.cpu_count()), collect)
    return done, failed


class FilesHalf:
    """The files' half of one ``make check``: each assignment's package (under ``scratch``, a copy made at
    once, so the run grades the files as they were when it started), the checks no notebook of the run keeps
    a result of graded in the background from the start (:meth:`start`), the rest at the end (:meth:`finish`)."""

    def __init__(self, folder: Path, only: Sequence[str] = (), scratch: Optional[Path] = None) -> None:
        self.todo: Dict[str, Tuple[str, ...]] = {a: checks_for(a, only) for a in ASSIGNMENTS
                                                 if (folder / a / PACKAGE).is_dir() and checks_for(a, only)}
        self.packages = {a: (scratch_copy(folder, a, scratch / a) if scratch else folder / a) / PACKAGE
                         for a in self.todo}
        self.done: Dict[str, Dict[str, CheckResult]] = {a: {} for a in self.todo}
        self.failed: Dict[str, Dict[str, str]] = {a: {} for a in self.todo}
        self.seconds: Dict[str, float] = {a: 0.0 for a in self.todo}
        self._early: Optional[threading.Thread] = None

    def _grade(self, assignment: str, checks: Sequence[str]) -> None:
        started = time.monotonic()
        done, failed = _grade_all(self.packages[assignment], checks)
        self.done[assignment].update(done)
        self.failed[assignment].update(failed)
        self.seconds[assignment] += time.monotonic() - started

    def start(self, kept: Mapping[str, AbstractSet[str]]) -> None:
        """Grade now, beside the notebooks, the checks whose result no notebook of the run keeps
        (``kept``: assignment -> checks whose result a check cell of the run keeps)."""
        early = {a: [c for c in checks if c not in kept.get(a, ())] for a, checks in self.todo.items()}
        early = {a: checks for a, checks in early.items() if checks}
        def grade_early() -> None:
            for assignment, checks in early.items():
                self._grade(assignment, checks)

        if early:
            self._early = threading.Thread(target=grade_early, name="files-half")
            self._early.start()

    def join(self) -> None:
        """Wait for the checks :meth:`start` began."""
        if self._early is not None:
            self._early.join()

    def finish(self) -> Tuple[float, float]:
        """Grade what is left (a kept result is taken at once), print the points and the failing parts'
        feedback; returns (points, possible)."""
        self.join()
        if not self.todo:
            return 0.0, 0.0
        print("check: your hri_lab files, graded as the course grades them (a check's points are your files'; "
              "the notebooks' check cells show the same feedback and add none)", flush=True)
        got = most = 0.0
        for assignment, checks in self.todo.items():
            left = [c for c in checks if c not in self.done[assignment] and c not in self.failed[assignment]]
            if left:
                self._grade(assignment, left)
            for check, reason in self.failed[assignment].items():
                print(f"  {assignment}/{PACKAGE}: {check} not graded: {reason}", flush=True)
                most += check_points(check)
            results = [self.done[assignment][c] for c in checks if c in self.done[assignment]]
            shown = {r.check: _shown_target(r, self.packages[assignment], assignment) for r in results}
            if results:
                print("\n".join(summary_lines(assignment, results, self.seconds[assignment], shown)), flush=True)
            got, most = got + sum(r.score for r in results), most + sum(r.max_score for r in results)
        print(f"check: {got:g}/{most:g} points for your files, beside the notebooks' autograded points above",
              flush=True)
        return got, most


def check_files(folder: Path, only: Sequence[str] = (), scratch: Optional[Path] = None) -> Tuple[float, float]:
    """Grade each assignment's hri_lab under ``folder`` (in a copy under ``scratch`` when given) and print the
    points and the failing parts' feedback; returns (points, possible)."""
    return FilesHalf(folder, only, scratch).finish()


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="make check", description=__doc__.split("\n")[0])
    parser.add_argument("folder", nargs="?", default=".")
    parser.add_argument("--only", default="", help="comma-separated notebook name prefixes, e.g. ex05,ex12")
    args = parser.parse_args(argv)
    check_files(Path(args.folder).resolve(), [p.strip() for p in args.only.split(",") if p.strip()])
    return 0


if __name__ == "__main__":
    sys.exit(main())
