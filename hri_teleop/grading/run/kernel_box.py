"""The kernel sandbox's launcher: one Jupyter kernel started in a bubblewrap box, and the box's rules.

Jupyter starts it in place of the kernel (:mod:`hri_teleop.grading.run.kernel_sandbox` says how and
why). It imports nothing of the grader's package, which takes half a second to import: it is loaded
from its file, so every notebook's kernel pays only for its box (grading/README.md, "Notebooks'
kernels"). The box's user writes the submission's copy in; Jupyter reaches the sockets via /proc.
"""

from __future__ import annotations

import ctypes
import json
import os
import shutil
import signal
import stat
import subprocess
import sys
import time
import uuid
from dataclasses import dataclass, replace
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.grading.run.sandbox import STUDENT_ENV, private_mounts, student_uid
from hri_teleop.grading.run.view import View, toolkit_view, under, view_argv
from hri_teleop.ros.proc_table import uid_process_count

__all__ = ["POLICY_ENV", "SCRATCH_BYTES", "MEMORY_BYTES", "CPU_S", "PROCESSES", "CHANNEL", "CHECK_RESULTS", "ERROR_MARK",
           "KernelBoxError", "KernelPolicy", "Box", "KERNEL_ENV", "kernel_view", "kernel_environment", "box_uid",
           "launch", "main"]

#: Set (to a :class:`KernelPolicy` as JSON) in the environment of nbgrader's autograde: its kernels are boxed.
POLICY_ENV = "HRI_KERNEL_SANDBOX"
#: The scratch folder's quota: a tmpfs, so memory, and only as much as the kernel writes.
SCRATCH_BYTES = 256 * 1024 ** 2
#: Address space of each process of a kernel's box (the kernel, its roscore, its nodes): a cell that asks for
#: more gets MemoryError instead of taking the grading machine's memory (a kernel once held 17 GB).
MEMORY_BYTES = 4 * 1024 ** 3
#: CPU seconds of each process of a kernel's box: no more than make grade gives a whole submission's notebooks
#: (a busy loop that never yields is ended by SIGXCPU even where a cell's timeout is raised).
CPU_S = 1800
#: Processes and threads of a kernel and all it starts (its roscore, nodes, the check cells' own sandboxes).
PROCESSES = 512
#: The box's /dev/shm (POSIX semaphores of multiprocessing).
SHM_BYTES = 16 * 1024 ** 2
#: The box's own folder (a tmpfs) for the kernel's sockets, its connection file and the stored check results.
CHANNEL = "/run/hri-kernel"
CHANNEL_BYTES = 16 * 1024 ** 2
#: Where the box holds its copy of this submission's stored check results (make grade's files job).
CHECK_RESULTS = CHANNEL + "/check-results"
#: The box's own /tmp (a tmpfs).
TMP_BYTES = 64 * 1024 ** 2
#: Lines the launcher prints when the box cannot start start with this (the grader quotes them).
ERROR_MARK = "kernel sandbox: "
_READY_TIMEOUT_S = 20.0     # bwrap sets up the box in milliseconds; this only guards a hang
_POLL_S = 0.005
_PR_SET_PDEATHSIG = 1
_SOCKETS = ("shell_port", "iopub_port", "stdin_port", "control_port", "hb_port")
#: The kernel's environment, by exact name: what Python, ROS, Jupyter's kernel, the notebooks and their check
#: cells read (grading/README.md, "Notebooks' kernels"); never the grader's tokens or keys, whatever their names.
KERNEL_ENV = frozenset(STUDENT_ENV | {
    "TZ", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NBGRADER_EXECUTION", "HRI_MODE",
    "HRI_NOTEBOOK_FAST", "HRI_GRADE_SEED", "HRI_GRADE_RESULTS", "HRI_GRADE_SANDBOX", "HRI_GRADE_CLOCK",
    "HRI_SIM_KERNEL", "HRI_TRIALS", "CATKIN_SHELL"})
# Run inside the box before the kernel: the launcher ignores SIGINT (Jupyter's interrupt goes to the whole
# process group, bwrap included), the kernel must take it again.
_RESET_SIGINT = "import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); os.execvp(sys.argv[1], sys.argv[1:])"


class KernelBoxError(HriTeleopError, RuntimeError):
    """A kernel's box cannot be set up (one line, starting with :data:`ERROR_MARK`: the cause and the fix)."""


def box_uid() -> Optional[int]:
    """As root: an unprivileged uid for what this process (and thread) starts; None otherwise."""
    return student_uid()


@dataclass(frozen=True)
class KernelPolicy:
    """What one submission's kernels get: ``hidden`` folders of the instructor's (the course, OUT: masked
    should they lie inside what the box shows, :func:`kernel_view`), ``check_results`` the host folder of this submission's stored check results
    (copied into the box), the scratch quota and the process limit. ``own_proc`` False: the box shows the
    machine's /proc instead of mounting its own (in a container that forbids the mount: Gradescope's)."""

    hidden: Tuple[str, ...] = ()
    check_results: str = ""
    scratch_bytes: int = SCRATCH_BYTES
    processes: int = PROCESSES
    own_proc: bool = True
    memory_bytes: int = MEMORY_BYTES
    cpu_s: int = CPU_S

    def to_json(self) -> str:
        return json.dumps({"hidden": list(self.hidden), "check_results": self.check_results,
                           "scratch_bytes": self.scratch_bytes, "processes": self.processes,
                           "own_proc": self.own_proc, "memory_bytes": self.memory_bytes, "cpu_s": self.cpu_s})

    @staticmethod
    def from_json(text: str) -> "KernelPolicy":
        try:
            data = json.loads(text)
            return KernelPolicy(tuple(str(p) for p in data.get("hidden", ())), str(data.get("check_results", "")),
                                int(data.get("scratch_bytes", SCRATCH_BYTES)), int(data.get("processes", PROCESSES)),
                                data.get("own_proc", True) is not False,
                                int(data.get("memory_bytes", MEMORY_BYTES)), int(data.get("cpu_s", CPU_S)))
        except (ValueError, TypeError, AttributeError) as exc:
            raise KernelBoxError(f"{POLICY_ENV}: not a kernel sandbox policy ({exc}); make grade sets it, unset it") \
                from None


def kernel_environment(env: Mapping[str, str], home: str, tmp: str) -> Dict[str, str]:
    """The kernel's environment: the variables of :data:`KERNEL_ENV` that ``env`` has (an exact list: no prefix
    lets a token through), HOME and TMPDIR in its scratch folder, and JPY_PARENT_PID 1: its parent is the box's
    init, pid 1 (Jupyter's pid would look gone to ipykernel's parent poller, which then ends the kernel; 1 turns
    the poller off, and the box ends with its launcher)."""
    kept = {k: v for k, v in env.items() if k in KERNEL_ENV}
    kept.update({"HOME": home, "TMPDIR": tmp, "USER": "student", "LOGNAME": "student", "JPY_PARENT_PID": "1"})
    return kept


def _reachable(path: str, uid: Optional[int]) -> bool:
    """Whether the box's user can reach ``path`` on the host: every folder above it lets others through
    (as root, the box runs under a uid of its own that owns nothing and is in no group)."""
    if not os.path.exists(path):
        return False
    if uid is None:
        return os.access(path, os.R_OK)
    parent = os.path.dirname(path)
    while True:
        try:
            if not os.stat(parent).st_mode & stat.S_IXOTH:
                return False
        except OSError:
            return False
        if parent == "/":
            return True
        parent = os.path.dirname(parent)


def kernel_view(policy: KernelPolicy, env: Mapping[str, str], uid: Optional[int]) -> View:
    """What a kernel's box shows (:func:`hri_teleop.grading.run.view.toolkit_view`: the system, Python and the
    toolkit without the answers, read-only; nothing else), with ``policy.hidden`` masked where it lies inside
    a shown folder, and only what the box's user can reach (bwrap, as that user, reads what it binds)."""
    view = toolkit_view(env)
    hidden = tuple(h for h in map(os.path.normpath, policy.hidden) if any(under(h, s) for s in view.shown))
    return replace(view, shown=tuple(p for p in view.shown if _reachable(p, uid)),
                   masked_files=tuple(p for p in view.masked_files if _reachable(p, uid)),
                   masked_folders=tuple(p for p in (*view.masked_folders, *hidden) if _reachable(p, uid)))


def _bwrap_argv(exe: str, view: View, cwd: str, policy: KernelPolicy, marker: str,
                info_fd: int, block_fd: int) -> List[str]:
    proc = ["--proc", "/proc"] if policy.own_proc else ["--ro-bind", "/proc", "/proc"]
    argv = [exe, "--unshare-user", "--unshare-pid", "--unshare-net", "--unshare-ipc", "--unshare-uts",
            "--unshare-cgroup-try", "--die-with-parent", "--cap-drop", "ALL", *view_argv(view, proc, TMP_BYTES),
            "--size", str(SHM_BYTES), "--tmpfs", "/dev/shm", "--remount-ro", "/dev",
            "--size", str(policy.scratch_bytes), "--tmpfs", cwd, "--size", str(CHANNEL_BYTES), "--tmpfs", CHANNEL,
            "--remount-ro", "/", "--dir", marker, "--chdir", cwd,
            "--info-fd", str(info_fd), "--block-fd", str(block_fd)]
    return argv


def _prctl_pdeathsig() -> None:
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):
        pass


#: A file tree read by the launcher: (path relative to its root, "d" | "f" | "l", mode, bytes or link target).
_Tree = List[Tuple[str, str, int, bytes]]


def _read_tree(root: str, budget: int) -> _Tree:
    """``root``'s folders, files and links (nothing else), read as the launcher; KernelBoxError past ``budget`` bytes."""
    tree: _Tree = []
    total = 0
    for dirpath, dirnames, filenames in os.walk(root):
        for name in sorted(dirnames + filenames):
            full = os.path.join(dirpath, name)
            rel = os.path.relpath(full, root)
            st = os.lstat(full)
            if stat.S_ISLNK(st.st_mode):
                tree.append((rel, "l", 0, os.fsencode(os.readlink(full))))
            elif stat.S_ISDIR(st.st_mode):
                tree.append((rel, "d", stat.S_IMODE(st.st_mode), b""))
            elif stat.S_ISREG(st.st_mode):
                total += st.st_size
                if total > budget:
                    raise KernelBoxError(f"{ERROR_MARK}the submission holds more than the scratch folder's "
                                       f"{budget // 1024 ** 2} MB; the student must hand in less")
                fd = os.open(full, os.O_RDONLY | os.O_NOFOLLOW)
                with os.fdopen(fd, "rb") as fh:
                    tree.append((rel, "f", stat.S_IMODE(st.st_mode), fh.read()))
    return tree


def _write_tree(tree: _Tree, target: str) -> None:
    os.makedirs(target, exist_ok=True)
    modes = []
    for rel, kind, mode, data in tree:
        path = os.path.join(target, rel)
        if kind == "d":
            os.mkdir(path, 0o700)
            modes.append((path, mode | stat.S_IRWXU))
        elif kind == "l":
            os.symlink(os.fsdecode(data), path)
        else:
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            with os.fdopen(fd, "wb") as fh:
                fh.write(data)
            os.chmod(path, mode | stat.S_IRUSR | stat.S_IWUSR)
    for path, mode in reversed(modes):
        os.chmod(path, mode)


class Box:
    """One bubblewrap box being set up: started blocked, filled from outside, then let run."""

    def __init__(self, command: Sequence[str], cwd: str, policy: KernelPolicy, env: Mapping[str, str],
                 stderr: Optional[int] = None) -> None:
        exe = shutil.which("bwrap", path=env.get("PATH"))
        if exe is None:
            raise KernelBoxError(f"{ERROR_MARK}bubblewrap (bwrap) is not installed; apt-get install bubblewrap")
        self.uid = box_uid()
        self.cwd = cwd
        self.marker = f"{CHANNEL}/.ready-{uuid.uuid4().hex}"
        info_r, info_w = os.pipe()
        block_r, self._block_w = os.pipe()
        nproc = policy.processes + (uid_process_count(os.geteuid()) if self.uid is None else 0)
        argv = _bwrap_argv(exe, kernel_view(policy, env, self.uid), cwd, policy, self.marker, info_w, block_r)
        argv += ["--", sys.executable, "-I", "-S", "-c", _RESET_SIGINT, *command]
        home = os.path.join(cwd, ".home")
        self.env = kernel_environment(env, home, os.path.join(cwd, ".tmp"))
        uid, quota, memory, cpu_s = self.uid, policy.scratch_bytes, policy.memory_bytes, policy.cpu_s

        def limits() -> None:
            import resource  # noqa: PLC0415 - Unix only: imported where it runs

            resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
            resource.setrlimit(resource.RLIMIT_FSIZE, (quota, quota))  # the inherited log files too
            resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
            resource.setrlimit(resource.RLIMIT_CPU, (cpu_s, cpu_s + 5))
            if uid is not None:
                private_mounts()
                os.setgroups([])
                os.setgid(uid)
                os.setuid(uid)
            resource.setrlimit(resource.RLIMIT_NPROC, (nproc, nproc))
            _prctl_pdeathsig()  # after setuid, which clears it

        try:
            self.process = subprocess.Popen(argv, env=self.env, cwd="/", pass_fds=(info_w, block_r),
                                            preexec_fn=limits, close_fds=True, stderr=stderr)
        finally:
            os.close(info_w)
            os.close(block_r)
        self.child = self._child_pid(info_r)

    def _child_pid(self, info_r: int) -> int:
        data = b""
        try:
            while True:
                chunk = os.read(info_r, 4096)
                if not chunk:
                    break
                data += chunk
                try:
                    return int(json.loads(data)["child-pid"])
                except (ValueError, KeyError):
                    continue
        finally:
            os.close(info_r)
        self.process.wait()
        raise KernelBoxError(f"{ERROR_MARK}bwrap could not set up the kernel's box (exit status "
                           f"{self.process.returncode}; its message is above)")

    @property
    def root(self) -> str:
        """The box's / as seen from outside."""
        return f"/proc/{self.child}/root"

    def wait_ready(self) -> None:
        """Until every mount is in place (the last one leaves the marker), or KernelBoxError."""
        deadline = time.monotonic() + _READY_TIMEOUT_S
        while not os.path.isdir(self.root + self.marker):
            if self.process.poll() is not None:
                raise KernelBoxError(f"{ERROR_MARK}bwrap ended while it set up the kernel's box (exit status "
                                   f"{self.process.returncode}; its message is above)")
            if time.monotonic() > deadline:
                raise KernelBoxError(f"{ERROR_MARK}bwrap did not set up the kernel's box within {_READY_TIMEOUT_S:.0f} s")
            time.sleep(_POLL_S)

    def fill(self, trees: Sequence[Tuple[_Tree, str]], files: Sequence[Tuple[str, bytes]]) -> None:
        """Write ``trees`` (each at a path in the box) and ``files`` (path, bytes) as the box's user,
        which the box's tmpfs takes (as root the launcher could not: its uid is not mapped in there)."""
        pid = os.fork()
        if pid == 0:  # pragma: no cover - the child's own exit status says how it went
            code = 0
            try:
                if self.uid is not None:
                    os.setgroups([])
                    os.setgid(self.uid)
                    os.setuid(self.uid)
                for tree, where in trees:
                    _write_tree(tree, self.root + where)
                for where, data in files:
                    fd = os.open(self.root + where, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
                    with os.fdopen(fd, "wb") as fh:
                        fh.write(data)
            except OSError as exc:
                print(f"{ERROR_MARK}cannot fill the kernel's scratch folder ({exc.strerror}: {exc.filename})",
                      file=sys.stderr, flush=True)
                code = 1
            os._exit(code)
        _pid, status = os.waitpid(pid, 0)
        if os.WEXITSTATUS(status) if os.WIFEXITED(status) else 1:
            raise KernelBoxError(f"{ERROR_MARK}the kernel's scratch folder could not be filled (see above)")

    def release(self) -> None:
        os.write(self._block_w, b"go")
        os.close(self._block_w)

    def kill(self) -> None:
        try:
            self.process.kill()
        except OSError:
            pass
        self.process.wait()


def _connection(path: str) -> Dict[str, Any]:
    with open(path, encoding="utf-8") as fh:
        info: Dict[str, Any] = json.load(fh)
    if info.get("transport") != "ipc":
        raise KernelBoxError(f"{ERROR_MARK}{path}: the kernel's transport is {info.get('transport')!r}; the box "
                           "needs ipc (--KernelManager.transport=ipc, as make grade sets)")
    return info


def _seeds(home: str) -> List[Tuple[_Tree, str]]:
    """The grader's caches a fresh home should have (matplotlib's font list: without it matplotlib warns on
    stderr, which nbgrader scores as a failed cell; the lab's live graph), copied into the box's home."""
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    found = []
    for source, target in ((os.path.join(cache, "matplotlib"), ".cache/matplotlib"),
                           (os.path.join(cache, "hri-teleop"), ".cache/hri-teleop")):
        if os.path.isdir(source):
            try:
                found.append((_read_tree(source, CHANNEL_BYTES), os.path.join(home, target)))
            except (OSError, KernelBoxError):
                continue  # a cache the kernel rebuilds
    return found


def _link_sockets(info: Mapping[str, Any], root: str) -> List[str]:
    """``ip-port`` for each of the kernel's sockets, a link to where the kernel binds it in the box."""
    made = []
    for name in _SOCKETS:
        link = f"{info['ip']}-{info[name]}"
        tmp = f"{link}.{os.getpid()}.tmp"
        os.symlink(f"{root}{CHANNEL}/k-{info[name]}", tmp)
        os.replace(tmp, link)
        made.append(link)
    return made


def launch(command: Sequence[str], connection_file: str, policy: KernelPolicy) -> int:
    """The launcher: the kernel ``command`` in a box at this process' folder; its exit status."""
    cwd = os.getcwd()
    info = _connection(connection_file)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Jupyter's interrupt is for the kernel (it takes it back)
    inner = dict(info, ip=f"{CHANNEL}/k")
    inside = f"{CHANNEL}/connection.json"
    command = [inside if arg == connection_file else arg for arg in command]
    submission = _read_tree(cwd, policy.scratch_bytes)
    results = _read_tree(policy.check_results, CHANNEL_BYTES) if os.path.isdir(policy.check_results) else []
    box = Box(command, cwd, policy, os.environ)
    links: List[str] = []

    def stop(signum: int, _frame: Any) -> None:
        box.kill()
        _unlink(links)
        os._exit(128 + signum)

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGHUP, stop)
    try:
        box.wait_ready()
        home = box.env["HOME"]
        trees = [(submission, cwd), *_seeds(home), ([], box.env["TMPDIR"])]
        if results:
            trees.append((results, CHECK_RESULTS))
        box.fill(trees, [(inside, json.dumps(inner).encode())])
        links = _link_sockets(info, box.root)
        box.release()
    except (KernelBoxError, OSError) as exc:
        box.kill()
        _unlink(links)
        print(exc if isinstance(exc, KernelBoxError) else f"{ERROR_MARK}{exc}", file=sys.stderr, flush=True)
        return 1
    code = box.process.wait()
    _unlink(links)
    return code if code >= 0 else 128 - code


def _unlink(links: Sequence[str]) -> None:
    for link in links:
        try:
            os.unlink(link)
        except OSError:
            pass


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``kernel_box.py --connection-file F --policy JSON -- KERNEL...``, run by its path (kernel_sandbox)."""
    args = list(sys.argv[1:] if argv is None else argv)
    try:
        split = args.index("--")
        options = dict(zip(args[:split:2], args[1:split:2]))
        command = args[split + 1:]
        if not command or set(options) != {"--connection-file", "--policy"}:
            raise ValueError
    except ValueError:
        print("usage: kernel_box.py --connection-file FILE --policy JSON -- KERNEL COMMAND... (make grade runs it)",
              file=sys.stderr)
        return 2
    try:
        return launch(command, options["--connection-file"], KernelPolicy.from_json(options["--policy"]))
    except (KernelBoxError, OSError) as exc:
        print(exc if isinstance(exc, KernelBoxError) else f"{ERROR_MARK}{exc}", file=sys.stderr, flush=True)
        return 1


if __name__ == "__main__":
    sys.exit(main())
