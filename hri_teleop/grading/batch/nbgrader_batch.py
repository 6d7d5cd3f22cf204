"""``make grade`` on an nbgrader course: nbgrader's own autograde and feedback, and hri-grade on the files.

``DIR`` is a course's ``submitted/`` or the course folder (:func:`course_layout`). Each (student,
assignment) is a job of its own: nbgrader's ``autograde --force`` (manual grades stay), then
``generate_feedback``, and ``hri-grade submission`` on that assignment's ``hri_lab`` with its
checks. The concurrent autogrades share one SQLite gradebook: a busy timeout and a retry on "database
is locked" keep them apart (docs/grading-internals.md). Results: notebooks/README.md.
"""

from __future__ import annotations

import functools
import json
import os
import re
import shutil
import sys
import tempfile
import threading
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

from jupyter_core.paths import jupyter_config_path
from traitlets.config import Config
from traitlets.config.loader import ConfigFileNotFound, PyFileConfigLoader

from hri_teleop.grading.assignments import ASSIGNMENT_CHECKS, ASSIGNMENTS, nbgrader_env
from hri_teleop.grading.batch.class_results import (
    read_summary,
    score_columns,
    update_rows,
    write_rows,
    write_summary,
)
from hri_teleop.grading.batch.feedback_html import sanitize_feedback
from hri_teleop.grading.batch.finish import check_policy, find_late_policy, finish
from hri_teleop.grading.batch.folders import (
    PER_SUBMISSION_TIMEOUT_S,
    BatchError,
    course_layout,
    grade_one,
    live_graph_cache,
    require_sandbox,
    select_student,
    submissions_in,
    unsandboxed_line,
)
from hri_teleop.grading.batch.notebook_judge import judge_autograded
from hri_teleop.grading.batch.report_data import FILES_JOB
from hri_teleop.grading.batch.spare_kernels import PROVISIONER, PROVISIONER_ENV, SPARES_ENV
from hri_teleop.grading.cases.inputs import SEED_ENV, student_seed
from hri_teleop.grading.judge import reuse
from hri_teleop.grading.points import check_cell_problems
from hri_teleop.grading.results import CheckResult, feedback_text, gradescope_json
from hri_teleop.grading.run.jobs import Progress, job_count, print_line, run_all, run_job
from hri_teleop.grading.run.kernel_sandbox import (
    CHECK_RESULTS,
    ERROR_MARK,
    POLICY_ENV,
    KernelPolicy,
    kernel_sandbox,
)
from hri_teleop.grading.run.sandbox import bwrap_problem, sandbox_mode
from hri_teleop.ros.kernel import install_kernelspec, ipc_kernel_argv

__all__ = ["assignment_order", "nbgrader_config", "open_course", "generate_feedback", "retry_cause", "BatchError", "JobOutcome", "course_layout", "course_submissions", "grade_course", "refresh_course",
           "nbgrader_job_env"]

_NOTEBOOK_TIMEOUT_S = 1800.0        # nbgrader autograde of one (student, assignment); a cell has 300 s of its own
_DB_BUSY_TIMEOUT_S = 60             # SQLite busy timeout of every nbgrader process
_DB_ATTEMPTS = 3                    # autograde runs of one submission when the machine failed it (_RETRY_CAUSES)
#: Notebook kernels start a private roscore only when no master is reachable: never share
#: one (the lab's on 11311, say) between students graded at the same time.
_NO_MASTER = "http://127.0.0.1:1/"


@dataclass(frozen=True)
class JobOutcome:
    """Course mode: one nbgrader autograde (``kind`` "notebooks") or one hri-grade run on the files ("files")."""

    student: str
    assignment: str
    kind: str            # "notebooks" | "files"
    score: float
    max_score: float
    status: str          # "graded" | "not graded"
    seconds: float
    message: str = ""
    needs_manual_grade: bool = False
    sandboxed: bool = True   # the student's code ran in bubblewrap (the kernels; the files' processes)

    @property
    def label(self) -> str:
        return self.assignment if self.kind == "notebooks" else f"{self.assignment}/{FILES_JOB}"


def assignment_order(names: Sequence[str]) -> List[str]:

    known = [a for a in ASSIGNMENTS if a in names]
    return known + sorted(set(names) - set(known))


def course_submissions(course: Path, submitted: Path) -> Tuple[List[Tuple[str, str]], List[str]]:
    """((student, assignment) of every ``submitted/<student>/<assignment>/``, students with no assignment folder).

    BatchError when there is none, or an assignment has no ``source/<assignment>`` in the course.
    """
    students = submissions_in(submitted)
    found: List[Tuple[str, str]] = []
    empty: List[str] = []
    for student in students:
        assignments = sorted(p.name for p in student.iterdir() if p.is_dir() and not p.name.startswith("."))
        if not assignments:
            empty.append(student.name)
        for assignment in assignments:
            if not (course / "source" / assignment).is_dir():
                known = sorted(p.name for p in (course / "source").glob("*") if p.is_dir()) \
                    if (course / "source").is_dir() else []
                raise BatchError(f"{student / assignment}: the course has no source/{assignment} "
                                 f"(assignments in {course / 'source'}: {', '.join(known) or 'none'}); "
                                 "rename the folder to its assignment or add the assignment to the course")
            found.append((student.name, assignment))
    if not found:
        raise BatchError(f"{submitted}: no submissions in it; expected submitted/<student>/<assignment>/ "
                         "(nbgrader collect, or unpack each student's assignment folder there)")
    return found, empty


def nbgrader_config(course: Path) -> Any:
    """nbgrader's configuration as its apps load it: Jupyter's config folders, then the course's file."""
    config = Config()
    for folder in [*reversed(jupyter_config_path()), str(course)]:
        try:
            config.merge(PyFileConfigLoader("nbgrader_config.py", path=folder).load_config())
        except ConfigFileNotFound:
            continue
    return config


def _with_busy_timeout(db_url: str) -> str:
    """The SQLite URL with a busy timeout (writers wait for each other's commit instead of failing)."""
    if not db_url.startswith("sqlite:") or "timeout=" in db_url:
        return db_url
    return f"{db_url}{'&' if '?' in db_url else '?'}timeout={_DB_BUSY_TIMEOUT_S}"


@dataclass(frozen=True)
class Course:
    root: Path
    submitted: Path
    course_id: str
    db_url: str

    def nbgrader_argv(self, *args: str) -> List[str]:
        argv = [sys.executable, "-m", "nbgrader", *args, f"--CourseDirectory.root={self.root}",
                f"--CourseDirectory.db_url={self.db_url}"]
        if self.submitted != self.root / "submitted":
            argv.append(f"--CourseDirectory.submitted_directory={self.submitted.name}")
        return argv


def open_course(course: Path, submitted: Path, assignments: Sequence[str]) -> Course:
    try:
        import nbgrader  # noqa: F401, PLC0415 - optional (not on Python 3.8): courses only
        from nbgrader.api import Gradebook, MissingEntry  # noqa: PLC0415 - optional (not on Python 3.8): courses only
        from nbgrader.coursedir import CourseDirectory  # noqa: PLC0415 - optional (not on Python 3.8): courses only
    except ImportError:
        raise BatchError(f"nbgrader is not installed for {sys.executable}, and {course} is an nbgrader course: "
                         "run `make setup` (nbgrader needs Python >= 3.9)") from None
    config = nbgrader_config(course)
    config.CourseDirectory.root = str(course)
    coursedir = CourseDirectory(config=config)
    db_url = _with_busy_timeout(coursedir.db_url)
    if db_url.startswith("sqlite:///") and not Path(coursedir.db_url[len("sqlite:///"):].split("?")[0]).is_file():
        raise BatchError(f"{course}: no gradebook ({coursedir.db_url}); run `make release` "
                         f"(nbgrader generate_assignment {' '.join(assignments)}) in the course first")
    with Gradebook(db_url, coursedir.course_id) as gb:
        for assignment in assignments:
            try:
                if not gb.find_assignment(assignment).notebooks:
                    raise MissingEntry()
            except MissingEntry:
                raise BatchError(f"assignment {assignment!r} is not in the gradebook {coursedir.db_url}: run "
                                 f"`make release` (nbgrader generate_assignment {assignment}) in {course} first") \
                    from None
    return Course(course, submitted, coursedir.course_id, db_url)


def _outside_links(folder: Path) -> List[str]:
    """Links in a submission that lead outside it (nbgrader copies what a link points at, into the feedback)."""
    found = []
    root = folder.resolve()
    for dirpath, dirnames, filenames in os.walk(folder):
        for name in dirnames + filenames:
            path = Path(dirpath) / name
            if path.is_symlink():
                target = path.resolve()
                if target != root and root not in target.parents:
                    found.append(f"{path.relative_to(folder)} -> {os.readlink(path)}")
    return sorted(found)


def _last_notebook(text: str) -> str:
    found = re.findall(r"Autograding (\S+\.ipynb)", text)
    return Path(found[-1]).name if found else ""


def _failure_reason(log: Path) -> str:
    """The cause of a failed nbgrader run from its log: the exception, and the notebook it ran."""
    text = log.read_text(errors="replace") if log.is_file() else ""
    lines = text.splitlines()
    boxed = [line.split(ERROR_MARK, 1)[1].strip() for line in lines if ERROR_MARK in line]
    if boxed:  # the kernel's sandbox could not start: that is why, whatever nbgrader made of it
        return f"the notebook's kernel could not start in its sandbox: {boxed[-1]}"[:300]
    cause = ""
    starts = [i for i, line in enumerate(lines) if "Traceback (most recent call last):" in line]
    if starts:  # the last line of the last traceback nbgrader logged: the exception
        exceptions = []
        for line in lines[starts[-1] + 1:]:
            if line.startswith("["):
                break
            match = re.match(r"^\s*(?:[A-Za-z_]\w*\.)*([A-Z]\w*(?:: .*)?)$", line)
            if match:
                exceptions.append(match.group(1).strip())
        if exceptions:
            cause = exceptions[-1]
    if not cause:
        errors = [line.split("| ERROR]", 1)[1].strip() for line in lines if "| ERROR]" in line]
        cause = errors[0] if errors else (lines[-1].strip() if lines else "no output")
    notebook = _last_notebook(text)
    where = f" in {notebook}" if notebook else ""
    return f"nbgrader autograde failed{where}: {cause}"[:300]


def nbgrader_job_env(base: Optional[Mapping[str, str]] = None) -> Dict[str, str]:
    """What each nbgrader autograde runs in: assignments.nbgrader_env, and no reachable ROS master,
    so that every kernel starts a private roscore (benchmarks run their reference in the same)."""

    return dict(nbgrader_env(base), ROS_MASTER_URI=_NO_MASTER)


def _submission_score(course: Course, lock: threading.Lock, student: str,
                      assignment: str) -> Tuple[float, float, bool]:
    from nbgrader.api import Gradebook  # noqa: PLC0415 - optional (not on Python 3.8): courses only

    with lock:
        gb = Gradebook(course.db_url, course.course_id)
        try:
            sub = gb.find_submission(assignment, student)
            return float(sub.score), float(sub.max_score), bool(sub.needs_manual_grade)
        finally:
            gb.close()
            gb.engine.dispose()


def _forget_outputs(course: Course, student: str, assignment: str) -> None:
    """A submission that was not graded has no autograded notebooks and no feedback (none stale either)."""
    from nbgrader.utils import rmtree  # noqa: PLC0415 - optional (not on Python 3.8): courses only

    for kind in ("autograded", "feedback"):
        folder = course.root / kind / student / assignment
        if folder.exists():
            rmtree(str(folder))
        try:
            folder.parent.rmdir()  # the student's folder, when this was its only assignment
        except OSError:
            pass


#: Failures of the grading machine, not of the submission: the run is repeated (``--force`` starts it clean).
#: A kernel that never answers its first request has run none of the student's code yet
#: (under load, two kernels started at once can lose their connection on a busy loopback).
_RETRY_CAUSES = (("database is locked", "the gradebook was locked"),
                 ("Kernel didn't respond in", "the notebook's kernel did not start"))


def retry_cause(log_text: str) -> str:
    """Why an autograde run is worth repeating ("" when the failure is the submission's)."""
    return next((why for needle, why in _RETRY_CAUSES if needle in log_text), "")


def _autograde(course: Course, student: str, assignment: str, out: Path, timeout_s: float,
               db_lock: threading.Lock, progress: Progress, results_dir: Optional[Path] = None,
               sandbox: Optional[KernelPolicy] = None, seed: Optional[int] = None) -> JobOutcome:
    folder = course.submitted / student / assignment
    links = _outside_links(folder)
    if links:
        _forget_outputs(course, student, assignment)
        return JobOutcome(student, assignment, "notebooks", 0.0, 0.0, "not graded", 0.0,
                          f"{links[0]} links outside the submission (nbgrader would copy that file into the "
                          "feedback); the student must hand in the file itself", sandboxed=sandbox is not None)
    sockets = Path(tempfile.mkdtemp(prefix="hri-kernel-"))  # the kernels' Unix sockets (no TCP port race)
    try:
        return autograde_in(course, student, assignment, out, timeout_s, db_lock, progress,
                             course.nbgrader_argv("autograde", assignment, "--student", student, "--force",
                                                  *ipc_kernel_argv(sockets)), results_dir, sandbox, seed)
    finally:
        shutil.rmtree(sockets, ignore_errors=True)


def autograde_in(course: Course, student: str, assignment: str, out: Path, timeout_s: float,
                  db_lock: threading.Lock, progress: Progress, argv: List[str],
                  results_dir: Optional[Path] = None, sandbox: Optional[KernelPolicy] = None,
                  seed: Optional[int] = None) -> JobOutcome:
    """``results_dir``: the files jobs' check results, which the notebooks' check cells of the
    same package take instead of running the check again (:mod:`hri_teleop.grading.judge.reuse`).
    ``sandbox``: the kernels start in the kernel sandbox (None: with the grader's rights). ``seed``:
    the check cells' hidden inputs (None: the student's, as the files job's)."""
    log = out / "autograde.log"
    seconds = 0.0
    env = nbgrader_job_env()
    env[SEED_ENV] = str(student_seed(student) if seed is None else seed)
    env.pop(reuse.WRITE_ENV, None)
    env.pop(POLICY_ENV, None)
    if results_dir is not None:
        env[reuse.READ_ENV] = str(results_dir)
    if sandbox is not None:  # the box holds a copy of this submission's results, where the kernel reads them
        env[POLICY_ENV] = replace(sandbox, check_results=str(results_dir or "")).to_json()
        if results_dir is not None:
            env[reuse.READ_ENV] = CHECK_RESULTS
    # Each notebook's kernel starts while the one before runs (hri_teleop.grading.batch.spare_kernels).
    env[PROVISIONER_ENV] = PROVISIONER
    env[SPARES_ENV] = str(max(0, len(list((course.root / "source" / assignment).glob("*.ipynb"))) - 1))
    for attempt in range(1, _DB_ATTEMPTS + 1):
        run = run_job(argv, log, timeout_s, cwd=course.root, env=env)
        seconds += run.seconds
        if run.timed_out:
            _forget_outputs(course, student, assignment)
            notebook = _last_notebook(log.read_text(errors="replace"))
            return JobOutcome(student, assignment, "notebooks", 0.0, 0.0, "not graded", seconds,
                              f"nbgrader autograde took longer than {timeout_s:.0f} s (stopped"
                              + (f" in {notebook})" if notebook else ")"), sandboxed=sandbox is not None)
        if run.returncode == 0:  # the kernel reported; the grader judges each autograded cell (notebook_judge)
            problem = judge_autograded(course.root, course.db_url, course.course_id, student, assignment, db_lock)
            if problem:
                _forget_outputs(course, student, assignment)
                return JobOutcome(student, assignment, "notebooks", 0.0, 0.0, "not graded", seconds, problem,
                                  sandboxed=sandbox is not None)
            score, maximum, manual = _submission_score(course, db_lock, student, assignment)
            return JobOutcome(student, assignment, "notebooks", score, maximum, "graded", seconds, "", manual,
                              sandboxed=sandbox is not None)
        cause = retry_cause(log.read_text(errors="replace"))
        if cause and attempt < _DB_ATTEMPTS:
            shutil.copy(log, log.with_name(f"autograde.attempt{attempt}.log"))
            progress(f"      {student} {assignment}: {cause}; autograding again "
                     f"(attempt {attempt + 1} of {_DB_ATTEMPTS})")
            continue
        break
    _forget_outputs(course, student, assignment)
    return JobOutcome(student, assignment, "notebooks", 0.0, 0.0, "not graded", seconds, _failure_reason(log),
                      sandboxed=sandbox is not None)


def autograde_one(course_root: Path, student: str, assignment: str, out: Path, timeout_s: float,
                  progress: Progress = print_line, sandbox: Optional[KernelPolicy] = None,
                  seed: Optional[int] = None) -> JobOutcome:
    """nbgrader autograde of one student's one assignment in the course folder ``course_root`` (its
    ``submitted/<student>/<assignment>/`` and gradebook), as make grade runs it (the Gradescope autograder).
    ``sandbox``: the kernels' sandbox (the course folder is hidden from them too); None: none. ``seed``: the
    check cells' hidden inputs (None: :func:`~hri_teleop.grading.cases.inputs.student_seed` of ``student``)."""
    course = open_course(course_root, course_root / "submitted", [assignment])
    out.mkdir(parents=True, exist_ok=True)
    if sandbox is not None:
        sandbox = replace(sandbox, hidden=(*sandbox.hidden, str(course.root), str(out)))
    return _autograde(course, student, assignment, out, timeout_s, threading.Lock(), progress, None, sandbox, seed)


def grade_files(course: Course, student: str, assignment: str, out: Path, checks: Sequence[str],
                 graph_cache: Optional[Path], timeout_s: float, results_dir: Optional[Path] = None) -> JobOutcome:
    o = grade_one(course.submitted / student / assignment, out, graph_cache, checks, timeout_s, results_dir,
                  seed=student_seed(student))
    return JobOutcome(student, assignment, "files", o.score, o.max_score, o.status, o.seconds, o.message,
                      sandboxed=not bwrap_problem())


def generate_feedback(course: Course, assignment: str, out: Path,
                       student: Optional[str] = None) -> Tuple[bool, Dict[str, str]]:
    """``nbgrader generate_feedback`` for every autograded student of ``assignment`` (or ``student`` only):
    (ok, {student: failure})."""
    log = out / f"generate_feedback.{assignment}.log"
    only = ["--student", student] if student is not None else []
    run = run_job(course.nbgrader_argv("generate_feedback", assignment, "--force", *only), log, 600.0,
                  cwd=course.root, env=nbgrader_job_env())
    for folder in sorted((course.root / "feedback").glob(f"*/{assignment}")):  # no student's script runs there
        if student is None or folder.parent.name == student:
            with log.open("a", encoding="utf-8") as fh:
                fh.writelines(f"feedback {folder / rel} not kept: {why}\n" for rel, why in sanitize_feedback(folder))
    text = log.read_text(errors="replace")
    failed = {m.group(2): "nbgrader generate_feedback failed (see " + str(log) + ")"
              for m in re.finditer(r"error processing assignment '([^']+)' for student '([^']+)'", text)}
    return run.returncode == 0, failed


def _combine_files_results(student_out: Path, assignments: Sequence[str]) -> None:
    """``OUT/<student>/results.json`` and ``feedback.txt``: the checks of all the student's assignments together."""
    results, parts = [], []
    for assignment in assignments:
        checks = student_out / assignment / "checks.json"
        if checks.is_file():
            these = [CheckResult.from_dict(d) for d in json.loads(checks.read_text(encoding="utf-8"))]
            results += these
            parts.append(f"== {assignment}: {assignment}/{FILES_JOB} ==\n{feedback_text(these)}")
    if results:
        (student_out / "results.json").write_text(json.dumps(gradescope_json(results), indent=2), encoding="utf-8")
        (student_out / "feedback.txt").write_text("\n\n".join(parts) + "\n", encoding="utf-8")


def grade_course(course: Path, submitted: Path, out: Path, jobs: Optional[int] = None,
                 checks: Optional[Sequence[str]] = None, progress: Progress = print_line,
                 timeout_s: Optional[float] = None, student: Optional[str] = None,
                 late: Optional[Path] = None, unsandboxed: bool = False) -> int:
    """nbgrader autograde + generate_feedback of every submission of the course, and hri-grade on its files.

    ``checks`` limits the files' checks (each assignment gets those of its own among
    them); ``timeout_s`` limits each (student, assignment) job. 0 when everything was
    graded, 2 when anything could not be (the reason is in grades.csv). ``student``: that
    one only (everyone else's rows kept); ``late``: the late policy (default: the course's late.yaml);
    ``unsandboxed``: the notebooks' kernels run with the grader's rights (else in the kernel sandbox, and
    BatchError where it cannot run).
    """
    course, submitted, out = Path(course).resolve(), Path(submitted).resolve(), Path(out).resolve()
    policy = find_late_policy(late, course)
    pairs, empty = course_submissions(course, submitted)
    only = select_student(sorted({s for s, _a in pairs} | set(empty)), student, submitted)
    if only is not None:
        pairs, empty = [p for p in pairs if p[0] == only], [s for s in empty if s == only]
    assignments = assignment_order(sorted({a for _s, a in pairs}))
    check_policy(policy, assignments)
    nb = open_course(course, submitted, assignments)
    counted_twice = check_cell_problems(course / "source")
    if counted_twice:  # a check's points are the files': a graded check cell would count them again
        raise BatchError(counted_twice[0])
    # The kernels see neither the course (other students, the gradebook, the answers) nor OUT.
    sandbox, problem = (None, "") if unsandboxed else kernel_sandbox(KernelPolicy((str(course), str(out))))
    require_sandbox(problem, unsandboxed, "the students' notebooks")
    if sandbox is None:
        progress(unsandboxed_line("the students' notebooks" + (" and files" if bwrap_problem() else "")))
    install_kernelspec()  # the notebooks' kernel "hri-teleop" (.venv's Python in the lab's shell)
    out.mkdir(parents=True, exist_ok=True)
    jobs = job_count(jobs)
    notebook_limit = timeout_s or _NOTEBOOK_TIMEOUT_S
    files_limit = timeout_s or PER_SUBMISSION_TIMEOUT_S
    files_checks = {a: [c for c in ASSIGNMENT_CHECKS.get(a, ()) if not checks or c in checks] for a in assignments}
    sandbox_mode()  # says once, up front, when bubblewrap is missing
    wanted = sorted({c for cs in files_checks.values() for c in cs})
    graph_cache = live_graph_cache(out, wanted) if wanted else None
    students = sorted({s for s, _a in pairs} | set(empty))
    db_lock = threading.Lock()

    # The files first: each check result they store is taken by the notebooks' check cells of the
    # same package instead of running the check a second time. Then the notebooks, the lab's
    # (longest) first.
    results_dir = out / ".check-results"  # <student>/<assignment>/: a box gets its submission's only
    shutil.rmtree(results_dir, ignore_errors=True)  # results of this run only, never an older grader's
    order = {a: i for i, a in enumerate(reversed(assignments))}
    tasks: List[Tuple[str, Callable[[], JobOutcome]]] = []
    for student, assignment in sorted(pairs, key=lambda p: (order[p[1]], p[0])):
        if files_checks[assignment]:
            tasks.append((f"{student}\0{assignment}\0files",
                          functools.partial(grade_files, nb, student, assignment, out / student / assignment,
                                            files_checks[assignment], graph_cache, files_limit,
                                            results_dir / student / assignment)))
    for student, assignment in sorted(pairs, key=lambda p: (order[p[1]], p[0])):
        tasks.append((f"{student}\0{assignment}\0notebooks",
                      functools.partial(_autograde, nb, student, assignment, out / student / assignment, notebook_limit,
                                        db_lock, progress, results_dir / student / assignment, sandbox)))
    progress(f"autograding {len(pairs)} submission(s) of {len(students)} student(s) in {course} with nbgrader "
             f"({', '.join(assignments)}), and their {FILES_JOB} files; {jobs} at once")
    started = time.monotonic()
    outcomes: Dict[str, JobOutcome] = {}
    width = len(str(len(tasks)))

    def done(key: str, outcome: Optional[JobOutcome], exc: Optional[BaseException]) -> None:
        if outcome is None:  # a bug of ours, recorded; the others go on
            student, assignment, kind = key.split("\0")
            outcome = JobOutcome(student, assignment, kind, 0.0, 0.0, "not graded", 0.0,
                                 f"{type(exc).__name__}: {exc}")
        outcomes[key] = outcome
        what = (f"{outcome.score:g}/{outcome.max_score:g}" if outcome.status == "graded"
                else f"NOT GRADED: {outcome.message}")
        progress(f"[{len(outcomes):>{width}}/{len(tasks)}] {outcome.student} {outcome.label} {what} "
                 f"({outcome.seconds:.1f} s)")

    run_all(tasks, jobs, done)

    feedback_problems: Dict[Tuple[str, str], str] = {}
    for assignment in assignments:
        graded = [o.student for o in outcomes.values()
                  if o.assignment == assignment and o.kind == "notebooks" and o.status == "graded"]
        if not graded:
            continue
        ok, failed = generate_feedback(nb, assignment, out, only)
        for student, why in failed.items():
            feedback_problems[(student, assignment)] = why
        problems = "" if ok else f"; errors, see {out / f'generate_feedback.{assignment}.log'}"
        progress(f"feedback: nbgrader generate_feedback {assignment} -> {course / 'feedback'}/<student>/{assignment}/ "
                 f"({len(graded) - len(failed)} student(s){problems})")

    rows, summary = [], []
    for student in students:
        mine = {(o.assignment, o.kind): o for o in outcomes.values() if o.student == student}
        # Each part counts once: an assignment's points are its notebooks' plus its files' (grading/points.py).
        row: Dict[str, str] = {"student": student, **score_columns([asdict(o) for o in mine.values()], assignments)}
        reasons: List[str] = []
        for assignment in assignments:
            o = mine.get((assignment, "notebooks"))
            if o is None:
                continue
            if o.status != "graded":
                reasons.append(f"{assignment}: {o.message}")
            f = mine.get((assignment, "files"))
            if f is not None and f.status != "graded":
                reasons.append(f"{assignment}/{FILES_JOB}: {f.message}")
            if (student, assignment) in feedback_problems:
                reasons.append(f"{assignment}: {feedback_problems[(student, assignment)]}")
        if student in empty:
            reasons.append(f"no assignment folder in {submitted / student} "
                           f"(expected {submitted.name}/{student}/<assignment>/)")
        _combine_files_results(out / student, assignments)
        status = "not graded" if reasons else "graded"
        row.update({"needs_manual_grade": " ".join(a for (a, k), o in sorted(mine.items())
                                                   if k == "notebooks" and o.needs_manual_grade),
                    "status": status, "seconds": f"{sum(o.seconds for o in mine.values()):.1f}",
                    "message": "; ".join(reasons)})
        rows.append(row)
        summary.append({"student": student, "status": status, "reasons": reasons,
                        "jobs": [asdict(o) for _k, o in sorted(mine.items())],
                        "feedback": {a: str(course / "feedback" / student / a) for (a, k), o in sorted(mine.items())
                                     if k == "notebooks" and o.status == "graded"
                                     and (student, a) not in feedback_problems}})
    everyone = assignment_order(sorted(set(assignments) | {str(j["assignment"]) for e in read_summary(out)
                                                              if only is not None for j in e.get("jobs", ())}))
    columns = ["student", *[f"{a}_{x}" for a in everyone for x in ("score", "max")], "notebooks_score",
               "notebooks_max", "files_score", "files_max", "needs_manual_grade", "status", "seconds", "message"]
    kept = {only} if only is not None else None
    write_rows(out / "grades.csv", columns, rows, kept)
    write_summary(out, summary, kept)
    finish(out, policy, lambda name, assignment: submitted / name / assignment, everyone, (nb.db_url, nb.course_id),
           lambda name, assignment: course / "feedback" / name / assignment, progress)
    not_graded = [r for r in rows if r["status"] != "graded"]
    manual = [r for r in rows if r["needs_manual_grade"]]
    progress(f"graded {len(rows) - len(not_graded)}/{len(rows)} student(s) in {time.monotonic() - started:.0f} s; "
             f"gradebook {nb.db_url.split('?')[0]}, results in {out} (grades.csv, report.html, lms.csv, "
             "<student>/feedback.txt)"
             + (f"; {len(manual)} with answers to grade by hand (make formgrader, then make feedback)" if manual else ""))
    return 2 if not_graded else 0


def refresh_course(course: Path, submitted: Path, out: Path, progress: Progress = print_line,
                   late: Optional[Path] = None) -> int:
    """``make grade REPORT=1``: nothing graded; the gradebook's scores now (after grading by hand) into
    OUT's summary.json and grades.csv, then the late policy, totals, lms.csv and report.html again."""
    course, submitted, out = Path(course).resolve(), Path(submitted).resolve(), Path(out).resolve()
    policy = find_late_policy(late, course)
    entries = read_summary(out)
    if not entries:
        raise BatchError(f"{out}: no results of make grade in it (summary.json); run make grade first, "
                         "or give its folder with OUT=...")
    assignments = assignment_order(sorted({str(j["assignment"]) for e in entries for j in e.get("jobs", ())}))
    check_policy(policy, assignments)
    nb = open_course(course, submitted, assignments)
    lock = threading.Lock()
    for entry in entries:
        for job in entry.get("jobs", ()):
            if job["kind"] == "notebooks" and job["status"] == "graded":
                job["score"], job["max_score"], job["needs_manual_grade"] = _submission_score(
                    nb, lock, str(entry["student"]), str(job["assignment"]))
    write_summary(out, entries)
    rows = []
    for entry in entries:
        graded = {j["assignment"]: j for j in entry.get("jobs", ()) if j["kind"] == "notebooks"
                  and j["status"] == "graded"}
        row = {"student": str(entry["student"]),
               "needs_manual_grade": " ".join(a for a, j in sorted(graded.items()) if j["needs_manual_grade"]),
               **score_columns(entry.get("jobs", ()), assignments)}
        rows.append(row)
    update_rows(out / "grades.csv", rows)
    finish(out, policy, lambda name, assignment: submitted / name / assignment, assignments, (nb.db_url, nb.course_id),
           lambda name, assignment: course / "feedback" / name / assignment, progress)
    return 0
