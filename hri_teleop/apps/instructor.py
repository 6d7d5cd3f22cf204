"""The instructor's nbgrader steps after ``make grade`` (docs/instructors.md, The cycle), from a fresh shell.

    python -m hri_teleop.apps.instructor formgrader [DIR] [jupyter lab options...]   make formgrader
    python -m hri_teleop.apps.instructor feedback [DIR] [--out OUT] [--late FILE]      make feedback
    python -m hri_teleop.apps.instructor release-feedback [DIR]                       make release-feedback
    python -m hri_teleop.apps.instructor nbgrader [DIR] ARGS...                       make nbgrader ARGS=...

DIR: the course (default notebooks/) or its submitted/, as for ``make grade``; nbgrader runs from .venv, in the course.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import List, Optional, Sequence, Tuple

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.paths import REPO
from hri_teleop.grading.batch.class_results import read_summary
from hri_teleop.grading.batch.folders import BatchError, course_layout
from hri_teleop.grading.batch.nbgrader_batch import (
    assignment_order,
    generate_feedback,
    nbgrader_config,
    open_course,
    refresh_course,
)

__all__ = ["main", "course_of", "unreleasable", "exchange_problem", "DEFAULT_EXCHANGE"]

#: nbgrader's own default of ``Exchange.root``.
DEFAULT_EXCHANGE = "/srv/nbgrader/exchange"
#: What ``nbgrader release_feedback`` needs in a student's feedback folder (written by ``nbgrader submit``).
RELEASE_NEEDS = ("timestamp.txt", "submission_secret.txt")


def course_of(folder: str) -> Tuple[Path, Path]:
    """(course, submitted) of DIR: the course folder or its submitted/ (BatchError when neither)."""
    path = Path(folder).resolve()
    if (path / "nbgrader_config.py").is_file():  # a course before anything was collected into it
        return path, path / "submitted"
    layout = course_layout(path) if path.is_dir() else None
    if layout is None:
        raise BatchError(f"{folder}: not an nbgrader course (no nbgrader_config.py there or above its submitted/); "
                         "give the course folder with DIR=..., e.g. DIR=notebooks")
    return layout[0], layout[1]


def _formgrader(course: Path, extra: Sequence[str]) -> int:
    from hri_teleop.apps.lab import lab_command  # noqa: PLC0415 - jupyterlab only here
    from hri_teleop.ros.kernel import install_kernelspec  # noqa: PLC0415 - only for the formgrader

    install_kernelspec()  # the formgrader can autograde one submission again: the notebooks' kernel
    command = lab_command(course, ["--ServerApp.default_url=/formgrader", *extra])
    print(f"formgrader: nbgrader's formgrader on {course} (the Formgrader page opens; Ctrl-C ends it)", flush=True)
    os.chdir(course)  # the formgrader reads the course's nbgrader_config.py from its working folder
    os.execv(command[0], command)
    return 0  # pragma: no cover - execv does not return


def _feedback(course: Path, submitted: Path, out: Path, late: Optional[Path]) -> int:
    entries = read_summary(out)
    if not entries:
        raise BatchError(f"{out}: no results of make grade in it (summary.json); run make grade first, "
                         "or give its folder with OUT=...")
    assignments = assignment_order(sorted({str(j["assignment"]) for e in entries for j in e.get("jobs", ())
                                            if j["kind"] == "notebooks" and j["status"] == "graded"}))
    nb = open_course(course, submitted, assignments)
    failed_any = False
    for assignment in assignments:  # the manual points into nbgrader's pages (they are rebuilt, then sanitized)
        ok, failed = generate_feedback(nb, assignment, out)
        failed_any |= not ok or bool(failed)
        print(f"feedback: nbgrader generate_feedback {assignment} -> {course / 'feedback'}/<student>/{assignment}/"
              + (f" (errors for {', '.join(sorted(failed)) or 'some'}: see {out / f'generate_feedback.{assignment}.log'})"
                 if not ok or failed else ""), flush=True)
    code = refresh_course(course, submitted, out, late=late)  # late lines, the files' blocks, grades, report
    return 2 if failed_any else code


def unreleasable(course: Path, assignment: str) -> List[str]:
    """Students whose feedback of ``assignment`` release_feedback cannot ship (not handed in with nbgrader submit)."""
    folders = sorted(p for p in (course / "feedback").glob(f"*/{assignment}") if p.is_dir())
    return [f.parent.name for f in folders if not all((f / name).is_file() for name in RELEASE_NEEDS)]


def exchange_problem(course: Path) -> str:
    """Why nbgrader's exchange of the course cannot take feedback ("" when it can)."""
    config = nbgrader_config(course)
    root = str(config.Exchange.root) if "root" in config.Exchange else DEFAULT_EXCHANGE
    if os.path.isdir(root) and os.access(root, os.W_OK | os.X_OK):
        return ""
    return (f"nbgrader's exchange {root} {'is not writable' if os.path.isdir(root) else 'does not exist'}: create it "
            f"(sudo mkdir -p -m 1777 {root}) or set c.Exchange.root in {course / 'nbgrader_config.py'}; or hand out "
            f"{course / 'feedback'}/<student>/ yourself")


def _release_feedback(course: Path) -> int:
    assignments = assignment_order(sorted({p.name for p in (course / "feedback").glob("*/*/")
                                             if p.is_dir()} if (course / "feedback").is_dir() else set()))
    if not assignments:
        raise BatchError(f"{course / 'feedback'}: no feedback to release; run make grade (and make feedback after "
                         "grading by hand) first")
    problem = exchange_problem(course)
    if problem:
        raise BatchError(problem)
    code = 0
    for assignment in assignments:
        skip = unreleasable(course, assignment)
        if skip:
            print(f"release-feedback: {assignment}: {', '.join(skip)} handed in without nbgrader submit (no "
                  f"{' or '.join(RELEASE_NEEDS)}), so nbgrader cannot release their feedback: hand out "
                  f"{course / 'feedback'}/<student>/{assignment}/ to them yourself", flush=True)
        if len(skip) == len(list((course / "feedback").glob(f"*/{assignment}"))):
            continue
        argv = [sys.executable, "-m", "nbgrader", "release_feedback", assignment]
        if skip:
            argv.append(f"--CourseDirectory.student_id_exclude={','.join(skip)}")
        run = subprocess.run(argv, cwd=course)
        code = code or (2 if run.returncode else 0)
        print(f"release-feedback: {assignment}: " + ("released (students: nbgrader fetch_feedback, or the Assignments "
              "tab)" if run.returncode == 0 else "nbgrader release_feedback failed (its output above)"), flush=True)
    return code


def _nbgrader(course: Path, args: Sequence[str]) -> int:
    if not args:
        raise BatchError("give nbgrader's command in ARGS, e.g. make nbgrader ARGS=\"collect preparation\"")
    return subprocess.run([sys.executable, "-m", "nbgrader", *args], cwd=course).returncode


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if not args or args[0] not in ("formgrader", "feedback", "release-feedback", "nbgrader"):
        print(__doc__, file=sys.stderr)
        return 2
    command, rest = args[0], args[1:]
    folder = rest.pop(0) if rest and not rest[0].startswith("-") and command != "nbgrader" else str(REPO / "notebooks")
    if command == "nbgrader" and rest and rest[0] == "--dir":
        folder, rest = rest[1], rest[2:]
    try:
        import nbgrader  # noqa: F401, PLC0415 - only to say what is missing
    except ImportError:
        print(f"{command}: nbgrader is not installed for {sys.executable}: run `make setup`", file=sys.stderr)
        return 2
    try:
        course, submitted = course_of(folder)
        if command == "formgrader":
            return _formgrader(course, rest)
        if command == "feedback":
            out, late = REPO / "out" / "grades", None
            while rest:
                flag, value = rest.pop(0), rest.pop(0) if rest else ""
                if flag == "--out" and value:
                    out = Path(value).resolve()
                elif flag == "--late" and value:
                    late = Path(value)
                else:
                    raise BatchError(f"feedback: {flag} {value}: give --out OUT or --late FILE")
            return _feedback(course, submitted, out, late)
        if command == "release-feedback":
            return _release_feedback(course)
        return _nbgrader(course, rest)
    except (HriTeleopError, OSError) as exc:  # BatchError, LateError, KernelError: one line each
        print(f"{command}: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
