"""Jobs run as processes that leave nothing behind, a few at a time, stopped as a whole on Ctrl-C.

What ``make grade`` grades each submission with: a crash or hang ends that job's process only,
and every job runs under a reaper (:func:`reap_main`) that kills everything it started, also the
Jupyter kernel and its roscore, which escape a process-group kill. Why a process per job and as
many jobs as cores: docs/grading-internals.md.
"""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, TypeVar

from hri_teleop.ros.proc_table import descendants

__all__ = ["Progress", "print_line", "Run", "run_job", "job_count", "run_all", "reap_main", "reap_command"]

_STOP_GRACE_S = 15.0                # a reaper told to stop gets this long before it is killed

Progress = Callable[[str], None]


def print_line(line: str) -> None:
    """The default :data:`Progress`: a line on stdout, at once."""
    print(line, flush=True)


T = TypeVar("T")
_PR_SET_PDEATHSIG, _PR_SET_CHILD_SUBREAPER = 1, 36
_RUNNING: Dict[int, "subprocess.Popen[bytes]"] = {}
_RUNNING_LOCK = threading.Lock()


@dataclass(frozen=True)
class Run:
    """How one job ended: ``returncode`` None when it was stopped at its time limit."""

    returncode: Optional[int]
    stdout: bytes
    seconds: float
    timed_out: bool


def _prctl(option: int, value: int) -> bool:
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return bool(libc.prctl(option, value, 0, 0, 0) == 0)
    except (OSError, AttributeError):
        return False


def _kill_descendants(root: int, reap: bool, deadline_s: float = 10.0) -> None:
    """SIGKILL everything below ``root`` until nothing is left (``reap``: ``root`` is us, collect the zombies)."""
    end = time.monotonic() + deadline_s
    while True:
        alive = descendants(root)
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


def reap_main(argv: Sequence[str]) -> int:
    """``python -m hri_teleop.grading.run.jobs reap -- COMMAND...``: run COMMAND, then kill all it left behind.

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


def reaped(argv: Sequence[str]) -> List[str]:
    """``argv`` run under a reaper (``python -m hri_teleop.grading.run.jobs reap -- ...``): stopping
    the reaper with :func:`stop_job` stops everything the command started, in any session."""
    return [sys.executable, "-m", "hri_teleop.grading.run.jobs", "reap", "--", *argv]


def _stop(proc: "subprocess.Popen[bytes]") -> None:
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


def run_job(argv: Sequence[str], log: Path, timeout_s: float, *, cwd: Optional[Path] = None,
            env: Optional[Dict[str, str]] = None, capture: bool = False,
            on_line: Optional[Callable[[str], None]] = None) -> Run:
    """Run ``argv`` under a reaper in a session of its own; stderr (and stdout unless ``capture``) into ``log``.

    ``on_line`` (implies ``capture``): called with each stdout line as it comes, for progress.
    """
    capture = capture or on_line is not None
    started = time.monotonic()
    log.parent.mkdir(parents=True, exist_ok=True)
    with open(log, "wb") as fh:
        proc = subprocess.Popen(reaped(argv), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE if capture else fh,
                                stderr=fh, cwd=str(cwd) if cwd else None, env=env, start_new_session=True)
        with _RUNNING_LOCK:
            _RUNNING[proc.pid] = proc
        try:
            if on_line is None:
                try:
                    stdout, _ = proc.communicate(timeout=timeout_s)
                    timed_out = False
                except subprocess.TimeoutExpired:
                    timed_out = True
                    _stop(proc)
                    stdout, _ = proc.communicate()
            else:
                stdout, timed_out = _stream(proc, timeout_s, on_line)
        finally:
            with _RUNNING_LOCK:
                _RUNNING.pop(proc.pid, None)
    return Run(None if timed_out else proc.returncode, stdout or b"", time.monotonic() - started, timed_out)


def _stream(proc: "subprocess.Popen[bytes]", timeout_s: float, on_line: Callable[[str], None]) -> Tuple[bytes, bool]:
    """Read ``proc``'s stdout line by line until it ends; a timer stops it at ``timeout_s``."""
    expired: List[bool] = []

    def expire() -> None:
        expired.append(True)
        _stop(proc)

    timer = threading.Timer(timeout_s, expire)
    timer.daemon = True
    timer.start()
    lines: List[bytes] = []
    try:
        assert proc.stdout is not None
        for raw in proc.stdout:
            lines.append(raw)
            on_line(raw.decode("utf-8", "replace").rstrip("\n"))
        proc.wait()
    finally:
        timer.cancel()
    return b"".join(lines), bool(expired)


def stop_running() -> None:
    """Stop every job :func:`run_job` is running (Ctrl-C in a caller that is not :func:`run_all`)."""
    _stop_all_running()


def _stop_all_running() -> None:
    with _RUNNING_LOCK:
        running = list(_RUNNING.values())
    for proc in running:
        if proc.poll() is None:
            _stop(proc)


def job_count(jobs: Optional[int]) -> int:
    """``jobs`` at once, or as many as the cores this process may run on."""
    if jobs:
        return max(1, jobs)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


def run_all(tasks: Sequence[Tuple[str, Callable[[], T]]], jobs: int,
            on_done: Callable[[str, Optional[T], Optional[BaseException]], None]) -> None:
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
    futures: Dict[Future[T], str] = {}
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


def reap_command(args: Sequence[str], module: str = "hri_teleop.grading.run.jobs") -> int:
    """``python -m MODULE reap -- COMMAND...`` (``args`` after MODULE): :func:`reap_main`, or the usage."""
    if list(args[:1]) == ["reap"]:
        rest = list(args[1:])
        return reap_main(rest[1:] if rest[:1] == ["--"] else rest)
    print(f"usage: python -m {module} reap -- COMMAND... (make grade runs it)", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(reap_command(sys.argv[1:]))
