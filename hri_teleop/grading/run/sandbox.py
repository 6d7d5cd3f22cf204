"""Running untrusted student code: limits, process groups, and bubblewrap where it works.

A grade must survive whatever a student wrote (an endless loop, a fork bomb, 100 MB of prints,
``sys.exit`` at import, a write to the instructor's files) without hanging the grader or costing
another student a grade. Two layers: the session (the grader's master, feeders and recorders) and
each student process inside it; what each gets, with and without bubblewrap, is in
grading/README.md ("Sandbox"). :func:`sandbox_mode` says which mode is in use.
"""

from __future__ import annotations

import itertools
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, List, Mapping, Optional, Sequence, TextIO, Tuple

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.grading.run.student_guard import GUARD_ENV
from hri_teleop.grading.run.student_guard import SITE_DIR as GUARD_SITE
from hri_teleop.grading.run.view import toolkit_view, view_argv
from hri_teleop.ros.proc_table import STUDENT_UID_BASE, uid_process_count

__all__ = ["SandboxError", "Limits", "DEFAULT_LIMITS", "sandbox_mode", "bwrap_problem", "session_argv",
           "StudentProcess", "student_uid", "STUDENT_ENV", "student_environment", "OUTPUT_CAP_BYTES", "describe_exit", "folder_bytes",
           "private_mounts"]

#: Largest output (stdout + stderr, and any one file) a student process may write.
OUTPUT_CAP_BYTES = 2 * 1024 * 1024
#: A student process' own /tmp (a tmpfs: memory, and only as much as it writes).
TMP_BYTES = 64 * 1024 * 1024
#: How often a student process' folder is measured against ``Limits.disk_bytes``.
DISK_CHECK_S = 0.05
_MODE_ENV = "HRI_GRADE_SANDBOX"


class SandboxError(HriTeleopError, RuntimeError):
    """The sandbox could not be set up as asked (one line: the cause and the fix)."""


@dataclass(frozen=True)
class Limits:
    """Per student process. ``processes`` counts threads too (rospy nodes use about 10)."""

    cpu_s: int = 30
    memory_bytes: int = 2 * 1024 ** 3
    file_bytes: int = OUTPUT_CAP_BYTES
    processes: int = 160
    open_files: int = 256
    #: what it may write into its folder in all (the files it was given count too)
    disk_bytes: int = 64 * 1024 ** 2


DEFAULT_LIMITS = Limits()

_bwrap_state: Dict[str, str] = {}


def _probe_bwrap() -> str:
    """'' if bubblewrap can run a session with a nested student sandbox here, else why not.

    It tries the real thing: an outer sandbox (new network and PID namespace) that starts
    an inner one as a student process would be started (as root: after dropping to an
    unprivileged uid).
    """
    exe = shutil.which("bwrap")
    if exe is None:
        return "bubblewrap (bwrap) is not installed; `apt-get install bubblewrap` (tools/setup.sh does)"
    # The probe's student folder is a fresh one, bound like a session's: nothing else under /tmp
    # is hidden, so a checkout (and its .venv) under /tmp is probed where it lies.
    folder = Path(tempfile.mkdtemp(prefix="hri-grade-probe-"))
    folder.chmod(0o777)
    inner = _student_argv(["true"], folder, nested=True, exe=exe)
    uid = student_uid()
    if uid is not None:
        inner = [sys.executable, "-c", "import os, sys; os.setgroups([]); os.setgid(%d); os.setuid(%d); "
                 "os.execvp(sys.argv[1], sys.argv[1:])" % (uid, uid)] + inner
    outer = [exe, "--unshare-net", "--unshare-pid", "--die-with-parent", "--ro-bind", "/", "/",
             "--dev", "/dev", "--proc", "/proc", "--bind", str(folder), str(folder), "--"] + inner
    try:
        proc = subprocess.run(outer, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=20)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"bwrap failed to start ({exc})"
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    if proc.returncode != 0:
        line = (proc.stderr.strip().splitlines() or ["exit status %d" % proc.returncode])[-1]
        return f"bwrap cannot create the namespaces here ({line}); user namespaces may be disabled"
    return ""


def unreachable(paths: Sequence[str], uid: Optional[int]) -> str:
    """'' when user ``uid`` (None: this process' own user, who reaches what it runs) may enter every folder
    above each of ``paths``, else one line naming the first folder in the way and the fix.

    As root, student code runs under a uid of its own that owns nothing and is in no group: a checkout
    inside a folder of mode 0700 (``mktemp -d``, some distributions' homes) hides its Python and toolkit
    from it, and every check of every student would fail as "could not be imported".
    """
    if uid is None:
        return ""
    for path in paths:
        folder = os.path.dirname(os.path.abspath(path))
        chain = []
        while True:
            chain.append(folder)
            if folder == "/":
                break
            folder = os.path.dirname(folder)
        for folder in reversed(chain):
            try:
                mode = os.stat(folder).st_mode
            except OSError:
                return f"{folder} cannot be read ({path} lies in it); grade from a checkout every user may enter"
            if not mode & 0o001:
                return (f"student code cannot reach {path}: {folder} (mode {mode & 0o777:04o}) lets no other user "
                        f"in; grade from a checkout every user may enter (chmod o+x {folder}, or clone it under "
                        "/opt or /srv)")
    return ""


def toolkit_paths() -> List[str]:
    """What student code runs on, as paths: the Python binary, its prefix and the toolkit's package."""
    toolkit = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))  # hri_teleop
    return [os.path.realpath(sys.executable), sys.prefix, toolkit]


def bwrap_problem() -> str:
    """Why bubblewrap is not used ('' when it is), probed once per process.

    First, whatever the mode: the student's uid must reach the toolkit and its Python, or SandboxError
    (one line): graded without them every student would get zeros.
    """
    if "problem" not in _bwrap_state:
        reach = unreachable(toolkit_paths(), student_uid())
        if reach:
            raise SandboxError(reach)
        wanted = os.environ.get(_MODE_ENV, "auto").strip().lower()
        if wanted == "none":
            _bwrap_state["problem"] = f"{_MODE_ENV}=none"
        elif wanted in ("auto", "bwrap", ""):
            _bwrap_state["problem"] = _probe_bwrap()
            if wanted == "bwrap" and _bwrap_state["problem"]:
                raise SandboxError(f"{_MODE_ENV}=bwrap but {_bwrap_state['problem']}")
        else:
            raise SandboxError(f"{_MODE_ENV}={wanted!r}; use auto, bwrap or none")
    return _bwrap_state["problem"]


def sandbox_mode(warn: bool = True, stream: Optional[TextIO] = None) -> str:
    """'bwrap' or 'limits-only'; the first call without bubblewrap prints the reason once.

    The note goes to stdout (``stream`` to change it): nbgrader scores a cell that wrote to
    stderr with 0 points, and the check's feedback repeats the note anyway.
    """
    problem = bwrap_problem()
    if problem and warn and not _bwrap_state.get("warned"):
        _bwrap_state["warned"] = "1"
        print(f"hri-grade: student code runs without bubblewrap ({problem}): resource limits, process "
              "groups and file permissions only; network and files outside the student's folder are "
              "not shielded", file=stream if stream is not None else sys.stdout, flush=True)
    return "limits-only" if problem else "bwrap"


#: uids of one grading process' threads are this far apart (above any pid: the kernel's largest pid_max).
UID_SLOT_SPAN = 1 << 22
_slots = itertools.count(1)
_thread_slot = threading.local()


def student_uid() -> Optional[int]:
    """An unprivileged uid for the student code of this grading process and thread, or None when not root.

    Its own uid per thread: checks graded side by side (``grade_submission(jobs=...)``) must not
    share one, since a check's end kills every process of its uid and the process limit counts
    per uid. The main thread's is ``STUDENT_UID_BASE + pid``, as a process grading alone has.
    """
    if os.geteuid() != 0:
        return None
    if threading.current_thread() is threading.main_thread():
        return STUDENT_UID_BASE + os.getpid()
    slot = getattr(_thread_slot, "slot", None)
    if slot is None:
        slot = _thread_slot.slot = next(_slots)
    return STUDENT_UID_BASE + os.getpid() + slot * UID_SLOT_SPAN


def session_argv(argv: Sequence[str], session_dir: Path, readonly_extra: Sequence[Path] = ()) -> List[str]:
    """``argv`` wrapped for the trusted session: own network and PID namespace, read-only
    everything but ``session_dir`` (/tmp included: give it TMPDIR inside ``session_dir``).
    Unchanged without bubblewrap."""
    if bwrap_problem():
        return list(argv)
    exe = shutil.which("bwrap") or "bwrap"
    wrapped = [exe, "--unshare-net", "--unshare-pid", "--unshare-ipc", "--die-with-parent",
               "--ro-bind", "/", "/", "--dev", "/dev", "--proc", "/proc"]
    for path in readonly_extra:
        wrapped += ["--ro-bind", str(path), str(path)]
    wrapped += ["--bind", str(session_dir), str(session_dir), "--chdir", str(session_dir), "--"]
    return wrapped + list(argv)


def _student_argv(argv: Sequence[str], folder: Path, nested: bool, exe: str = "", network: bool = True,
                  env: Optional[Mapping[str, str]] = None) -> List[str]:
    """bubblewrap for one student process: its folder writable, and of the rest only what it runs on
    (:func:`hri_teleop.grading.run.view.toolkit_view`: the system, Python, the toolkit without the answers,
    and the ROS workspace around its folder) read-only; /tmp its own (TMPDIR points into the folder
    anyway), no capabilities.

    ``nested``: inside a session sandbox, whose /proc cannot be mounted again from a user
    namespace; the session's /proc is bound instead (the student's own PID namespace still
    keeps it from signalling anything outside). ``network`` False: not even a loopback to
    a master (the probes need none).
    """
    exe = exe or shutil.which("bwrap") or "bwrap"
    proc = ["--ro-bind", "/proc", "/proc"] if nested else ["--proc", "/proc"]
    net = [] if network else ["--unshare-net"]
    env = env if env is not None else os.environ
    # the catkin-free workspace the grader built around the student's package (stand-ins, ros_intro)
    around = [str(folder.parent)] if str(folder.parent) in env.get("ROS_PACKAGE_PATH", "").split(":") else []
    view = toolkit_view(env, writable=[str(folder)], extra_shown=around, cwd=str(folder))
    return [exe, "--unshare-user", "--unshare-pid", "--unshare-ipc", "--unshare-uts", *net, "--die-with-parent",
            "--cap-drop", "ALL", *view_argv(view, proc, TMP_BYTES), "--remount-ro", "/",
            "--chdir", str(folder), "--"] + list(argv)


#: A student process' environment, by exact name: what Python and ROS need. An exact list, not prefixes: the
#: grader's own variables (a token named ROS_..., an HRI_CANVAS_TOKEN) stay with it.
STUDENT_ENV = frozenset({
    "PATH", "HOME", "LANG", "LANGUAGE", "TERM", "TMPDIR", "PYTHONPATH", "PYTHONUNBUFFERED", "PYTHONDONTWRITEBYTECODE",
    "PYTHONIOENCODING", "LD_LIBRARY_PATH", "CMAKE_PREFIX_PATH", "PKG_CONFIG_PATH", "MPLBACKEND", "SDL_VIDEODRIVER",
    "SDL_AUDIODRIVER", "PYGAME_HIDE_SUPPORT_PROMPT", "HRI_PAD_CLOCK", "HRI_CLOCK_SLEEP_ROOT", "HRI_ROBOT",
    "LC_ALL", "LC_CTYPE", "LC_NUMERIC", "LC_MESSAGES",
    "ROS_MASTER_URI", "ROS_HOSTNAME", "ROS_IP", "ROS_PACKAGE_PATH", "ROS_DISTRO", "ROS_ROOT", "ROS_ETC_DIR",
    "ROS_VERSION", "ROS_PYTHON_VERSION", "ROS_HOME", "ROS_LOG_DIR", "ROS_NAMESPACE", "ROS_LANG_DISABLE",
    "ROSCONSOLE_CONFIG_FILE", "ROSCONSOLE_FORMAT", "ROSCONSOLE_STDOUT_LINE_BUFFERED", "ROS_PYTHON_LOG_CONFIG_FILE",
    "ROSLISP_PACKAGE_DIRECTORIES", "ROSOUT_DISABLE_FILE_LOGGING",
})


def student_environment(env: Mapping[str, str]) -> Dict[str, str]:
    """Only what ROS and Python need (:data:`STUDENT_ENV`): the grader's other variables stay with it."""
    return {k: v for k, v in env.items() if k in STUDENT_ENV}


_CLONE_NEWNS = 0x00020000
_MS_REC, _MS_PRIVATE = 1 << 14, 1 << 18


def private_mounts() -> bool:
    """In a child about to start a box, as root: a mount namespace of its own whose mounts propagate nothing
    in, so a mount that appears on the machine after the box started never shows inside it (bubblewrap alone
    makes its box a slave of the machine's mounts). True when done; an unprivileged grader cannot, and its
    boxes keep bubblewrap's propagation (docs/grading-internals.md, threat model)."""
    if os.geteuid() != 0:
        return False
    import ctypes  # noqa: PLC0415 - only in the child that starts a box

    libc = ctypes.CDLL(None, use_errno=True)
    if libc.unshare(_CLONE_NEWNS) != 0:
        return False
    return bool(libc.mount(b"none", b"/", None, _MS_REC | _MS_PRIVATE, None) == 0)


def _preexec(limits: Limits, uid: Optional[int], nproc: int) -> Callable[[], None]:
    import resource  # noqa: PLC0415 - Unix only: imported here so that the rest of the grader imports anywhere

    def apply() -> None:
        os.setsid()
        resource.setrlimit(resource.RLIMIT_CPU, (limits.cpu_s, limits.cpu_s + 5))
        resource.setrlimit(resource.RLIMIT_AS, (limits.memory_bytes, limits.memory_bytes))
        resource.setrlimit(resource.RLIMIT_FSIZE, (limits.file_bytes, limits.file_bytes))
        resource.setrlimit(resource.RLIMIT_NOFILE, (limits.open_files, limits.open_files))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if uid is not None:
            private_mounts()
            os.setgroups([])
            os.setgid(uid)
            os.setuid(uid)
        # Inside a notebook kernel's box the limit is already set (lower): never ask for more than it.
        hard = resource.getrlimit(resource.RLIMIT_NPROC)[1]
        limit = nproc if hard == resource.RLIM_INFINITY else min(nproc, hard)
        resource.setrlimit(resource.RLIMIT_NPROC, (limit, limit))
    return apply


def describe_exit(code: Optional[int]) -> str:
    """A student-readable sentence for a process' exit status."""
    if code is None:
        return "was still running"
    if code >= 0:
        return f"exited with status {code}"
    sig = -code
    reasons: Dict[int, str] = {
        signal.SIGXFSZ: "was stopped because it wrote more than the output limit (%d MB): remove prints in "
                        "loops" % (OUTPUT_CAP_BYTES // (1024 * 1024)),  # (Python ignores SIGXFSZ: it gets EFBIG)
        signal.SIGXCPU: "was stopped because it used more CPU time than allowed: look for an endless loop",
        signal.SIGKILL: "was killed (SIGKILL): it hung, or used too much memory or CPU",
        signal.SIGSEGV: "crashed (segmentation fault)",
    }
    try:
        name = signal.Signals(sig).name
    except ValueError:
        name = f"signal {sig}"
    return reasons.get(sig, f"was ended by {name}")


def folder_bytes(folder: Path, stop_above: int) -> int:
    """The bytes of the regular files below ``folder`` (links not followed), counted until past ``stop_above``."""
    total = 0
    stack = [str(folder)]
    while stack and total <= stop_above:
        try:
            entries = list(os.scandir(stack.pop()))
        except OSError:
            continue
        for entry in entries:
            try:
                if entry.is_dir(follow_symlinks=False):
                    stack.append(entry.path)
                elif entry.is_file(follow_symlinks=False):
                    total += entry.stat(follow_symlinks=False).st_size
            except OSError:
                continue
    return total


class StudentProcess:
    """One untrusted process: own group (and namespaces), limits, output into a capped log file."""

    def __init__(self, argv: Sequence[str], folder: Path, env: Mapping[str, str], log_path: Path,
                 limits: Limits = DEFAULT_LIMITS, uid: Optional[int] = None, nested: bool = True,
                 network: bool = True, guard: str = "") -> None:
        self.argv = list(argv)
        self.folder = Path(folder)
        self.log_path = Path(log_path)
        self.log_path.parent.mkdir(parents=True, exist_ok=True)
        self.limits = limits
        nproc = limits.processes
        if uid is None and os.geteuid() != 0:
            nproc += uid_process_count(os.geteuid())  # the limit counts all of this user's processes
        env = student_environment(env)
        if guard:  # the reference guard (student_guard) starts first in every Python of this process' tree
            env[GUARD_ENV] = guard
            env["PYTHONPATH"] = os.pathsep.join(p for p in (GUARD_SITE, env.get("PYTHONPATH", "")) if p)
        tmp = self.folder / ".tmp"
        tmp.mkdir(exist_ok=True)
        if uid is not None:
            os.chown(tmp, uid, uid)
        env["TMPDIR"] = str(tmp)
        self._log = open(self.log_path, "wb")
        self.started_s = time.monotonic()
        self._wrapped = not bwrap_problem()
        self.popen = subprocess.Popen(
            self.argv if bwrap_problem() else _student_argv(self.argv, self.folder, nested, network=network, env=env),
            env=dict(env), cwd=str(self.folder),
            stdin=subprocess.DEVNULL, stdout=self._log, stderr=subprocess.STDOUT,
            preexec_fn=_preexec(limits, uid, nproc), close_fds=True,
        )
        self.uid = uid
        self.disk_exceeded = False
        self._watching = threading.Event()
        threading.Thread(target=self._watch_disk, name="student-disk", daemon=True).start()

    def _watch_disk(self) -> None:
        """Until the process ends: what it writes into its folder stays under ``limits.disk_bytes`` in all (each
        file is capped by RLIMIT_FSIZE, but not how many it writes); past that its group is killed and the log
        says why. Checked every :data:`DISK_CHECK_S`, so it overshoots by at most what it writes in that time."""
        while not self._watching.wait(DISK_CHECK_S):
            if self.popen.poll() is not None:
                return
            if folder_bytes(self.folder, self.limits.disk_bytes) > self.limits.disk_bytes:
                self.disk_exceeded = True
                try:
                    os.killpg(self.popen.pid, signal.SIGKILL)
                except (ProcessLookupError, PermissionError):
                    pass
                return

    @property
    def running(self) -> bool:
        return self.popen.poll() is None

    @property
    def returncode(self) -> Optional[int]:
        """The exit status, with bubblewrap's 128 + N for "killed by signal N" turned into -N."""
        code = self.popen.poll()
        if code is not None and self._wrapped and 128 < code < 128 + 65:
            return -(code - 128)
        return code

    def wait(self, timeout_s: float) -> Optional[int]:
        try:
            self.popen.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            return None
        return self.returncode

    def output_tail(self, limit: int = 3000) -> str:
        """The last ``limit`` characters it printed (never the whole, possibly huge, log)."""
        if not self._log.closed:
            self._log.flush()
        try:
            size = self.log_path.stat().st_size
            with open(self.log_path, "rb") as fh:
                fh.seek(max(0, size - limit))
                return fh.read().decode("utf-8", errors="replace")
        except OSError:
            return ""

    def process_count(self) -> int:
        """How many processes (threads included) its uid runs now; 0 when it has no uid of its own."""
        return uid_process_count(self.uid) if self.uid is not None else 0

    def output_size(self) -> int:
        try:
            return self.log_path.stat().st_size
        except OSError:
            return 0

    def stop(self, grace_s: float = 3.0) -> Optional[int]:
        """SIGINT the group (how ROS nodes end cleanly), then SIGTERM, then SIGKILL; kill leftovers."""
        return self._end(((signal.SIGINT, grace_s), (signal.SIGTERM, 1.0), (signal.SIGKILL, 2.0)))

    def kill(self) -> Optional[int]:
        """SIGKILL at once, then the leftovers: for a run whose verdict is recorded (no clean exit needed)."""
        return self._end(((signal.SIGKILL, 2.0),))

    def _end(self, steps: Sequence[Tuple[int, float]]) -> Optional[int]:
        """Each (signal, wait in s) to the group until it has ended; then its leftovers; the log closed."""
        for sig, wait_s in steps:
            if self.popen.poll() is not None:
                break
            try:
                os.killpg(self.popen.pid, sig)
            except (ProcessLookupError, PermissionError):
                pass
            try:
                self.popen.wait(timeout=wait_s)
            except subprocess.TimeoutExpired:
                continue
        self._watching.set()
        self.kill_leftovers()
        if not self._log.closed:
            if self.disk_exceeded:
                self._log.write(f"\nhri-grade: stopped: it wrote more than {self.limits.disk_bytes // 1024 ** 2} MB "
                                "into its folder; write less (no files in a loop)\n".encode())
            self._log.close()
        return self.returncode

    def kill_leftovers(self) -> None:
        """Whatever it spawned that left its group: the group, and (own uid) every process of the uid."""
        try:
            os.killpg(self.popen.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        if self.uid is not None:
            killer = subprocess.Popen([sys.executable, "-c", "import os, signal; os.kill(-1, signal.SIGKILL)"],
                                      preexec_fn=_as_uid(self.uid), stdin=subprocess.DEVNULL,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            killer.wait(timeout=10)
            deadline = time.monotonic() + 3.0
            while self.process_count() and time.monotonic() < deadline:
                time.sleep(0.05)  # killed processes leave /proc once their parents reap them


def _as_uid(uid: int) -> Callable[[], None]:
    def apply() -> None:
        os.setgroups([])
        os.setgid(uid)
        os.setuid(uid)
    return apply
