"""The processes a private master's owner starts: each in its own session, stopped with all it spawned.

A ROS tool started here leads a process group of its own, so a stop reaches what it spawned;
roslaunch also puts each node in a session of its own, so a stop records the whole tree first and
escalates to every process of it. What still runs when Python exits is stopped by an exit hook.
"""

from __future__ import annotations

import atexit
import os
import shutil
import signal
import subprocess
import threading
import time
from pathlib import Path
from typing import Any, List, Mapping, Optional, Sequence, Set

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.ros.proc_table import ProcessIds, descendants, ignores_signal


class MasterError(HriTeleopError, RuntimeError):
    """A ROS master or a process on it could not be started or did not answer."""


#: The processes this module started that still run (what :func:`stop_all` stops at exit).
LIVE_PROCESSES: "Set[ManagedProcess]" = set()
_HOOKED: List[bool] = []


def stop_all() -> None:
    """What is still running when Python exits (a notebook kernel closing): the nodes side by
    side, then the masters killed -- after the nodes, nobody reads them, and a kernel whose
    exit takes 2 s stalls the notebook's restart (and nbgrader, once per notebook)."""
    live = list(LIVE_PROCESSES)
    interrupt_nodes()
    stop_side_by_side([proc for proc in live if not proc.is_master])
    for proc in live:
        if proc.is_master:
            proc.kill()


def _track(proc: "ManagedProcess") -> None:
    """Remember a live process; the first one registers :func:`stop_all` as the exit hook
    (on use, not on import: importing this module changes nothing)."""
    if not LIVE_PROCESSES and not _HOOKED:
        atexit.register(stop_all)
        _HOOKED.append(True)
    LIVE_PROCESSES.add(proc)


def interrupt_nodes() -> None:
    """SIGINT every live process but the masters, without waiting: their shutdowns overlap
    with whatever the caller does next (a kernel's own rospy shutdown takes 0.6 s)."""
    for proc in list(LIVE_PROCESSES):
        if not proc.is_master:
            proc.interrupt()


def _stop_all_then_die(signum: int, _frame: object) -> None:
    stop_all()
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)


def _stop_children_on_sigterm() -> None:
    """On SIGTERM, stop every child first, then die of SIGTERM as before.

    Why: children run in sessions of their own (so a stop reaches what they spawn), which
    also means they outlive a parent killed by SIGTERM -- a ``kill``, a CI or job-runner
    timeout -- since Python's default SIGTERM action skips the exit hook. Only from the
    main thread, and never over a handler the program installed itself.
    """
    if threading.current_thread() is not threading.main_thread():
        return
    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, _stop_all_then_die)


def stop_side_by_side(procs: Sequence[Any], kill: bool = False) -> None:
    """``proc.stop()`` of each at once (threads): their grace periods overlap instead of adding up.

    ``kill``: ``proc.kill()`` instead, for runs whose every judged output is already recorded (a
    clean exit adds nothing and costs rospy's 0.5 s shutdown poll).
    """
    threads = [threading.Thread(target=proc.kill if kill else proc.stop, daemon=True)
               for proc in procs if proc.running]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()


class ManagedProcess:
    """A child process in its own process group, with its output kept in a log file."""

    def __init__(self, argv: Sequence[str], env: Mapping[str, str], log_path: Path,
                 cwd: Optional[Path] = None, is_master: bool = False) -> None:
        self.argv = list(argv)
        self.log_path = log_path
        #: A roscore: stopped after everything else at exit, and killed rather than asked.
        self.is_master = is_master
        self._interrupted = False
        log_path.parent.mkdir(parents=True, exist_ok=True)
        self._log = open(log_path, "wb")
        if shutil.which(self.argv[0], path=env.get("PATH")) is None and not os.path.exists(self.argv[0]):
            self._log.close()
            raise MasterError(
                f"{self.argv[0]} not found on PATH: run 'make setup' (it installs ROS 1) "
                "or source tools/env.sh"
            )
        self.popen = subprocess.Popen(
            self.argv, env=dict(env), cwd=str(cwd) if cwd else None,
            stdin=subprocess.DEVNULL, stdout=self._log, stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        self.pgid = self.popen.pid  # start_new_session: the child leads its own group
        _track(self)
        _stop_children_on_sigterm()

    @property
    def running(self) -> bool:
        return self.popen.poll() is None

    @property
    def anything_left(self) -> bool:
        """True while any process of this one's group (itself or what it spawned) lives."""
        return _group_alive(self.pgid)

    def output(self) -> str:
        """Everything the process printed so far (stdout and stderr)."""
        if not self._log.closed:
            self._log.flush()
        return self.log_path.read_text(errors="replace")

    def stop(self, timeout_s: float = 10.0) -> Optional[int]:
        """SIGINT the whole group (how ROS tools shut down cleanly; SIGTERM where the leader ignores SIGINT), then escalate.

        SIGTERM and SIGKILL also reach every process that was below this one when the stop began:
        roslaunch's nodes run in sessions of their own, and a node that hangs in its shutdown
        outlived a roslaunch killed before its own escalation (one lab_sim ran on for 2 hours).
        """
        try:
            pgid: Optional[int] = os.getpgid(self.popen.pid)
        except ProcessLookupError:
            pgid = None
        family = ProcessIds(descendants(self.popen.pid))
        # A leader that ignores SIGINT (inherited: see ignores_signal) would only wait out the timeout.
        asks = signal.SIGTERM if ignores_signal(self.popen.pid, signal.SIGINT) else signal.SIGINT
        for sig, wait_s in ((asks, timeout_s), (signal.SIGTERM, 3.0), (signal.SIGKILL, 3.0)):
            if sig == signal.SIGINT and self._interrupted:
                pass  # interrupt() sent it: a second SIGINT would cut a clean shutdown short
            elif pgid is not None:
                try:
                    os.killpg(pgid, sig)
                except ProcessLookupError:
                    pass
            if sig != signal.SIGINT:
                family.signal(sig)
            deadline = time.monotonic() + wait_s
            try:
                self.popen.wait(timeout=wait_s)
            except subprocess.TimeoutExpired:
                continue
            # The leader is gone, but its children may still be finishing (rosbag's
            # wrapper exits before the recorder has closed the bag): give them the
            # rest of this step's time before escalating.
            def left() -> bool:
                return (pgid is not None and _group_alive(pgid)) or bool(family.alive())

            while left() and time.monotonic() < deadline:
                time.sleep(0.02)
            if not left():
                break
        LIVE_PROCESSES.discard(self)
        if not self._log.closed:
            self._log.close()
        return self.popen.returncode

    def interrupt(self) -> None:
        """SIGINT the group now without waiting (stop() then only waits): many shut down at once."""
        if self._interrupted or not self.running:
            return
        self._interrupted = True
        try:
            os.killpg(os.getpgid(self.popen.pid), signal.SIGINT)
        except ProcessLookupError:
            pass

    def kill(self) -> Optional[int]:
        """SIGKILL the whole group and every descendant at once: for what nobody needs a clean exit
        of (a grading master). roslaunch starts its nodes in sessions of their own (roscore's
        rosmaster and rosout too), so killing the group alone would orphan them."""
        family = [self.popen.pid, *descendants(self.popen.pid)]
        try:
            os.killpg(os.getpgid(self.popen.pid), signal.SIGKILL)
        except ProcessLookupError:
            pass
        for pid in family:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        return self.stop(timeout_s=3.0)

    def wait(self, timeout_s: float) -> Optional[int]:
        try:
            return self.popen.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            return None


def _group_alive(pgid: int) -> bool:
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
