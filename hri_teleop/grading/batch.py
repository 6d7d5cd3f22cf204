"""``make grade``: every submission in a folder, several at once, each in a process of its own.

Two modes, chosen by the folder:

* **nbgrader course** (``DIR`` is a course's ``submitted/`` -- its parent holds
  ``nbgrader_config.py`` or ``source/`` -- or the course folder itself): nbgrader's own
  ``autograde`` for every ``submitted/<student>/<assignment>/`` (``--force``: the notebooks
  run again, manual grades stay), then ``nbgrader generate_feedback`` (the HTML feedback in
  the course's ``feedback/``), and beside it ``hri-grade submission`` on the student's
  ``hri_lab`` of each assignment with that assignment's checks
  (:data:`hri_teleop.course.ASSIGNMENT_CHECKS`).
* **files only** (any other folder: one subfolder per student): ``hri-grade submission``
  on each student's package.

Why a process per submission, driven by a few threads: a grade must never be lost because
of another student -- a crash or hang on one submission ends that process only (it is
timed out and recorded as not graded, with the reason), and each process gives its student
code a uid and sandboxes of its own. Every job runs under a *reaper* (``python -m
hri_teleop.grading.batch reap -- ...``): a child subreaper that, when the job ends or is
stopped, kills everything the job started -- also the Jupyter kernel and the kernel's
private roscore, which start sessions of their own and so escape a process-group kill.

nbgrader's gradebook is one SQLite file shared by the concurrent ``autograde`` processes.
Each of them writes only its own student's rows, in short transactions (a submission's
rows at the start, each notebook's grades after it ran), and SQLite serialises the
writers; the processes are given a 60 s busy timeout (``?timeout=60`` on the database URL;
Python's default is 5 s) so a writer waits for another's commit instead of failing, and a
run that still fails with "database is locked" is graded again (up to two more times;
``--force`` makes the retry start clean). Measured on 2 cores: 16 concurrent
``autograde`` runs, 8 at once, no lock error; a 7 s exclusive lock on the gradebook while
autogrades start costs no run with the 60 s timeout and fails them with 1 s (then the
retry grades them). Speed (notebooks/README.md has the numbers): ``JOBS`` = cores is
1.9x one after another on the preparation; more jobs than cores helped long notebooks
(they wait for ROS and real time) and hurt short ones, so the default is the cores.

Results: ``OUT/<student>/results.json`` (Gradescope format), ``feedback.txt``, plots and
logs per check (course mode: per assignment in ``OUT/<student>/<assignment>/``, with
nbgrader's log ``autograde.log``); ``OUT/grades.csv`` and ``OUT/summary.json`` for all.
"""

from __future__ import annotations

import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

__all__ = ["BatchError", "Outcome", "JobOutcome", "submissions_in", "course_layout", "course_submissions",
           "grade_all", "grade_course"]

_PER_SUBMISSION_TIMEOUT_S = 600.0   # hri-grade submission: one student's files
_NOTEBOOK_TIMEOUT_S = 1800.0        # nbgrader autograde of one (student, assignment); a cell has 300 s of its own
_DB_BUSY_TIMEOUT_S = 60             # SQLite busy timeout of every nbgrader process
_DB_ATTEMPTS = 3                    # autograde runs of one submission when the gradebook was locked
_STOP_GRACE_S = 15.0                # a reaper told to stop gets this long before it is killed
#: Notebook kernels start a private roscore only when no master is reachable: never share
#: one (the lab's on 11311, say) between students graded at the same time.
_NO_MASTER = "http://127.0.0.1:1/"
_FILES = "hri_lab"                  # the label of a files-only job in course mode

Progress = Callable[[str], None]


class BatchError(RuntimeError):
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

    @property
    def label(self) -> str:
        return self.assignment if self.kind == "notebooks" else f"{self.assignment}/{_FILES}"


def _print(line: str) -> None:
    print(line, flush=True)


# -- running one job: a reaper process, a timeout, everything stopped ------------------------------

_PR_SET_PDEATHSIG, _PR_SET_CHILD_SUBREAPER = 1, 36
_RUNNING: Dict[int, subprocess.Popen] = {}
_RUNNING_LOCK = threading.Lock()


@dataclass(frozen=True)
class _Run:
    returncode: Optional[int]
    stdout: bytes
    seconds: float
    timed_out: bool


def _prctl(option: int, value: int) -> bool:
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(option, value, 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _proc_table() -> Dict[int, Tuple[int, bytes]]:
    """pid -> (parent pid, state) of every process, from /proc."""
    table: Dict[int, Tuple[int, bytes]] = {}
    try:
        entries = os.listdir("/proc")
    except OSError:
        return table
    for entry in entries:
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat", "rb") as fh:
                stat = fh.read()
            fields = stat[stat.rindex(b")") + 2:].split()
            table[int(entry)] = (int(fields[1]), fields[0])
        except (OSError, ValueError, IndexError):
            continue
    return table


def _descendants(root: int) -> List[int]:
    """Every live (not zombie) process below ``root``."""
    table = _proc_table()
    children: Dict[int, List[int]] = {}
    for pid, (ppid, _state) in table.items():
        children.setdefault(ppid, []).append(pid)
    found, todo = [], list(children.get(root, []))
    while todo:
        pid = todo.pop()
        found.append(pid)
        todo.extend(children.get(pid, []))
    return [pid for pid in found if table.get(pid, (0, b"Z"))[1] not in (b"Z", b"X")]


def _kill_descendants(root: int, reap: bool, deadline_s: float = 10.0) -> None:
    """SIGKILL everything below ``root`` until nothing is left (``reap``: ``root`` is us, collect the zombies)."""
    end = time.monotonic() + deadline_s
    while True:
        alive = _descendants(root)
        for pid in alive:
            try:
                os.kill(pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        if reap:
            while True:
                try:
                    pid, _status = os.waitpid(-1, os.WNOHANG)
                except ChildProcessError:
                    break
                if pid == 0:
                    break
        if not alive or time.monotonic() > end:
            return
        time.sleep(0.05)


def _reap_main(argv: Sequence[str]) -> int:
    """``python -m hri_teleop.grading.batch reap -- COMMAND...``: run COMMAND, then kill all it left behind.

    A child subreaper: orphans of the job (a kernel's roscore, a student's detached
    process) become its children instead of init's, so when COMMAND ends -- or this
    process is told to stop (SIGTERM, or its parent died) -- nothing of the job survives.
    """
    if not argv:
        print("reap: no command", file=sys.stderr)
        return 2
    parent = os.getppid()
    _prctl(_PR_SET_CHILD_SUBREAPER, 1)
    _prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    me = os.getpid()

    def stop(signum: int, _frame: Any) -> None:
        _kill_descendants(me, reap=True)
        os._exit(128 + signum)

    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, stop)
    if os.getppid() != parent:  # the batch died before we could ask to be told
        return 128 + signal.SIGTERM
    try:
        child = subprocess.Popen(list(argv), stdin=subprocess.DEVNULL)
    except OSError as exc:
        print(f"reap: cannot run {argv[0]}: {exc.strerror}", file=sys.stderr)
        return 127
    code = child.wait()
    _kill_descendants(me, reap=True)
    return code if code >= 0 else 128 - code


def _stop(proc: subprocess.Popen) -> None:
    """Stop a reaper and its job: SIGTERM (it kills its descendants), then SIGKILL whatever is left."""
    try:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=_STOP_GRACE_S)
    except subprocess.TimeoutExpired:
        pass
    except ProcessLookupError:
        return
    if proc.poll() is None:
        _kill_descendants(proc.pid, reap=False)
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def _run(argv: Sequence[str], log: Path, timeout_s: float, *, cwd: Optional[Path] = None,
         env: Optional[Dict[str, str]] = None, capture: bool = False) -> _Run:
    """Run ``argv`` under a reaper in a session of its own; stderr (and stdout unless ``capture``) into ``log``."""
    wrapped = [sys.executable, "-m", "hri_teleop.grading.batch", "reap", "--", *argv]
    started = time.monotonic()
    log.parent.mkdir(parents=True, exist_ok=True)
    with open(log, "wb") as fh:
        proc = subprocess.Popen(wrapped, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE if capture else fh,
                                stderr=fh, cwd=str(cwd) if cwd else None, env=env, start_new_session=True)
        with _RUNNING_LOCK:
            _RUNNING[proc.pid] = proc
        try:
            try:
                stdout, _ = proc.communicate(timeout=timeout_s)
                timed_out = False
            except subprocess.TimeoutExpired:
                timed_out = True
                _stop(proc)
                stdout, _ = proc.communicate()
        finally:
            with _RUNNING_LOCK:
                _RUNNING.pop(proc.pid, None)
    return _Run(None if timed_out else proc.returncode, stdout or b"", time.monotonic() - started, timed_out)


def _stop_all_running() -> None:
    with _RUNNING_LOCK:
        running = list(_RUNNING.values())
    for proc in running:
        if proc.poll() is None:
            _stop(proc)


def _jobs(jobs: Optional[int]) -> int:
    if jobs:
        return max(1, jobs)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


def _pool_run(tasks: Sequence[Tuple[str, Callable[[], Any]]], jobs: int,
              on_done: Callable[[str, Any, Optional[BaseException]], None]) -> None:
    """Run ``tasks`` (key, callable) ``jobs`` at a time; ``on_done`` in this thread as each ends.

    Ctrl-C or SIGTERM: the jobs not started are dropped, the running ones stopped (with
    everything they started), then KeyboardInterrupt goes on.
    """
    main = threading.current_thread() is threading.main_thread()
    previous = {}
    if main:
        def on_term(_signum: int, _frame: Any) -> None:
            raise KeyboardInterrupt

        previous = {signal.SIGTERM: signal.signal(signal.SIGTERM, on_term),
                    signal.SIGINT: signal.getsignal(signal.SIGINT)}
    pool = ThreadPoolExecutor(max_workers=jobs)
    futures: Dict[Future, str] = {}
    try:
        futures = {pool.submit(call): key for key, call in tasks}
        pending = set(futures)
        while pending:
            # short waits: a signal may land on a worker thread, and only a main thread that
            # wakes up runs the handler (a wait without timeout would sleep through Ctrl-C)
            finished, pending = wait(pending, timeout=0.5, return_when=FIRST_COMPLETED)
            for future in sorted(finished, key=lambda f: futures[f]):
                exc = future.exception()
                on_done(futures[future], None if exc else future.result(), exc)
    except KeyboardInterrupt:
        if main:  # make passes a SIGTERM on as well: a second signal must not cut the stopping short
            signal.signal(signal.SIGTERM, signal.SIG_IGN)
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        for future in futures:
            future.cancel()
        _stop_all_running()
        raise
    finally:
        pool.shutdown(wait=True)
        for sig, handler in previous.items():
            signal.signal(sig, handler)


# -- files only ----------------------------------------------------------------------------------

def submissions_in(folder: Path) -> List[Path]:
    """One submission per subfolder (nbgrader's submitted/<student>/...), sorted by name."""
    if not folder.is_dir():
        raise BatchError(f"{folder}: no such folder; collect submissions first (nbgrader: notebooks/submitted/) "
                         "or pass the folder, e.g. make grade DIR=path/to/submissions")
    found = sorted(p for p in folder.iterdir() if p.is_dir() and not p.name.startswith("."))
    if not found:
        raise BatchError(f"{folder}: no submission folders in it; expected one subfolder per student")
    return found


def _hri_grade_argv(folder: Path, out: Path, graph_cache: Optional[Path], checks: Optional[Sequence[str]]) -> List[str]:
    argv = [sys.executable, "-m", "hri_teleop.grading.cli", "submission", str(folder), "--json", "--out", str(out)]
    if graph_cache is not None:
        argv += ["--graph-cache", str(graph_cache)]
    if checks:
        argv += ["--checks", ",".join(checks)]
    return argv


def _files_result(run: _Run, log: Path, timeout_s: float) -> Tuple[str, float, float, str]:
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


def _grade_one(folder: Path, out: Path, graph_cache: Optional[Path], checks: Optional[Sequence[str]],
               timeout_s: float = _PER_SUBMISSION_TIMEOUT_S) -> Outcome:
    out.mkdir(parents=True, exist_ok=True)
    log = out / "grader.log"
    run = _run(_hri_grade_argv(folder, out, graph_cache, checks), log, timeout_s, capture=True)
    status, score, maximum, message = _files_result(run, log, timeout_s)
    return Outcome(folder.name, score, maximum, status, run.seconds, message)


def _live_graph_cache(out: Path, checks: Optional[Sequence[str]]) -> Optional[Path]:
    from hri_teleop.grading.checks import live_graph

    if checks and "graph" not in checks:
        return None
    cache = out / "live_graph.json"
    if cache.exists():
        cache.unlink()  # the lab's graph of today, not of an earlier run
    live_graph(cache)
    return cache


def grade_all(folder: Path, out: Path, jobs: Optional[int] = None, checks: Optional[Sequence[str]] = None,
              progress: Progress = _print, timeout_s: Optional[float] = None) -> int:
    """Grade every submission in ``folder`` into ``out``; 0 when all were graded, 2 if any could not be.

    An nbgrader course's ``submitted/`` (or the course folder) is graded with nbgrader
    (:func:`grade_course`); any other folder holds one student's files per subfolder.
    """
    folder = Path(folder)
    if not folder.is_dir():
        submissions_in(folder)  # raises the one-line error
    layout = course_layout(folder)
    if layout is not None:
        return grade_course(layout[0], layout[1], out, jobs=jobs, checks=checks, progress=progress,
                            timeout_s=timeout_s)
    from hri_teleop.grading.sandbox import sandbox_mode

    subs = submissions_in(folder)
    out.mkdir(parents=True, exist_ok=True)
    jobs = _jobs(jobs)
    limit = timeout_s or _PER_SUBMISSION_TIMEOUT_S
    sandbox_mode()  # says once, up front, when bubblewrap is missing
    graph_cache = _live_graph_cache(out, checks)
    progress(f"grading {len(subs)} submission(s) from {folder}, {jobs} at once")
    started = time.monotonic()
    outcomes: Dict[str, Outcome] = {}
    width = len(str(len(subs)))

    def done(name: str, outcome: Optional[Outcome], exc: Optional[BaseException]) -> None:
        if outcome is None:  # a bug of ours, recorded; the others go on
            outcome = Outcome(name, 0.0, 0.0, "not graded", 0.0, f"{type(exc).__name__}: {exc}")
        outcomes[name] = outcome
        line = f"[{len(outcomes):>{width}}/{len(subs)}] {outcome.student:<24} "
        line += (f"{outcome.score:g}/{outcome.max_score:g}" if outcome.status == "graded"
                 else f"NOT GRADED: {outcome.message}")
        progress(f"{line}  ({outcome.seconds:.1f} s)")

    _pool_run([(sub.name, lambda sub=sub: _grade_one(sub, out / sub.name, graph_cache, checks, limit))
               for sub in subs], jobs, done)
    ordered = [outcomes[s.name] for s in subs]
    with open(out / "grades.csv", "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["student", "score", "max_score", "status", "seconds", "message"])
        for o in ordered:
            writer.writerow([o.student, f"{o.score:g}", f"{o.max_score:g}", o.status, f"{o.seconds:.1f}", o.message])
    (out / "summary.json").write_text(json.dumps([asdict(o) for o in ordered], indent=2), encoding="utf-8")
    failed = [o for o in ordered if o.status != "graded"]
    progress(f"graded {len(ordered) - len(failed)}/{len(ordered)} in {time.monotonic() - started:.0f} s; "
             f"results in {out} (grades.csv, <student>/feedback.txt)")
    return 2 if failed else 0


# -- nbgrader course -------------------------------------------------------------------------------

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


def _assignment_order(names: Sequence[str]) -> List[str]:
    from hri_teleop.course import ASSIGNMENTS

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


def _nbgrader_config(course: Path) -> Any:
    """nbgrader's configuration as its apps load it: Jupyter's config folders, then the course's file."""
    from jupyter_core.paths import jupyter_config_path
    from traitlets.config import Config
    from traitlets.config.loader import ConfigFileNotFound, PyFileConfigLoader

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
class _Course:
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


def _open_course(course: Path, submitted: Path, assignments: Sequence[str]) -> _Course:
    try:
        import nbgrader  # noqa: F401
        from nbgrader.api import Gradebook, MissingEntry
        from nbgrader.coursedir import CourseDirectory
    except ImportError:
        raise BatchError(f"nbgrader is not installed for {sys.executable}, and {course} is an nbgrader course: "
                         "run `make setup` (nbgrader needs Python >= 3.9)") from None
    config = _nbgrader_config(course)
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
    return _Course(course, submitted, coursedir.course_id, db_url)


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


def _nbgrader_env() -> Dict[str, str]:
    # Warnings to stderr would cost an autograded cell its points (nbgrader scores a cell
    # that wrote to stderr 0), as in hri_teleop.course's own nbgrader runs.
    return dict(os.environ, PYTHONWARNINGS="ignore", ROS_MASTER_URI=_NO_MASTER)


def _submission_score(course: _Course, lock: threading.Lock, student: str,
                      assignment: str) -> Tuple[float, float, bool]:
    from nbgrader.api import Gradebook

    with lock:
        gb = Gradebook(course.db_url, course.course_id)
        try:
            sub = gb.find_submission(assignment, student)
            return float(sub.score), float(sub.max_score), bool(sub.needs_manual_grade)
        finally:
            gb.close()
            gb.engine.dispose()


def _forget_outputs(course: _Course, student: str, assignment: str) -> None:
    """A submission that was not graded has no autograded notebooks and no feedback (none stale either)."""
    from nbgrader.utils import rmtree

    for kind in ("autograded", "feedback"):
        folder = course.root / kind / student / assignment
        if folder.exists():
            rmtree(str(folder))
        try:
            folder.parent.rmdir()  # the student's folder, when this was its only assignment
        except OSError:
            pass


def _autograde(course: _Course, student: str, assignment: str, out: Path, timeout_s: float,
               db_lock: threading.Lock, progress: Progress) -> JobOutcome:
    folder = course.submitted / student / assignment
    links = _outside_links(folder)
    if links:
        _forget_outputs(course, student, assignment)
        return JobOutcome(student, assignment, "notebooks", 0.0, 0.0, "not graded", 0.0,
                          f"{links[0]} links outside the submission (nbgrader would copy that file into the "
                          "feedback); the student must hand in the file itself")
    argv = course.nbgrader_argv("autograde", assignment, "--student", student, "--force")
    log = out / "autograde.log"
    seconds = 0.0
    for attempt in range(1, _DB_ATTEMPTS + 1):
        run = _run(argv, log, timeout_s, cwd=course.root, env=_nbgrader_env())
        seconds += run.seconds
        if run.timed_out:
            _forget_outputs(course, student, assignment)
            notebook = _last_notebook(log.read_text(errors="replace"))
            return JobOutcome(student, assignment, "notebooks", 0.0, 0.0, "not graded", seconds,
                              f"nbgrader autograde took longer than {timeout_s:.0f} s (stopped"
                              + (f" in {notebook})" if notebook else ")"))
        if run.returncode == 0:
            score, maximum, manual = _submission_score(course, db_lock, student, assignment)
            return JobOutcome(student, assignment, "notebooks", score, maximum, "graded", seconds, "", manual)
        if "database is locked" in log.read_text(errors="replace") and attempt < _DB_ATTEMPTS:
            shutil.copy(log, log.with_name(f"autograde.attempt{attempt}.log"))
            progress(f"      {student} {assignment}: the gradebook was locked; autograding again "
                     f"(attempt {attempt + 1} of {_DB_ATTEMPTS})")
            continue
        break
    _forget_outputs(course, student, assignment)
    return JobOutcome(student, assignment, "notebooks", 0.0, 0.0, "not graded", seconds, _failure_reason(log))


def _grade_files(course: _Course, student: str, assignment: str, out: Path, checks: Sequence[str],
                 graph_cache: Optional[Path], timeout_s: float) -> JobOutcome:
    out.mkdir(parents=True, exist_ok=True)
    log = out / "grader.log"
    run = _run(_hri_grade_argv(course.submitted / student / assignment, out, graph_cache, checks), log, timeout_s,
               capture=True)
    status, score, maximum, message = _files_result(run, log, timeout_s)
    return JobOutcome(student, assignment, "files", score, maximum, status, run.seconds, message)


def _generate_feedback(course: _Course, assignment: str, out: Path) -> Tuple[bool, Dict[str, str]]:
    """``nbgrader generate_feedback`` for every autograded student of ``assignment``: (ok, {student: failure})."""
    log = out / f"generate_feedback.{assignment}.log"
    run = _run(course.nbgrader_argv("generate_feedback", assignment, "--force"), log, 600.0, cwd=course.root,
               env=_nbgrader_env())
    text = log.read_text(errors="replace")
    failed = {m.group(2): "nbgrader generate_feedback failed (see " + str(log) + ")"
              for m in re.finditer(r"error processing assignment '([^']+)' for student '([^']+)'", text)}
    return run.returncode == 0, failed


def _combine_files_results(student_out: Path, assignments: Sequence[str]) -> None:
    """``OUT/<student>/results.json`` and ``feedback.txt``: the checks of all the student's assignments together."""
    from hri_teleop.grading.results import CheckResult, feedback_text, gradescope_json

    results, parts = [], []
    for assignment in assignments:
        checks = student_out / assignment / "checks.json"
        if checks.is_file():
            these = [CheckResult.from_dict(d) for d in json.loads(checks.read_text(encoding="utf-8"))]
            results += these
            parts.append(f"== {assignment}: {assignment}/{_FILES} ==\n{feedback_text(these)}")
    if results:
        (student_out / "results.json").write_text(json.dumps(gradescope_json(results), indent=2), encoding="utf-8")
        (student_out / "feedback.txt").write_text("\n\n".join(parts) + "\n", encoding="utf-8")


def _fmt(value: Optional[float]) -> str:
    return "" if value is None else f"{value:g}"


def grade_course(course: Path, submitted: Path, out: Path, jobs: Optional[int] = None,
                 checks: Optional[Sequence[str]] = None, progress: Progress = _print,
                 timeout_s: Optional[float] = None) -> int:
    """nbgrader autograde + generate_feedback of every submission of the course, and hri-grade on its files.

    ``checks`` limits the files' checks (each assignment gets those of its own among
    them); ``timeout_s`` limits each (student, assignment) job. 0 when everything was
    graded, 2 when anything could not be (the reason is in grades.csv).
    """
    from hri_teleop.course import ASSIGNMENT_CHECKS
    from hri_teleop.grading.sandbox import sandbox_mode
    from hri_teleop.labkernel import install_kernelspec

    course, submitted, out = Path(course).resolve(), Path(submitted).resolve(), Path(out).resolve()
    pairs, empty = course_submissions(course, submitted)
    assignments = _assignment_order(sorted({a for _s, a in pairs}))
    nb = _open_course(course, submitted, assignments)
    install_kernelspec()  # the notebooks' kernel "hri-teleop" (.venv's Python in the lab's shell)
    out.mkdir(parents=True, exist_ok=True)
    jobs = _jobs(jobs)
    notebook_limit = timeout_s or _NOTEBOOK_TIMEOUT_S
    files_limit = timeout_s or _PER_SUBMISSION_TIMEOUT_S
    files_checks = {a: [c for c in ASSIGNMENT_CHECKS.get(a, ()) if not checks or c in checks] for a in assignments}
    sandbox_mode()  # says once, up front, when bubblewrap is missing
    wanted = sorted({c for cs in files_checks.values() for c in cs})
    graph_cache = _live_graph_cache(out, wanted) if "graph" in wanted else None
    students = sorted({s for s, _a in pairs} | set(empty))
    db_lock = threading.Lock()

    # longest first: the lab's notebooks, then the preparation's, then the files
    order = {a: i for i, a in enumerate(reversed(assignments))}
    tasks: List[Tuple[str, Callable[[], JobOutcome]]] = []
    for student, assignment in sorted(pairs, key=lambda p: (order[p[1]], p[0])):
        tasks.append((f"{student}\0{assignment}\0notebooks",
                      lambda s=student, a=assignment: _autograde(nb, s, a, out / s / a, notebook_limit, db_lock,
                                                                 progress)))
    for student, assignment in sorted(pairs, key=lambda p: (order[p[1]], p[0])):
        if files_checks[assignment]:
            tasks.append((f"{student}\0{assignment}\0files",
                          lambda s=student, a=assignment: _grade_files(nb, s, a, out / s / a, files_checks[a],
                                                                       graph_cache, files_limit)))
    progress(f"autograding {len(pairs)} submission(s) of {len(students)} student(s) in {course} with nbgrader "
             f"({', '.join(assignments)}), and their {_FILES} files; {jobs} at once")
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

    _pool_run(tasks, jobs, done)

    feedback_problems: Dict[Tuple[str, str], str] = {}
    for assignment in assignments:
        graded = [o.student for o in outcomes.values()
                  if o.assignment == assignment and o.kind == "notebooks" and o.status == "graded"]
        if not graded:
            continue
        ok, failed = _generate_feedback(nb, assignment, out)
        for student, why in failed.items():
            feedback_problems[(student, assignment)] = why
        problems = "" if ok else f"; errors, see {out / f'generate_feedback.{assignment}.log'}"
        progress(f"feedback: nbgrader generate_feedback {assignment} -> {course / 'feedback'}/<student>/{assignment}/ "
                 f"({len(graded) - len(failed)} student(s){problems})")

    rows, summary = [], []
    for student in students:
        mine = {(o.assignment, o.kind): o for o in outcomes.values() if o.student == student}
        row: Dict[str, str] = {"student": student}
        reasons: List[str] = []
        nb_score = nb_max = files_score = files_max = None
        for assignment in assignments:
            o = mine.get((assignment, "notebooks"))
            row[f"{assignment}_score"] = row[f"{assignment}_max"] = ""
            if o is None:
                continue
            if o.status == "graded":
                row[f"{assignment}_score"], row[f"{assignment}_max"] = _fmt(o.score), _fmt(o.max_score)
                nb_score, nb_max = (nb_score or 0.0) + o.score, (nb_max or 0.0) + o.max_score
            else:
                reasons.append(f"{assignment}: {o.message}")
            f = mine.get((assignment, "files"))
            if f is not None and f.status == "graded":
                files_score, files_max = (files_score or 0.0) + f.score, (files_max or 0.0) + f.max_score
            elif f is not None:
                reasons.append(f"{assignment}/{_FILES}: {f.message}")
            if (student, assignment) in feedback_problems:
                reasons.append(f"{assignment}: {feedback_problems[(student, assignment)]}")
        if student in empty:
            reasons.append(f"no assignment folder in {submitted / student} "
                           f"(expected {submitted.name}/{student}/<assignment>/)")
        _combine_files_results(out / student, assignments)
        status = "not graded" if reasons else "graded"
        row.update({"notebooks_score": _fmt(nb_score), "notebooks_max": _fmt(nb_max), "files_score": _fmt(files_score),
                    "files_max": _fmt(files_max),
                    "needs_manual_grade": " ".join(a for (a, k), o in sorted(mine.items())
                                                   if k == "notebooks" and o.needs_manual_grade),
                    "status": status, "seconds": f"{sum(o.seconds for o in mine.values()):.1f}",
                    "message": "; ".join(reasons)})
        rows.append(row)
        summary.append({"student": student, "status": status, "reasons": reasons,
                        "jobs": [asdict(o) for _k, o in sorted(mine.items())],
                        "feedback": {a: str(course / "feedback" / student / a) for (a, k), o in sorted(mine.items())
                                     if k == "notebooks" and o.status == "graded"
                                     and (student, a) not in feedback_problems}})
    columns = ["student", *[f"{a}_{x}" for a in assignments for x in ("score", "max")], "notebooks_score",
               "notebooks_max", "files_score", "files_max", "needs_manual_grade", "status", "seconds", "message"]
    with open(out / "grades.csv", "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    (out / "summary.json").write_text(json.dumps(summary, indent=2), encoding="utf-8")
    failed = [r for r in rows if r["status"] != "graded"]
    manual = [r for r in rows if r["needs_manual_grade"]]
    progress(f"graded {len(rows) - len(failed)}/{len(rows)} student(s) in {time.monotonic() - started:.0f} s; "
             f"gradebook {nb.db_url.split('?')[0]}, results in {out} (grades.csv, <student>/feedback.txt)"
             + (f"; {len(manual)} with answers to grade by hand (nbgrader formgrader)" if manual else ""))
    return 2 if failed else 0


if __name__ == "__main__":
    if sys.argv[1:2] == ["reap"]:
        rest = sys.argv[2:]
        sys.exit(_reap_main(rest[1:] if rest[:1] == ["--"] else rest))
    print("usage: python -m hri_teleop.grading.batch reap -- COMMAND... (make grade runs it)", file=sys.stderr)
    sys.exit(2)
