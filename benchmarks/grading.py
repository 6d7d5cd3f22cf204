"""Benchmark 4: grading throughput, from real runs of the grader's own command lines.

Four rows: ``hri-grade submission`` on the answer key (against the checks' own time in the same
run), the same in real time (``HRI_GRADE_CLOCK=real``, the "before" row), and ``make grade`` with 1
and N workers on an nbgrader course of 20 submissions (against nbgrader's own autograde one after
another). A run that graded nothing real raises :class:`BenchError`, never a time. Why these
references, and how runs are isolated and stopped: docs/benchmarks.md.
"""

from __future__ import annotations

import csv
import json
import math
import os
import shutil
import statistics
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, List, Mapping, Optional, Sequence, Tuple

from benchmarks.report import BenchError, BenchOptions, BenchRow
from hri_teleop.core.paths import REPO, SOLUTIONS
from hri_teleop.course.nodes import STUDENT_PACKAGE
from hri_teleop.grading.batch import nbgrader_batch
from hri_teleop.grading.cases.templates import generate_answers, generate_templates
from hri_teleop.grading.checks import CHECKS
from hri_teleop.grading.judge.harness import CLOCK_ENV
from hri_teleop.grading.run import jobs
from hri_teleop.ros.kernel import install_kernelspec
from hri_teleop.ros.master import lab_shell_env

__all__ = ["ASSIGNMENT", "SMOKE_NOTEBOOKS", "SMOKE_CHECKS", "FULL_SUBMISSIONS", "SMOKE_SUBMISSIONS",
           "SUBMISSIONS_ENV", "Student", "submission_count", "student_plan", "autograded_points",
           "check_grades_csv", "build_course", "measure_submission", "measure_make_grade", "run"]

Progress = Callable[[str], None]

ASSIGNMENT = "preparation"
#: The preparation's cheapest notebook (Ex. 1 runs no ROS): what smoke runs grade, to keep make test short.
SMOKE_NOTEBOOKS = ("ex01_fsr_and_arduino",)
#: The cheapest check (no ROS session): what smoke runs of the files grade.
SMOKE_CHECKS = ("robot-params",)
FULL_SUBMISSIONS = 20
SMOKE_SUBMISSIONS = 2
#: Environment variable that overrides the full-size number of submissions (e.g. 4 for a quick look).
SUBMISSIONS_ENV = "HRI_BENCH_SUBMISSIONS"
SUBMISSION_RUNS, SMOKE_SUBMISSION_RUNS = 3, 1

# Time limits: backstops far above the measured times (42 s per submission for the whole
# preparation, notebooks/README.md), the grader's own defaults where it has one.
_SUBMISSION_TIMEOUT_S = 600.0       # hri-grade submission (batch.PER_SUBMISSION_TIMEOUT_S)
_AUTOGRADE_TIMEOUT_S = 1800.0       # one nbgrader autograde (nbgrader_batch._NOTEBOOK_TIMEOUT_S)
_SETUP_TIMEOUT_S = 300.0            # nbgrader generate_assignment


# -- pure helpers ------------------------------------------------------------------------------

@dataclass(frozen=True)
class Student:
    """One submission: ``answer_key`` True hands in the solutions, False the untouched release."""

    name: str
    answer_key: bool


def submission_count(smoke: bool, environ: Mapping[str, str] = os.environ) -> int:
    """How many submissions ``make grade`` grades: 2 in smoke runs, else ``HRI_BENCH_SUBMISSIONS`` or 20."""
    if smoke:
        return SMOKE_SUBMISSIONS
    text = environ.get(SUBMISSIONS_ENV, "").strip()
    if not text:
        return FULL_SUBMISSIONS
    try:
        count = int(text)
    except ValueError:
        count = 0
    if count < 1:
        raise BenchError(f"{SUBMISSIONS_ENV}={text!r}: give a whole number of submissions >= 1, e.g. 4")
    return count


def student_plan(count: int) -> List[Student]:
    """``count`` students s01, s02, ...: the answer key and the untouched release by turns (s01 the answer key)."""
    if count < 1:
        raise BenchError(f"{count} submissions: grading needs at least one")
    width = max(2, len(str(count)))
    return [Student(f"s{i + 1:0{width}d}", i % 2 == 0) for i in range(count)]


def autograded_points(notebooks: Sequence[Path]) -> Tuple[float, float]:
    """(autograded points, all points) of ``notebooks`` from nbgrader's cell metadata.

    The answer key must get every autograded point; the manually graded answers wait for a
    person (score 0 until then), so they count in the maximum only.
    """
    auto = total = 0.0
    for path in notebooks:
        for cell in json.loads(Path(path).read_text(encoding="utf-8"))["cells"]:
            meta = cell.get("metadata", {}).get("nbgrader", {})
            if meta.get("grade"):
                total += float(meta.get("points", 0))
                auto += 0.0 if meta.get("solution") else float(meta.get("points", 0))
    return auto, total


def _number(text: str) -> Optional[float]:
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def check_grades_csv(path: Path, plan: Sequence[Student], auto: float, total: float,
                     files_checked: bool) -> Dict[str, Dict[str, str]]:
    """The rows of a ``make grade`` grades.csv, checked to be a real grading of ``plan``; else BenchError.

    One row per student, every one graded, every answer key at ``auto`` of ``total``
    notebook points and (``files_checked``) full points on its files.
    """
    if not path.is_file():
        raise BenchError(f"{path}: make grade wrote no grades.csv")
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    names = [r.get("student", "") for r in rows]
    wanted = [s.name for s in plan]
    if sorted(names) != sorted(wanted):
        raise BenchError(f"{path}: {len(rows)} row(s) for {', '.join(names) or 'nobody'}; expected one per "
                         f"submission ({len(wanted)}: {', '.join(wanted)})")
    by_name = {r["student"]: r for r in rows}
    for student in plan:
        row = by_name[student.name]
        if row.get("status") != "graded":
            raise BenchError(f"{path}: {student.name} was not graded: {row.get('message', '')[:300]}")
        if not student.answer_key:
            continue
        # the notebooks' own points (nbgrader's); <assignment>_score adds the files' (hri_teleop.grading.points)
        score, maximum = _number(row.get("notebooks_score", "")), _number(row.get("notebooks_max", ""))
        if score is None or maximum is None or not (math.isclose(score, auto) and math.isclose(maximum, total)):
            raise BenchError(f"{path}: answer key {student.name} scored {row.get('notebooks_score')}/"
                             f"{row.get('notebooks_max')} on the notebooks, not the full {auto:g}/{total:g}")
        if files_checked:
            got, most = _number(row.get("files_score", "")), _number(row.get("files_max", ""))
            if got is None or most is None or most <= 0 or not math.isclose(got, most):
                raise BenchError(f"{path}: answer key {student.name} scored {row.get('files_score')}/"
                                 f"{row.get('files_max')} on its hri_lab files, not full points")
    return by_name


def _ratio(figure: float, reference: float) -> float:
    return figure / reference if reference > 0 else float("nan")


# -- processes that leave nothing behind ------------------------------------------------------------
# Each measured command runs under make grade's own reaper (hri_teleop.grading.run.jobs): a timeout or
# Ctrl-C stops it with everything it started, kernels and their roscores included.

@dataclass(frozen=True)
class _Ran:
    returncode: int
    seconds: float
    stdout: str


def _run(argv: Sequence[str], *, what: str, log: Path, timeout_s: float, env: Mapping[str, str],
         cwd: Optional[Path] = None, on_line: Optional[Callable[[str], None]] = None) -> _Ran:
    """``argv`` through make grade's own job runner (stderr into ``log``), timed from start to exit.

    BenchError when it outlives ``timeout_s`` (it is stopped, with all it started); on
    Ctrl-C it is stopped the same way and KeyboardInterrupt goes on.
    """
    try:
        run = jobs.run_job(argv, log, timeout_s, cwd=cwd, env=dict(env), on_line=on_line)
    except BaseException:
        jobs.stop_running()
        raise
    if run.timed_out:
        raise BenchError(f"{what} took longer than {timeout_s:.0f} s and was stopped (its stderr: {log})")
    return _Ran(int(run.returncode or 0), run.seconds, run.stdout.decode("utf-8", "replace").rstrip("\n"))


def _tail(ran: _Ran, log: Path, lines: int = 8) -> str:
    text = (ran.stdout + "\n" + (log.read_text(errors="replace") if log.is_file() else "")).strip()
    return " | ".join(text.splitlines()[-lines:])


def _lab_env() -> Dict[str, str]:
    """tools/env.sh's environment (this Python's folder first on PATH, hri_lab on ROS_PACKAGE_PATH)."""
    env = lab_shell_env(package_root=REPO)
    env.setdefault("ROS_HOSTNAME", "127.0.0.1")
    return env


# -- 1. hri-grade submission ----------------------------------------------------------------------

def measure_submission(work_dir: Path, runs: int = SUBMISSION_RUNS, checks: Sequence[str] = (),
                       progress: Progress = lambda _m: None, real_time: bool = False) -> BenchRow:
    """``hri-grade submission solutions/hri_lab`` ``runs`` times (``checks``: a subset, default all).

    Figure: the median wall time of a run; reference: the median of the sums of the
    checks' own ``duration_s`` in the same runs (see the module's docstring for why).
    ``real_time``: as before the grader owned the clock (``HRI_GRADE_CLOCK=real``, one check at a
    time, and a cache folder of its own, so the lab's graph is computed as it was in every run).
    """
    wanted = list(checks) or list(CHECKS)
    env = _lab_env()
    if real_time:
        env = dict(env, **{CLOCK_ENV: "real"})
    label = "hri-grade submission, real time" if real_time else "hri-grade submission"
    walls: List[float] = []
    sums: List[float] = []
    per_check: Dict[str, List[float]] = {}
    for index in range(1, runs + 1):
        out = work_dir / f"run{index}"
        if out.exists():
            shutil.rmtree(out)
        if real_time:
            cache = work_dir / f"cache{index}"
            shutil.rmtree(cache, ignore_errors=True)
            env["XDG_CACHE_HOME"] = str(cache)
        argv = [sys.executable, "-m", "hri_teleop.apps.grade", "submission", str(SOLUTIONS), "--out", str(out)]
        if checks:
            argv += ["--checks", ",".join(checks)]
        if real_time:  # as grading ran before: one check after the other (the grader's clock runs them side by side)
            argv += ["--jobs", "1"]
        progress(f"{label}: run {index}/{runs} ({', '.join(wanted)})")
        log = work_dir / f"run{index}.stderr"
        ran = _run(argv, what="hri-grade submission", log=log, timeout_s=_SUBMISSION_TIMEOUT_S, env=env)
        if ran.returncode != 0:
            raise BenchError(f"hri-grade submission on the answer key exited {ran.returncode} (expected 0: every "
                             f"check passes): {_tail(ran, log)}")
        try:
            results = json.loads((out / "checks.json").read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise BenchError(f"hri-grade submission wrote no readable {out / 'checks.json'} ({exc})") from None
        graded = [r["check"] for r in results]
        if graded != wanted or any(r["score"] != r["max_score"] or r["max_score"] <= 0 for r in results):
            raise BenchError(f"{out / 'checks.json'}: checks {graded} with scores "
                             f"{[(r['score'], r['max_score']) for r in results]}; expected {wanted} at full points")
        walls.append(ran.seconds)
        sums.append(sum(float(r["duration_s"]) for r in results))
        for r in results:
            per_check.setdefault(r["check"], []).append(float(r["duration_s"]))
        progress(f"{label}: run {index}/{runs} took {ran.seconds:.1f} s "
                 f"(checks {sums[-1]:.1f} s)")
    wall_s, checks_s = round(statistics.median(walls), 3), round(statistics.median(sums), 3)
    slowest = max(per_check, key=lambda c: statistics.median(per_check[c]))
    values = {"per_submission_s": wall_s, "min_s": round(min(walls), 3), "max_s": round(max(walls), 3),
              "checks_sum_s": checks_s, "runs": float(runs), "checks": float(len(wanted)),
              **{f"check_{c.replace('-', '_')}_s": round(statistics.median(v), 3) for c, v in per_check.items()}}
    return BenchRow(
        benchmark=label,
        figure=(f"{wall_s:.1f} s per submission (answer key, {len(wanted)} check(s), median of {runs}; "
                f"slowest: {slowest} {statistics.median(per_check[slowest]):.1f} s)"),
        reference=f"the checks' own time {checks_s:.1f} s (sum of checks.json duration_s)",
        ratio=_ratio(wall_s, checks_s),
        ratio_means="wall / checks' sum",
        values=values,
    )


# -- 2. make grade against nbgrader autograde --------------------------------------------------------

def _answer_key_package(target: Path) -> None:
    """The answer key's hri_lab as a good student hands it in: solutions/ with the marker lines dropped."""
    generate_answers(SOLUTIONS, target)


def build_course(root: Path, notebooks: Optional[Sequence[str]], plan: Sequence[Student],
                 env: Mapping[str, str]) -> Path:
    """An nbgrader course at ``root`` with ``notebooks`` of the preparation (None: all) and ``plan``'s submissions.

    As ``notebooks/``: the source notebooks with ``hri_lab`` linked to the answer key,
    ``nbgrader generate_assignment`` (the gradebook and the student version), the release's
    ``hri_lab`` templates; then ``submitted/<student>/preparation/``. Returns ``root``.
    """
    from hri_teleop.course.release import COURSE_DIR  # noqa: PLC0415 - loads nbgrader (2 s); run() checks it first

    if root.exists():
        shutil.rmtree(root)
    source = root / "source" / ASSIGNMENT
    source.mkdir(parents=True)
    shutil.copy(COURSE_DIR / "nbgrader_config.py", root / "nbgrader_config.py")
    available = sorted(p.stem for p in (COURSE_DIR / "source" / ASSIGNMENT).glob("*.ipynb"))
    chosen = list(notebooks) if notebooks else available
    missing = [n for n in chosen if n not in available]
    if missing:
        raise BenchError(f"no notebook {', '.join(missing)} in {COURSE_DIR / 'source' / ASSIGNMENT} "
                         f"(there: {', '.join(available)})")
    for name in chosen:
        shutil.copy(COURSE_DIR / "source" / ASSIGNMENT / f"{name}.ipynb", source)
    (source / STUDENT_PACKAGE).symlink_to(SOLUTIONS, target_is_directory=True)  # nbgrader does not follow it
    log = root.parent / "generate_assignment.log"
    ran = _run([sys.executable, "-m", "nbgrader", "generate_assignment", ASSIGNMENT, "--create", "--force",
                f"--CourseDirectory.root={root}"], what="nbgrader generate_assignment", log=log,
               timeout_s=_SETUP_TIMEOUT_S, env=nbgrader_batch.nbgrader_job_env(env), cwd=root)
    if ran.returncode != 0:
        raise BenchError(f"nbgrader generate_assignment {ASSIGNMENT} failed (exit {ran.returncode}): {_tail(ran, log)}")
    release = root / "release" / ASSIGNMENT
    generate_templates(SOLUTIONS, release / STUDENT_PACKAGE)
    install_kernelspec()  # the notebooks' kernel; make grade installs it too, the reference needs it first
    for student in plan:
        folder = root / "submitted" / student.name / ASSIGNMENT
        if student.answer_key:
            folder.mkdir(parents=True)
            for name in chosen:
                shutil.copy(source / f"{name}.ipynb", folder)
            _answer_key_package(folder / STUDENT_PACKAGE)
        else:
            shutil.copytree(release, folder)
    return root


def _fresh_copy(pristine: Path, target: Path) -> Path:
    """A copy of the course as built: gradebook with no submission graded, no autograded/ nor feedback/."""
    if target.exists():
        shutil.rmtree(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copytree(pristine, target, symlinks=True)
    return target


def _reference_run(course: Path, plan: Sequence[Student], auto: float, total: float, env: Mapping[str, str],
                   progress: Progress) -> float:
    """nbgrader's own autograde of every student one after another; total seconds (checked with the gradebook)."""
    from nbgrader.api import Gradebook, MissingEntry  # noqa: PLC0415 - heavy (1.5 s): only the reference row

    nb_env = nbgrader_batch.nbgrader_job_env(env)
    total_s = 0.0
    for index, student in enumerate(plan, 1):
        log = course.parent / "logs" / f"autograde.{student.name}.log"
        ran = _run([sys.executable, "-m", "nbgrader", "autograde", ASSIGNMENT, "--student", student.name,
                    f"--CourseDirectory.root={course}"], what=f"nbgrader autograde {student.name}", log=log,
                   timeout_s=_AUTOGRADE_TIMEOUT_S, env=nb_env, cwd=course)
        if ran.returncode != 0:
            raise BenchError(f"nbgrader autograde {ASSIGNMENT} --student {student.name} failed "
                             f"(exit {ran.returncode}): {_tail(ran, log)}")
        total_s += ran.seconds
        progress(f"nbgrader autograde one after another: {index}/{len(plan)} graded ({total_s:.0f} s)")
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gb:
        for student in plan:
            try:
                sub = gb.find_submission(ASSIGNMENT, student.name)
            except MissingEntry:
                raise BenchError(f"nbgrader autograde exited 0 but {course / 'gradebook.db'} has no submission of "
                                 f"{student.name}") from None
            if not math.isclose(sub.max_score, total) or (student.answer_key and not math.isclose(sub.score, auto)):
                raise BenchError(f"nbgrader autograde gave {'the answer key ' if student.answer_key else ''}"
                                 f"{student.name} {sub.score:g}/{sub.max_score:g} "
                                 f"(expected {auto:g}/{total:g} for the answer key, of {total:g} for all)")
    return total_s


@dataclass(frozen=True)
class _BatchRun:
    total_s: float
    autograde_jobs_s: float


def _batch_run(course: Path, plan: Sequence[Student], workers: int, checks: Sequence[str], auto: float, total: float,
               env: Mapping[str, str], progress: Progress) -> _BatchRun:
    """``hri-grade batch COURSE/submitted --out OUT --jobs N`` (make grade's command line), checked."""
    out = course.parent / "grades"
    argv = [sys.executable, "-m", "hri_teleop.apps.grade", "batch", str(course / "submitted"), "--out", str(out),
            "--jobs", str(workers)]
    if checks:
        argv += ["--checks", ",".join(checks)]
    label = f"make grade JOBS={workers}"

    def on_line(line: str) -> None:
        if line.startswith("["):  # "[k/N] student assignment score/max (t s)", one per job
            progress(f"{label}: {line.strip()}")

    log = course.parent / "make_grade.stderr"
    progress(f"{label}: grading {len(plan)} submission(s)")
    ran = _run(argv, what=label, log=log, timeout_s=300.0 + 2 * _AUTOGRADE_TIMEOUT_S * len(plan), env=env,
               cwd=course.parent, on_line=on_line)
    (course.parent / "make_grade.stdout").write_text(ran.stdout + "\n", encoding="utf-8")
    if ran.returncode != 0:
        raise BenchError(f"{label} exited {ran.returncode} (expected 0: every submission graded): {_tail(ran, log)}")
    check_grades_csv(out / "grades.csv", plan, auto, total, files_checked=True)
    autograde_s = 0.0
    try:
        for entry in json.loads((out / "summary.json").read_text(encoding="utf-8")):
            autograde_s += sum(float(j["seconds"]) for j in entry["jobs"] if j["kind"] == "notebooks")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise BenchError(f"{out / 'summary.json'}: not make grade's summary ({exc})") from None
    progress(f"{label}: done in {ran.seconds:.0f} s")
    return _BatchRun(ran.seconds, autograde_s)


def measure_make_grade(work_dir: Path, submissions: int = FULL_SUBMISSIONS, notebooks: Optional[Sequence[str]] = None,
                       jobs_all: Optional[int] = None, checks: Sequence[str] = (),
                       progress: Progress = lambda _m: None) -> List[BenchRow]:
    """make grade with 1 worker and with ``jobs_all`` against nbgrader autograde one after another.

    ``submissions`` students hand in ``notebooks`` of the preparation (None: all of them);
    ``checks`` limits the files' checks (default: the assignment's own). Each of the three
    runs grades a fresh copy of the same course. Two rows (1 worker, ``jobs_all`` workers),
    each with the reference's total and its ratio to it.
    """
    from hri_teleop.course.release import COURSE_DIR  # noqa: PLC0415 - loads nbgrader (2 s); run() checks it first

    jobs_all = jobs_all or os.cpu_count() or 1
    plan = student_plan(submissions)
    env = _lab_env()
    progress(f"building an nbgrader course with {submissions} submission(s) of {ASSIGNMENT} "
             f"({', '.join(notebooks) if notebooks else 'every notebook'})")
    pristine = build_course(work_dir / "course", notebooks, plan, env)
    sources = sorted((pristine / "source" / ASSIGNMENT).glob("*.ipynb"))
    auto, total = autograded_points(sources)
    if auto <= 0:
        raise BenchError(f"{COURSE_DIR / 'source' / ASSIGNMENT}: the chosen notebooks have no autograded points")

    reference_s = _reference_run(_fresh_copy(pristine, work_dir / "nbgrader" / "course"), plan, auto, total, env,
                                 progress)
    one = _batch_run(_fresh_copy(pristine, work_dir / "jobs1" / "course"), plan, 1, checks, auto, total, env, progress)
    many = _batch_run(_fresh_copy(pristine, work_dir / f"jobs{jobs_all}" / "course"), plan, jobs_all, checks, auto,
                      total, env, progress)

    n = len(plan)
    ref_s = round(reference_s, 3)
    what = (f"{len(sources)} notebook(s) + files"
            f"{' (' + ','.join(checks) + ')' if checks else ''} + feedback")
    reference = f"nbgrader autograde one after another: {ref_s / n:.1f} s per submission ({ref_s:.0f} s for {n})"
    rows = []
    for label, result, workers in (("make grade, 1 worker", one, 1), (f"make grade, {jobs_all} workers", many, jobs_all)):
        total_s = round(result.total_s, 3)
        values = {"submissions": float(n), "jobs": float(workers), "per_submission_s": round(total_s / n, 3),
                  "total_s": total_s, "reference_total_s": ref_s, "reference_per_submission_s": round(ref_s / n, 3),
                  "autograde_jobs_s": round(result.autograde_jobs_s, 3)}
        figure = f"{total_s / n:.1f} s per submission ({total_s:.0f} s for {n}: {what})"
        if workers != 1:
            speedup = round(one.total_s, 3) / total_s
            values["speedup_vs_1_worker"] = round(speedup, 3)
            figure += f"; {speedup:.2f}× faster than 1 worker"
        rows.append(BenchRow(benchmark=label, figure=figure, reference=reference, ratio=_ratio(total_s, ref_s),
                             ratio_means="make grade total / nbgrader sequential total", values=values))
    return rows


def run(options: BenchOptions, progress: Progress) -> List[BenchRow]:
    """The three rows of benchmark 4 (smoke: 1 run of one check, 2 submissions of two notebooks)."""
    try:
        import nbgrader  # noqa: F401, PLC0415 - the check that it is installed, with the fix
    except ImportError:
        raise BenchError(f"nbgrader is not installed for {sys.executable} (it needs Python >= 3.9): run `make setup`") \
            from None
    if shutil.which("roscore", path=_lab_env().get("PATH")) is None:
        raise BenchError("roscore not found: run `make setup` (installs ROS 1) or source tools/env.sh")
    work = Path(options.out_dir) / "grading"
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    smoke = options.smoke
    runs, checks = (SMOKE_SUBMISSION_RUNS, SMOKE_CHECKS) if smoke else (SUBMISSION_RUNS, ())
    after = measure_submission(work / "submission", runs, checks, progress)
    before = measure_submission(work / "submission-real-time", runs, checks, progress, real_time=True)
    # Before and after in one run: the grader's clock against real time, on the same machine.
    before_s, after_s = before.values["per_submission_s"], after.values["per_submission_s"]
    before = BenchRow(benchmark=before.benchmark, figure=before.figure + " [before: HRI_GRADE_CLOCK=real, one check at a time]",
                      reference=f"the grader's clock, same run: {after_s:.1f} s per submission",
                      ratio=_ratio(before_s, after_s), ratio_means="real time / grader's clock",
                      values=dict(before.values, grader_clock_s=after_s))
    rows = [after, before]
    rows += measure_make_grade(work / "make_grade", submission_count(smoke),
                               SMOKE_NOTEBOOKS if smoke else None, options.jobs,
                               SMOKE_CHECKS if smoke else (), progress)
    return rows
