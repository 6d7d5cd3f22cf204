"""What every check shares: the grader's environment, one run's folders, workspace and runs.

Also the reuse of results, the sandboxed probe and session runs, and the refusal of the lab's
reference code.
"""

from __future__ import annotations

import functools
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Type, TypeVar, Union

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.grading.cases import inputs as C
from hri_teleop.grading.cases.templates import TemplateError, kind_of, make_template
from hri_teleop.grading.deliverables import key_of
from hri_teleop.grading.exercise import Exercise
from hri_teleop.grading.judge import reuse
from hri_teleop.grading.judge.reference_guard import reference_uses, refusal
from hri_teleop.grading.judge.tracebacks import is_template
from hri_teleop.grading.results import CheckResult, GradingError, Part, not_judged
from hri_teleop.grading.run.records import (
    ClockedObservation,
    LaunchParseResult,
    Obs,
    ProbeResult,
    ProcessFacts,
    SessionContext,
    SessionPlan,
    SessionRequest,
)
from hri_teleop.grading.run.sandbox import (
    DEFAULT_LIMITS,
    StudentProcess,
    describe_exit,
    sandbox_mode,
    session_argv,
    student_uid,
)
from hri_teleop.grading.run.untrusted_files import read_regular
from hri_teleop.grading.run.workspace import (
    DELIVERABLES,
    REPO,
    Workspace,
    find_package_root,
    given_path,
    locate,
    prepare_workspace,
    refusal_for,
    ros_package_path,
)
from hri_teleop.ros.master import lab_shell_env

PathLike = Union[str, Path]
P = TypeVar("P", bound=ProbeResult)
_PROBE_TIMEOUT_S = 20.0
#: The most a probe's JSON may hold (a student's YAML or parts run are a few kB).
_PROBE_OUTPUT_CAP = 4 * 1024 ** 2
TWIST_TOPIC = DEFAULT_TWIST_TOPIC


#: How an isolated Python finds what ``PYTHONPATH`` names (ROS from /opt/ros, say) without letting it
#: shadow anything: ``-I`` ignores the variable, so its entries go last on ``sys.path``, except those in
#: the working folder (a student's, for a probe), and the module runs as ``-m`` would run it.
_ISOLATED_BOOT = (
    "import os, runpy, sys\n"
    "here = os.path.realpath(os.getcwd())\n"
    "for entry in os.environ.get('PYTHONPATH', '').split(os.pathsep):\n"
    "    real = os.path.realpath(entry) if entry else ''\n"
    "    if real and os.path.commonpath([real, here]) != here and real not in sys.path:\n"
    "        sys.path.append(real)\n"
    "module = sys.argv.pop(1)\n"
    "runpy.run_module(module, run_name='__main__', alter_sys=True)\n")


def isolated_module_argv(module: str, args: Sequence[str], python: str = sys.executable) -> List[str]:
    """``python -m module args`` started isolated (``-I``): neither the working folder nor ``PYTHON*``
    variables come before the toolkit on ``sys.path``, so no module a student left in their folder (say
    ``hri_teleop/grading/run/probe.py``) stands in for the grader's."""
    return [python, "-I", "-c", _ISOLATED_BOOT, module, *args]


def require_ros() -> None:
    for tool in ("roscore", "roslaunch"):
        if shutil.which(tool, path=grader_shell_env()["PATH"]) is None:
            raise GradingError(f"{tool} not found: run 'make setup' (it installs ROS 1) and source tools/env.sh")


def grader_shell_env(package_path: str = "") -> Dict[str, str]:
    """tools/env.sh's environment with ``package_path`` (default: the lab's hri_lab) and no outside master."""
    env = lab_shell_env(package_root=REPO)
    if package_path:
        env["ROS_PACKAGE_PATH"] = package_path
    for key in ("ROS_MASTER_URI", "ROS_IP"):
        env.pop(key, None)
    env["ROS_HOSTNAME"] = "127.0.0.1"
    env["PYTHONUNBUFFERED"] = "1"
    return env


class _OpenRuns(threading.local):
    """The scratch runs this thread opened (checks graded side by side close their own only)."""

    def __init__(self) -> None:
        self.runs: "List[CheckRun]" = []


_OPEN = _OpenRuns()


def closing_scratch(check: Callable[..., CheckResult]) -> Callable[..., CheckResult]:
    """Whatever happens inside a check, its scratch folder does not outlive it."""
    @functools.wraps(check)
    def wrapper(*args: Any, **kwargs: Any) -> CheckResult:
        try:
            return check(*args, **kwargs)
        finally:
            for run in list(_OPEN.runs):
                run.close()
    return wrapper


#: Keyword arguments that do not change a check's result (the lab's graph is the same from a cache).
_SAME_RESULT_KWARGS = {"seed", "out_dir", "graph_cache"}


def reusable(check: str) -> Callable[[Callable[..., CheckResult]], Callable[..., CheckResult]]:
    """In make grade only: the files job stores each result, a notebook's check cell of the same
    package takes it (:mod:`hri_teleop.grading.judge.reuse`). A file given alone, or arguments that
    change what is judged (``node=False``), always run the check."""
    def decorate(grade_fn: Callable[..., CheckResult]) -> Callable[..., CheckResult]:
        @functools.wraps(grade_fn)
        def wrapper(path: PathLike, **kwargs: Any) -> CheckResult:
            write, read = os.environ.get(reuse.WRITE_ENV), os.environ.get(reuse.READ_ENV)
            given = Path(path).expanduser()
            if not (write or read) or not set(kwargs) <= _SAME_RESULT_KWARGS or not given.is_dir():
                return grade_fn(path, **kwargs)
            root = find_package_root(given)
            seed = C.default_seed(root) if kwargs.get("seed") is None else int(kwargs["seed"])
            if read and not write:
                found = reuse.load(Path(read), check, seed, root)
                if found is not None:
                    return found
            result = grade_fn(path, **kwargs)
            if write:
                reuse.store(Path(write), check, seed, root, result)
            return result
        return wrapper
    return decorate


class CheckRun:
    """One check's scratch folder (a fresh workspace) and where its plots and logs go."""

    def __init__(self, check: str, submission: PathLike, out_dir: Optional[PathLike], key: str,
                 single_file: Optional[Path], reference: Sequence[str] = ()) -> None:
        self.check = check
        self.session_dir = Path(tempfile.mkdtemp(prefix=f"hri-grade-{check}-"))
        # Without out_dir, plots of failed parts go to a fresh temp path (created only if one is drawn)
        # and the logs are not kept.
        self.keep_logs = out_dir is not None
        self.out_dir = Path(out_dir) / check if out_dir else \
            Path(tempfile.gettempdir()) / f"hri-grade-out-{check}-{os.getpid()}-{time.monotonic_ns()}"
        if out_dir:
            self.out_dir.mkdir(parents=True, exist_ok=True)
        self.uid = student_uid()
        self.closed = False
        _OPEN.runs.append(self)
        self.space: Workspace = prepare_workspace(submission, self.session_dir, self.uid, single_file, key,
                                                  reference=reference)
        self.started = time.monotonic()

    def close(self) -> None:
        """Keep the logs (256 kB each) next to the plots, delete the scratch folder; safe to call twice."""
        if self.closed:
            return
        self.closed = True
        if self in _OPEN.runs:
            _OPEN.runs.remove(self)
        logs = self.session_dir / "logs"
        if logs.is_dir() and self.keep_logs:
            target = self.out_dir / "logs"
            target.mkdir(parents=True, exist_ok=True)
            for log in logs.glob("*.log"):
                with open(log, "rb") as src, open(target / log.name, "wb") as dst:
                    dst.write(src.read(256 * 1024))
        if not os.environ.get("HRI_GRADE_KEEP"):
            shutil.rmtree(self.session_dir, ignore_errors=True)

    def env(self) -> Dict[str, str]:
        return grader_shell_env(ros_package_path(self.space.ws))

    def probe(self, command: str, target: Path, name: str, result_type: Type[P], plan: Optional[Path] = None
              ) -> Tuple[Optional[P], ProcessFacts]:
        """Run a probe as a student process (no network); (its result or None, facts about the process)."""
        out = self.space.grader_dir / f"{name}.json"
        env = self.env()
        env.update({"HOME": str(self.space.package), "ROS_HOME": str(self.space.package / ".ros"),
                    "PYTHONDONTWRITEBYTECODE": "1", "MPLBACKEND": "Agg", "SDL_VIDEODRIVER": "dummy",
                    "SDL_AUDIODRIVER": "dummy"})
        argv = isolated_module_argv("hri_teleop.grading.run.probe", [command, str(target)] + (
            [str(plan)] if plan is not None else []) + [str(out)])
        proc = StudentProcess(argv, self.space.package, env, self.session_dir / "logs" / f"{name}.log",
                              DEFAULT_LIMITS, uid=self.uid, nested=True, network=False, guard=self.space.guard)
        code = proc.wait(_PROBE_TIMEOUT_S)
        problem = "" if code is not None else f"was still running after {_PROBE_TIMEOUT_S:.0f} s (an endless loop?)"
        proc.stop()
        facts = ProcessFacts(exit_code=proc.returncode, output_tail=proc.output_tail(), output_bytes=proc.output_size(),
                             problem=problem or (describe_exit(proc.returncode) if proc.returncode else ""))
        data: Optional[P] = None
        if code == 0:
            try:  # the student's uid could have left a link or a FIFO there: read it as any submitted file
                data = result_type.from_json(json.loads(read_regular(out, _PROBE_OUTPUT_CAP, root=self.space.package)))
            except (OSError, ValueError):  # UntrustedFileError, RecordError too: not what the probe writes
                data = None
        return data, facts

    def session(self, plan: SessionPlan[Obs], timeout_s: float) -> Obs:
        """Run a session plan (sandboxed: own network namespace) and return its observation."""
        context = SessionContext(session_dir=str(self.session_dir), student_folder=str(self.space.package),
                                 uid=self.uid, python=sys.executable,
                                 env=dict(self.env(), TMPDIR=str(self.session_dir)),
                                 out=str(self.session_dir / f"{plan.KIND}.out.json"), limits=DEFAULT_LIMITS,
                                 guard=self.space.guard)
        return run_session_plan(context, plan, self.session_dir, timeout_s)


def run_session_plan(context: SessionContext, plan: SessionPlan[Obs], session_dir: Path, timeout_s: float) -> Obs:
    """Start ``python -m hri_teleop.grading.session`` (in bubblewrap where it works), wait, read."""
    plan_path = session_dir / f"{plan.KIND}.plan.json"
    plan_path.write_text(json.dumps(SessionRequest(context, plan).to_json()), encoding="utf-8")
    out = Path(context.out)
    observation = plan.observation_type()
    argv = session_argv(isolated_module_argv("hri_teleop.grading.session", [str(plan_path)]), session_dir)
    log = open(session_dir / f"{plan.KIND}.session.log", "wb")
    proc = subprocess.Popen(argv, env=context.env, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True, cwd=str(session_dir))
    try:
        proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        for sig in (signal.SIGTERM, signal.SIGKILL):
            try:
                os.killpg(proc.pid, sig)
            except ProcessLookupError:
                break
            try:
                proc.wait(timeout=3)
                break
            except subprocess.TimeoutExpired:
                continue
        log.close()
        return observation(session_error=f"the grading session did not finish within {timeout_s:.0f} s")
    log.close()
    if not out.is_file():
        tail = (session_dir / f"{plan.KIND}.session.log").read_text(errors="replace")[-1500:]
        return observation(session_error=f"the grading session ended without a result (status {proc.returncode}): "
                                         f"{tail}")
    return observation.from_json(json.loads(out.read_text(encoding="utf-8")))


def missing_result(exercise: Exercise, root: Path, seed: Optional[int]) -> CheckResult:
    """Every part failed: the deliverable is not in the package."""
    sub = DELIVERABLES[exercise.key]
    entries = list(exercise.parts.values())
    parts = [Part(entries[0][0], entries[0][1], False, f"{sub} was not found in {root}: put it at {sub} in your "
                                                        "hri_lab package")]
    parts += [not_judged(name, points, f"{sub} was not found") for name, points in entries[1:]]
    return CheckResult(exercise.check, str(root / sub), parts, seed if exercise.hidden_inputs else None)


def refused_result(exercise: Exercise, root: Path, reason: str, seed: Optional[int]) -> CheckResult:
    """Every part failed: the deliverable is a link, a special file or too large (``reason``); nothing of it read."""
    sub = DELIVERABLES[exercise.key]
    entries = list(exercise.parts.values())
    parts = [Part(entries[0][0], entries[0][1], False, reason)]
    parts += [not_judged(name, points, f"{sub} was not read (see above)") for name, points in entries[1:]]
    return CheckResult(exercise.check, str(root / sub), parts, seed if exercise.hidden_inputs else None)


def resolve_deliverable(path: PathLike, key: str) -> Tuple[Path, Optional[Path], Optional[Path], str]:
    """(package root, the file given explicitly or None, the file found or None, why it is refused or "").

    Nothing is followed: a file given alone must be a regular file itself, and a file found in a
    package is reached without a link (:func:`~hri_teleop.grading.run.workspace.refusal_for`)."""
    path = given_path(path)
    if not os.path.lexists(path):
        raise GradingError(f"{path}: no such file or folder; give the student's {DELIVERABLES[key]} or their "
                           "hri_lab folder")
    root = find_package_root(path)
    if not path.is_dir() or path.is_symlink():
        return root, path, path, refusal_for(root, key, path)
    found = locate(root, key)
    return root, None, found, refusal_for(root, key, found)


def finish_check(exercise: Exercise, run: CheckRun, parts: List[Part], notes: Sequence[str] = (),
                 seed: Optional[int] = None) -> CheckResult:
    """The result of a check that ran (``seed``: named in it when the exercise has hidden inputs)."""
    target = run.space.originals.get(exercise.key)
    mode = sandbox_mode(warn=False)
    all_notes = list(notes) + ([] if mode == "bwrap" else ["student code ran without bubblewrap (limits only)"])
    if run.space.substituted:
        names = ", ".join(Path(DELIVERABLES[k]).name for k in run.space.substituted)
        all_notes.append(f"ran the lab's {names} in place of yours: each is graded in its own check, so a mistake "
                         "there costs points there only")
    result = CheckResult(exercise.check, str(target) if target else "", parts,
                         seed if exercise.hidden_inputs else None, time.monotonic() - run.started, tuple(all_notes))
    run.close()
    return result


def start_check(exercise: Exercise, path: PathLike, out_dir: Optional[PathLike], seed: Optional[int]
                ) -> Tuple[Union[CheckRun, CheckResult], int]:
    """(the check's run, or its result when the file is missing: every part failed; the seed)."""
    key = exercise.key
    root, given, found, refused = resolve_deliverable(path, key)
    seed = C.default_seed(root) if seed is None else int(seed)
    if refused:
        return refused_result(exercise, root, refused, seed), seed
    if found is None:
        return missing_result(exercise, root, seed), seed
    sandbox_mode()  # says once when bubblewrap is missing
    stand_ins = [key_of(sub) for sub in exercise.lab_stand_ins]  # in the exercise's order
    return CheckRun(exercise.check, root if given is None else given, out_dir, key, given or found,
                    reference=stand_ins), seed


def refuse_reference(run: CheckRun, exercise: Exercise, seed: Optional[int]) -> Optional[CheckResult]:
    """Every part failed when the student's file uses the lab's reference rules (None: it does not)."""
    target = run.space.files[exercise.key]
    try:
        uses = reference_uses(read_regular(target, root=run.space.package).decode("utf-8")) if target is not None else []
    except (OSError, UnicodeDecodeError):  # UntrustedFileError is an OSError
        uses = []  # the check itself says the file cannot be read
    if not uses:
        return None
    entries = list(exercise.parts.values())
    message = refusal(Path(DELIVERABLES[exercise.key]).name, uses)
    parts = [Part(entries[0][0], entries[0][1], False, message)]
    parts += [not_judged(name, points, "the file uses the lab's reference implementation") for name, points in entries[1:]]
    return finish_check(exercise, run, parts, seed=seed)


def parse_launch(run: CheckRun, key: str) -> Tuple[LaunchParseResult, ProcessFacts]:
    data, facts = run.probe("launch-parse", run.space.file(key), f"parse-{key}", LaunchParseResult)
    return (data if data is not None else LaunchParseResult()), facts


#: ``HRI_GRADE_CLOCK=real`` runs the nodes in real time, as before the grader owned the clock
#: (to compare, or to rule the clock out when a node behaves differently under grading).
CLOCK_ENV = "HRI_GRADE_CLOCK"


def grading_clock() -> str:
    """"grader" (the default: /use_sim_time, /clock stepped by the grader) or "real time"."""
    value = os.environ.get(CLOCK_ENV, "grader").strip() or "grader"
    if value not in ("grader", "real"):
        raise GradingError(f"{CLOCK_ENV} is {value!r}; use grader (the default: the grader owns /clock) or real "
                           "(the nodes run in real time)")
    return "grader" if value == "grader" else "real time"


def left_as_template(run: CheckRun, key: str, submission: Optional[Path] = None) -> bool:
    """The student's deliverable is still the template handed out (every part YOUR CODE HERE unfilled): its
    workspace copy, or with ``submission`` (the package's folder) the file handed in (the lab's may stand in)."""
    target = run.space.originals.get(key) if submission is not None else run.space.files.get(key)
    solution = SOLUTIONS / DELIVERABLES[key]
    try:
        root = submission if submission is not None else run.space.package
        text = read_regular(target, root=root).decode("utf-8") if target is not None else ""
        template = make_template(solution.read_text(encoding="utf-8"), kind_of(solution)) if solution.is_file() else ""
    except (OSError, UnicodeDecodeError, TemplateError):  # UntrustedFileError is an OSError
        return False
    return is_template(text, template)


def clock_notes(observation: Optional[ClockedObservation], prefix: str = "", note: str = "") -> List[str]:
    """A note when the grader meant to own the clock and a node made it fall back to real time (``note``: why)."""
    if observation is None or observation.problem or observation.session_error:
        return []
    if observation.clock == "real time" and grading_clock() == "grader":
        return [prefix + (note or _REAL_TIME_NOTE)]
    return []


_REAL_TIME_NOTE = ("a node did not publish at every tick of the grader's /clock (a loop kept by rospy.Rate, or by "
                   "time.sleep in your files, follows it), so it was run in real time")
