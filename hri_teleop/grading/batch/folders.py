"""``make grade``: every submission in a folder, several at once, each in a process of its own.

:func:`course_layout` picks the mode: an nbgrader course goes to
:mod:`hri_teleop.grading.batch.nbgrader_batch`, any other folder (one subfolder per student) gets
``hri-grade submission`` on each student's package here. Both grade the files with
:func:`grade_one` and run their jobs with :mod:`hri_teleop.grading.run.jobs`; why two modules:
docs/grading-internals.md. The results in ``OUT/``: notebooks/README.md.
"""

from __future__ import annotations

import difflib
import functools
import json
import os
import sys
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.grading.batch.class_results import read_summary, write_rows, write_summary
from hri_teleop.grading.batch.finish import check_policy, find_late_policy, finish
from hri_teleop.grading.batch.report_data import FILES_ONLY
from hri_teleop.grading.cases.inputs import student_seed
from hri_teleop.grading.exercises.registry import exercises
from hri_teleop.grading.judge import reuse
from hri_teleop.grading.run.jobs import (
    Progress,
    Run,
    job_count,
    print_line,
    reap_command,
    run_all,
    run_job,
)
from hri_teleop.grading.run.sandbox import bwrap_problem, sandbox_mode

__all__ = ["BatchError", "Outcome", "submissions_in", "select_student", "grade_one", "live_graph_cache", "course_layout", "grade_all",
           "refresh_folders", "require_sandbox", "unsandboxed_line"]

PER_SUBMISSION_TIMEOUT_S = 600.0    # hri-grade submission: one student's files


class BatchError(HriTeleopError, RuntimeError):
    """The submissions cannot be graded as asked (folder missing or empty, nbgrader missing): one line with the fix."""


@dataclass(frozen=True)
class Outcome:
    """Files-only mode: one student's ``hri-grade submission``."""

    student: str
    score: float
    max_score: float
    status: str          # "graded" | "not graded"
    seconds: float
    message: str = ""
    sandboxed: bool = True   # the student's processes ran in bubblewrap


def require_sandbox(problem: str, unsandboxed: bool, what: str) -> None:
    """BatchError (one line) when ``what`` (the students' notebooks, files) cannot be sandboxed here
    (``problem`` says why) and the instructor did not ask to grade without (``unsandboxed``)."""
    if problem and not unsandboxed:
        raise BatchError(f"bubblewrap cannot sandbox {what} here ({problem}); install bubblewrap and allow user "
                         "namespaces (grading/README.md, Sandbox), or grade with the grader's rights: "
                         "make grade UNSANDBOXED=1 (hri-grade batch --unsandboxed)")


def unsandboxed_line(what: str) -> str:
    """make grade's first line when ``what`` runs without the sandbox."""
    return (f"UNSANDBOXED (make grade UNSANDBOXED=1): {what} run with the grader's rights: they can read the "
            "instructor's files, write outside their folder and reach the network")


def submissions_in(folder: Path) -> List[Path]:
    """One submission per subfolder (nbgrader's submitted/<student>/...), sorted by name."""
    if not folder.is_dir():
        raise BatchError(f"{folder}: no such folder; collect submissions first (nbgrader: notebooks/submitted/) "
                         "or pass the folder, e.g. make grade DIR=path/to/submissions")
    # a link to a folder is listed too, to be refused by name (grade_one), never graded through
    found = sorted(p for p in folder.iterdir() if p.is_dir() and not p.name.startswith("."))
    if not found:
        raise BatchError(f"{folder}: no submission folders in it; expected one subfolder per student")
    return found


def select_student(available: Sequence[str], wanted: Optional[str], folder: Path) -> Optional[str]:
    """``wanted`` when it is one of ``available`` (None: everyone); else BatchError saying how to find the ids."""
    if wanted is None:
        return None
    if wanted in available:
        return wanted
    close = difflib.get_close_matches(wanted, available, n=3)
    hint = f" (did you mean {', '.join(close)}?)" if close else ""
    raise BatchError(f"STUDENT={wanted}: no submission of that id in {folder}{hint}; the ids are the names of its "
                     f"subfolders (ls {folder}) and the student column of grades.csv")



def _hri_grade_argv(folder: Path, out: Path, graph_cache: Optional[Path], checks: Optional[Sequence[str]],
                    seed: Optional[int] = None) -> List[str]:
    # one check at a time: make grade runs submissions side by side already
    argv = [sys.executable, "-m", "hri_teleop.apps.grade", "submission", str(folder), "--json", "--out", str(out),
            "--jobs", "1"]
    if seed is not None:
        argv += ["--seed", str(seed)]
    if graph_cache is not None:
        argv += ["--graph-cache", str(graph_cache)]
    if checks:
        argv += ["--checks", ",".join(checks)]
    return argv


def _files_result(run: Run, log: Path, timeout_s: float) -> Tuple[str, float, float, str]:
    """(status, score, max, message) of one hri-grade submission run."""
    if run.timed_out:
        return "not graded", 0.0, 0.0, f"grading took longer than {timeout_s:.0f} s"
    if run.returncode not in (0, 1):
        tail = log.read_text(errors="replace").strip().splitlines()[-1:] or ["no output"]
        return "not graded", 0.0, 0.0, tail[0][:300]
    try:
        payload = json.loads(run.stdout.decode("utf-8"))
    except ValueError:
        return "not graded", 0.0, 0.0, "the grader printed no JSON"
    maximum = sum(float(t["max_score"]) for t in payload["tests"])
    return "graded", float(payload["score"]), maximum, ""


def grade_one(folder: Path, out: Path, graph_cache: Optional[Path], checks: Optional[Sequence[str]],
              timeout_s: float = PER_SUBMISSION_TIMEOUT_S, results_dir: Optional[Path] = None,
              seed: Optional[int] = None) -> Outcome:
    """``hri-grade submission`` on ``folder`` in a job of its own, into ``out`` (the student is the folder's name).

    ``results_dir``: where it stores each check's result for the notebooks' check cells of the
    same package (:mod:`hri_teleop.grading.judge.reuse`); ``seed``: the hidden inputs' (make grade
    gives the student's, :func:`~hri_teleop.grading.cases.inputs.student_seed`; None: the folder's).
    """
    out.mkdir(parents=True, exist_ok=True)
    log = out / "grader.log"
    if folder.is_symlink():  # the grader follows no link of a submission: it could lead to another student's
        return Outcome(folder.name, 0.0, 0.0, "not graded", 0.0, f"{folder} is a link; put the student's own "
                       "folder there, not a link to one")
    env = {k: v for k, v in os.environ.items() if k not in (reuse.READ_ENV, reuse.WRITE_ENV)}
    if results_dir is not None:
        env[reuse.WRITE_ENV] = str(results_dir)
    run = run_job(_hri_grade_argv(folder, out, graph_cache, checks, seed), log, timeout_s, capture=True, env=env)
    status, score, maximum, message = _files_result(run, log, timeout_s)
    return Outcome(folder.name, score, maximum, status, run.seconds, message)


def live_graph_cache(out: Path, checks: Optional[Sequence[str]]) -> Optional[Path]:
    """What a check reads in every submission (the lab's live graph), computed once into ``out`` by the
    exercise's ``batch_cache``; handed to each ``hri-grade`` as ``--graph-cache``.

    None when ``checks`` (None or empty: all) leaves every exercise with a ``batch_cache`` out.
    """
    caching = [e for e in exercises() if e.batch_cache is not None and (not checks or e.check in checks)]
    if not caching:
        return None
    cache = out / "live_graph.json"
    if cache.exists():
        cache.unlink()  # the lab's graph of today, not of an earlier run
    for found in caching:
        assert found.batch_cache is not None  # for mypy: filtered above
        found.batch_cache(cache)
    return cache


def course_layout(folder: Path) -> Optional[Tuple[Path, Path]]:
    """(course folder, submitted folder) when ``folder`` is an nbgrader course's submissions, else None.

    A course folder holds ``nbgrader_config.py`` or ``source/``; ``folder`` is either its
    ``submitted/`` (any name: nbgrader is told) or the course folder itself.
    """
    folder = Path(folder).resolve()

    def is_course(path: Path) -> bool:
        return (path / "nbgrader_config.py").is_file() or (path / "source").is_dir()

    if (folder / "submitted").is_dir() and is_course(folder):
        return folder, folder / "submitted"
    if is_course(folder.parent):
        return folder.parent, folder
    return None


def grade_all(folder: Path, out: Path, jobs: Optional[int] = None, checks: Optional[Sequence[str]] = None,
              progress: Progress = print_line, timeout_s: Optional[float] = None, student: Optional[str] = None,
              late: Optional[Path] = None, unsandboxed: bool = False) -> int:
    """Grade every student's files in ``folder`` (a subfolder each) into ``out``; 0 when all were graded,
    2 if any could not be. An nbgrader course (:func:`course_layout`) goes to
    :func:`hri_teleop.grading.batch.nbgrader_batch.grade_course` instead (``hri-grade batch`` decides).

    ``student``: grade that one only, keeping everyone else's rows in OUT; ``late``: the late policy
    (default: ``folder``/late.yaml when there is one); ``unsandboxed``: grade even where bubblewrap cannot
    run (:func:`require_sandbox`). Then :func:`~hri_teleop.grading.batch.finish.finish`.
    """
    folder = Path(folder)
    policy = find_late_policy(late, folder)
    check_policy(policy, [FILES_ONLY])
    subs = submissions_in(folder)
    only = select_student([s.name for s in subs], student, folder)
    if only is not None:
        subs = [s for s in subs if s.name == only]
    problem = bwrap_problem()
    require_sandbox(problem, unsandboxed, "the students' files")
    if problem:
        progress(unsandboxed_line("the students' files"))
    out.mkdir(parents=True, exist_ok=True)
    jobs = job_count(jobs)
    limit = timeout_s or PER_SUBMISSION_TIMEOUT_S
    sandbox_mode()  # says once, up front, when bubblewrap is missing
    graph_cache = live_graph_cache(out, checks)
    progress(f"grading {len(subs)} submission(s) from {folder}, {jobs} at once")
    started = time.monotonic()
    outcomes: Dict[str, Outcome] = {}
    width = len(str(len(subs)))

    def done(name: str, outcome: Optional[Outcome], exc: Optional[BaseException]) -> None:
        if outcome is None:  # a bug of ours, recorded; the others go on
            outcome = Outcome(name, 0.0, 0.0, "not graded", 0.0, f"{type(exc).__name__}: {exc}")
        outcome = replace(outcome, sandboxed=not problem)
        outcomes[name] = outcome
        line = f"[{len(outcomes):>{width}}/{len(subs)}] {outcome.student:<24} "
        line += (f"{outcome.score:g}/{outcome.max_score:g}" if outcome.status == "graded"
                 else f"NOT GRADED: {outcome.message}")
        progress(f"{line}  ({outcome.seconds:.1f} s)")

    run_all([(sub.name, functools.partial(grade_one, sub, out / sub.name, graph_cache, checks, limit,
                                          seed=student_seed(sub.name))) for sub in subs], jobs, done)
    ordered = [outcomes[s.name] for s in subs]
    kept = {only} if only is not None else None
    write_rows(out / "grades.csv", ["student", "score", "max_score", "status", "seconds", "message"],
               [{"student": o.student, "score": f"{o.score:g}", "max_score": f"{o.max_score:g}", "status": o.status,
                 "seconds": f"{o.seconds:.1f}", "message": o.message} for o in ordered], kept)
    write_summary(out, [asdict(o) for o in ordered], kept)
    finish(out, policy, lambda name, _assignment: folder / name, progress=progress)
    failed = [o for o in ordered if o.status != "graded"]
    progress(f"graded {len(ordered) - len(failed)}/{len(ordered)} in {time.monotonic() - started:.0f} s; "
             f"results in {out} (grades.csv, report.html, lms.csv, <student>/feedback.txt)")
    return 2 if failed else 0


def refresh_folders(folder: Path, out: Path, progress: Progress = print_line, late: Optional[Path] = None) -> int:
    """``make grade REPORT=1`` on plain folders: nothing graded; the late policy, totals, lms.csv, report again."""
    folder = Path(folder)
    policy = find_late_policy(late, folder)
    check_policy(policy, [FILES_ONLY])
    if not read_summary(out):
        raise BatchError(f"{out}: no results of make grade in it (summary.json); run make grade first, "
                         "or give its folder with OUT=...")
    finish(out, policy, lambda name, _assignment: folder / name, progress=progress)
    return 0


if __name__ == "__main__":  # ``python -m hri_teleop.grading.batch.folders reap -- COMMAND...``: the reaper of jobs.py
    sys.exit(reap_command(sys.argv[1:], "hri_teleop.grading.batch.folders"))
