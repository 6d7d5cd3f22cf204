"""A private ROS master for tests, demos and notebooks, and the processes that run on it.

Every test and demo needs a real ``roscore`` nobody else talks to, on a free port (never 11311),
and must leave nothing behind: children start in their own process group, so stopping one stops
what it spawned (roslaunch starts nodes, roscore starts rosmaster and rosout). The master is
reached over XML-RPC and the ROS command-line tools, never rospy, so a test process can use many
masters one after another.
"""

from __future__ import annotations

import os
import shutil
import socket
import sys
import tempfile
import time
import xmlrpc.client
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Set, Tuple

from hri_teleop.core.paths import REPO
from hri_teleop.ros.master_api import MasterApiError, master_call
from hri_teleop.ros.master_core import PORT_TAKEN, core_params, rosmaster_argv, rosout_argv, rosout_program
from hri_teleop.ros.proc_table import descendants
from hri_teleop.ros.processes import (
    LIVE_PROCESSES,
    ManagedProcess,
    MasterError,
    interrupt_nodes,
    stop_all,
    stop_side_by_side,
)

__all__ = ["uri_key", "OWN_MASTER_ENV", "Registrations", "started_here", "lab_shell_env", "finds_hri_lab", "free_port",
           "PrivateMaster", "RunningMaster", "run_reporting",
           # where the callers have always imported them from (hri_teleop.ros.processes)
           "LIVE_PROCESSES", "ManagedProcess", "MasterError", "interrupt_nodes", "stop_all", "stop_side_by_side"]

#: (topic or service, [node, ...]): one entry of the master's getSystemState.
Registrations = List[Tuple[str, List[str]]]

#: Set for the processes a PrivateMaster's owner starts: "URI PID" of the master (its rosmaster's pid).
OWN_MASTER_ENV = "HRI_OWN_MASTER"
#: The masters this process started (URI -> its roscore): :func:`started_here` asks it.
_OWN_MASTERS: "Dict[str, ManagedProcess]" = {}


def uri_key(uri: str) -> str:
    """``http://localhost:N/`` and ``http://127.0.0.1:N`` name the same master."""
    rest = uri.strip().rstrip("/")
    rest = rest[len("http://"):] if rest.startswith("http://") else rest
    host, _, port = rest.rpartition(":")
    return f"{'127.0.0.1' if host in ('localhost', '127.0.0.1', '') else host}:{port}"


def started_here(uri: str, env: Optional[Mapping[str, str]] = None, timeout_s: float = 1.0) -> bool:
    """True when the master at ``uri`` is a roscore this process, or the process that started
    this one (``$HRI_OWN_MASTER``, set by :class:`PrivateMaster` for its children), started.

    Asked of the master itself: its pid must be the one recorded at its start, so a port
    taken over by somebody else's master, or a copied setting, is not ours.
    """
    key = uri_key(uri)
    core = _OWN_MASTERS.get(key)
    if core is not None and not core.running:
        core = None
    if core is None:
        mark = (os.environ if env is None else env).get(OWN_MASTER_ENV, "").split()
        if len(mark) != 2 or uri_key(mark[0]) != key or not mark[1].isdigit():
            return False
        expected = int(mark[1])
    try:
        pid = master_call("getPid", uri=uri, timeout_s=timeout_s)
    except MasterApiError:
        return False
    if core is None:
        return bool(pid == expected)
    root = core.popen.pid
    return pid == root or pid in descendants(root)


def lab_shell_env(base: Optional[Mapping[str, str]] = None, venv_bin: Optional[Path] = None,
                  package_root: Optional[Path] = None) -> Dict[str, str]:
    """The environment ``tools/env.sh`` gives, for processes started from Python.

    ``venv_bin`` first on PATH (default: this interpreter's folder, so a node's
    ``#!/usr/bin/env python3`` finds rospy and hri_teleop), ``package_root``'s ``hri_lab``
    (default: the repository's) first on ROS_PACKAGE_PATH, and Debian's ``/usr/share``
    package manifests when no ROS distribution was sourced (with make setup's manifests of
    Debian's message definitions, ``.venv/share/hri-ros-msgs``). The package folder itself, not
    ``package_root``: rospack searches subfolders, and a copy of hri_lab under ``out/``
    would shadow the lab's.
    """
    env = dict(os.environ if base is None else base)
    venv = str(venv_bin if venv_bin is not None else Path(sys.executable).parent)
    if venv not in env.get("PATH", "").split(":"):
        env["PATH"] = venv + ":" + env.get("PATH", "/usr/bin:/bin")
    root = Path(package_root if package_root is not None else REPO).resolve()
    package = root / "hri_lab" if (root / "hri_lab" / "package.xml").is_file() else root
    paths = [p for p in env.get("ROS_PACKAGE_PATH", "").split(":") if p and Path(p).resolve() not in (root, package)]
    paths.insert(0, str(package))
    if not env.get("ROS_DISTRO") and "/usr/share" not in paths:
        paths.append("/usr/share")
    manifests = Path(venv).parent / "share" / "hri-ros-msgs"  # make setup's, for Debian's message definitions
    if not env.get("ROS_DISTRO") and manifests.is_dir() and str(manifests) not in paths:
        paths.append(str(manifests))
    env["ROS_PACKAGE_PATH"] = ":".join(paths)
    return env


def finds_hri_lab(entry: str) -> bool:
    """True when rospack would find an hri_lab through this ROS_PACKAGE_PATH entry directly:
    the package folder itself or the folder holding it (what must not shadow a student's)."""
    folder = Path(entry)
    return (folder / "hri_lab" / "package.xml").is_file() or (
        folder.name == "hri_lab" and (folder / "package.xml").is_file())


def free_port() -> int:
    """A TCP port nobody listens on right now (the kernel's choice, never 11311)."""
    while True:
        with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
            sock.bind(("127.0.0.1", 0))
            port = int(sock.getsockname()[1])
        if port != 11311:
            return port


class PrivateMaster:
    """A private master on a free port with its own log directory; a context manager.

    What roscore starts (rosmaster, rosout, its parameters), without roscore's own process unless
    ``roscore``. ``env`` is the environment to give every ROS process meant to talk to this master.
    """

    def __init__(self, port: Optional[int] = None, base_env: Optional[Mapping[str, str]] = None,
                 work_dir: Optional[Path] = None, roscore: bool = False) -> None:
        #: ``roscore`` itself rather than what it starts (:mod:`~hri_teleop.ros.master_core`): the lab twin's.
        self._roscore = roscore
        self._rosout: Optional[ManagedProcess] = None
        self._auto_port = port is None  # a port of our own choice may be taken again: start() picks another
        self.port = port or free_port()
        self.uri = f"http://127.0.0.1:{self.port}/"
        self._own_dir = work_dir is None
        self.work_dir = Path(work_dir) if work_dir else Path(tempfile.mkdtemp(prefix="hri-ros-"))
        env = dict(base_env if base_env is not None else os.environ)
        env.update({
            "ROS_MASTER_URI": self.uri,
            "ROS_HOSTNAME": "127.0.0.1",
            "ROS_LOG_DIR": str(self.work_dir / "log"),
            "ROS_HOME": str(self.work_dir / "home"),
            "PYTHONUNBUFFERED": "1",
        })
        env.pop("ROS_IP", None)
        self.env: Dict[str, str] = env
        self.core: Optional[ManagedProcess] = None
        self.children: List[ManagedProcess] = []
        self.started: List[ManagedProcess] = []  # everything ever started here, for leak checks

    # -- lifecycle -------------------------------------------------------------------
    def start(self, timeout_s: float = 20.0, attempts: int = 3) -> "PrivateMaster":
        """Start the master and wait until /rosout is up.

        Between free_port() and the master's bind, any process may take the port for an outgoing
        connection (ROS nodes open many): then, on a port of our own choice, a fresh one is tried.
        """
        rosout = None if self._roscore else rosout_program(self.env)
        for attempt in range(attempts):
            argv = rosmaster_argv(self.port) if rosout else ["roscore", "-p", str(self.port)]
            self.core = ManagedProcess(argv, self.env, self.work_dir / "roscore.log", is_master=True)
            self.started.append(self.core)
            deadline = time.monotonic() + timeout_s
            while time.monotonic() < deadline:
                problem = self._start_problem()
                if problem:
                    self._stop_core(quick=True)
                    if self._auto_port and problem == "taken" and attempt + 1 < attempts:
                        self._move_to(free_port())
                        break
                    raise MasterError(f"the ROS master on port {self.port} exited: {problem}")
                if rosout and self._rosout is None and self.is_online():
                    for name, value in core_params(self.env).items():
                        self.set_param(name, value)
                    self._rosout = ManagedProcess(rosout_argv(rosout, Path(self.env["ROS_LOG_DIR"])), self.env,
                                                  self.work_dir / "rosout.log", is_master=True)
                    self.started.append(self._rosout)
                if self.is_online() and "/rosout" in self.node_names():
                    _OWN_MASTERS[uri_key(self.uri)] = self.core
                    self.env[OWN_MASTER_ENV] = f"{self.uri} {self.master_pid()}"
                    return self
                time.sleep(0.02 if rosout else 0.1)
            else:
                self.stop()
                raise MasterError(f"the ROS master on port {self.port} did not come up within {timeout_s:.0f} s")
        raise MasterError(f"the ROS master found no free port in {attempts} attempts")  # pragma: no cover

    def _start_problem(self) -> str:
        """Why the starting master cannot serve: "taken" (its port), another reason, or "" (none yet)."""
        assert self.core is not None
        output = self.core.output() if not self.core.running or self._rosout is None else ""
        if "Address already in use" in output or PORT_TAKEN in output:
            return "taken"
        if not self.core.running:
            return output.strip()[-400:] or f"status {self.core.popen.returncode}"
        if self._rosout is not None and not self._rosout.running:
            return "rosout exited: " + self._rosout.output().strip()[-400:]
        if self.core.argv[0] == "rosmaster" and self.is_online() and self.master_pid() != self.core.popen.pid:
            return "taken"  # another master answers there
        return ""

    def _stop_core(self, quick: bool) -> None:
        """Stop rosout and the master (roscore: with everything it started); killed when ``quick``."""
        for proc in (self._rosout, self.core):
            if proc is not None:
                proc.kill() if quick else proc.stop()
        self._rosout = None
        self.core = None

    @property
    def core_processes(self) -> List[ManagedProcess]:
        """What runs the master itself: rosmaster and rosout, or roscore."""
        return [p for p in (self.core, self._rosout) if p is not None]

    @property
    def core_pids(self) -> List[int]:
        """The pids of the master's own processes, roscore's children included."""
        procs = [p for p in self.core_processes if p.running]
        return [pid for p in procs for pid in [p.popen.pid, *descendants(p.popen.pid)]]

    def _move_to(self, port: int) -> None:
        self.port = port
        self.uri = f"http://127.0.0.1:{port}/"
        self.env["ROS_MASTER_URI"] = self.uri

    def stop(self, quick: bool = False) -> None:
        """Stop what was started here, newest first, then roscore.

        ``quick``: the children are stopped side by side and roscore is killed rather than
        asked (its clean shutdown takes 0.6 s and keeps nothing anyone reads): the grader's way.
        """
        if quick:
            stop_side_by_side(list(self.children))
        for child in reversed(self.children):
            child.stop()
        self.children.clear()
        if self.core is not None:
            _OWN_MASTERS.pop(uri_key(self.uri), None)
        self._stop_core(quick)
        if self._own_dir:
            shutil.rmtree(self.work_dir, ignore_errors=True)

    def __enter__(self) -> "PrivateMaster":
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # -- talking to the master -----------------------------------------------------------
    def _proxy(self) -> Any:  # XML-RPC answers are untyped lists
        return xmlrpc.client.ServerProxy(self.uri)

    def master_pid(self) -> int:
        """The pid of the rosmaster answering at this URI."""
        return int(master_call("getPid", uri=self.uri))

    def is_online(self) -> bool:
        try:
            code, _, _ = self._proxy().getPid("/hri_probe")
            return bool(code == 1)
        except (OSError, xmlrpc.client.Error):
            return False

    def system_state(self) -> Tuple[Registrations, Registrations, Registrations]:
        """(publishers, subscribers, services), each as (name, [node, ...]) pairs."""
        code, msg, state = self._proxy().getSystemState("/hri_probe")
        if code != 1:
            raise MasterError(f"master at {self.uri} refused getSystemState: {msg}")
        pubs, subs, srvs = ([(name, list(nodes)) for name, nodes in part] for part in state)
        return pubs, subs, srvs

    def node_names(self) -> Set[str]:
        pubs, subs, srvs = self.system_state()
        return {n for _, nodes in list(pubs) + list(subs) + list(srvs) for n in nodes}

    def publishers(self, topic: str) -> List[str]:
        return next((nodes for t, nodes in self.system_state()[0] if t == topic), [])

    def subscribers(self, topic: str) -> List[str]:
        return next((nodes for t, nodes in self.system_state()[1] if t == topic), [])

    def topic_types(self) -> Dict[str, str]:
        code, msg, types = self._proxy().getTopicTypes("/hri_probe")
        if code != 1:
            raise MasterError(f"master at {self.uri} refused getTopicTypes: {msg}")
        return dict(types)

    def get_param(self, name: str) -> object:
        code, msg, value = self._proxy().getParam("/hri_probe", name)
        if code != 1:
            raise MasterError(f"parameter {name} is not set: {msg}")
        return value

    def set_param(self, name: str, value: object) -> None:
        self._proxy().setParam("/hri_probe", name, value)

    def wait_for(self, condition: Callable[[], bool], timeout_s: float, what: str, poll_s: float = 0.05) -> None:
        """Poll ``condition()`` until true; MasterError naming ``what`` on timeout."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if condition():
                return
            time.sleep(poll_s)
        raise MasterError(f"timed out after {timeout_s:.0f} s waiting for {what}")

    # -- processes on this master ------------------------------------------------------
    def run(self, argv: Sequence[str], name: str, extra_env: Optional[Mapping[str, str]] = None,
            cwd: Optional[Path] = None) -> ManagedProcess:
        env = dict(self.env)
        env.update(extra_env or {})
        proc = ManagedProcess(argv, env, self.work_dir / f"{name}.log", cwd=cwd)
        self.children.append(proc)
        self.started.append(proc)
        return proc

    def roslaunch(self, package: str, launch_file: str, args: Optional[Mapping[str, object]] = None,
                  name: Optional[str] = None) -> ManagedProcess:
        argv = ["roslaunch", "--wait", package, launch_file]
        argv += [f"{k}:={v}" for k, v in (args or {}).items()]
        return self.run(argv, name or Path(launch_file).stem)

    def connections(self, node: str, topic: str, direction: str = "i") -> int:
        """How many connections ``node`` has on ``topic`` now, by its own bus info (as ``rosnode
        info`` reads it): ``direction`` "i" to publishers it subscribes to, "o" to subscribers.

        The master only knows who registered; a connection may still be forming, and a
        publisher sends a message only to the connections it has counted.
        """
        try:
            code, _msg, uri = self._proxy().lookupNode("/hri_probe", node)
            if code != 1:
                return 0
            node_api: Any = xmlrpc.client.ServerProxy(uri)  # XML-RPC answers are untyped lists
            code, _msg, bus = node_api.getBusInfo("/hri_probe")
        except (OSError, xmlrpc.client.Error):
            return 0
        return sum(1 for c in bus if code == 1 and len(c) > 5 and c[2] == direction and c[4] == topic and c[5])

    def record(self, bag_path: Path, topics: Sequence[str], timeout_s: float = 15.0) -> ManagedProcess:
        """``rosbag record`` the topics into ``bag_path``; returns once it is connected to every
        publisher each topic has now (a topic without one yet: once it has subscribed)."""
        recorder = f"/record_{Path(bag_path).stem}_{os.getpid()}_{len(self.started)}".replace("-", "_")
        proc = self.run(["rosbag", "record", "--tcpnodelay", "-O", str(bag_path), f"__name:={recorder[1:]}",
                         *topics], f"record-{Path(bag_path).stem}")

        def connected(topic: str) -> bool:
            if recorder not in self.subscribers(topic):
                return False
            return self.connections(recorder, topic) >= len(self.publishers(topic))

        self.wait_for(lambda: all(connected(t) for t in topics) or not proc.running,
                      timeout_s, f"rosbag record to connect to {', '.join(topics)}")
        if not proc.running:
            raise MasterError(f"rosbag record exited: {proc.output().strip()[-400:]}")
        return proc


class RunningMaster(PrivateMaster):
    """A master someone else started (the lab PC's ``roscore``): run processes on it, never stop it.

    Same interface as :class:`PrivateMaster` -- ``record``, ``roslaunch``, ``run`` -- so the
    code that records a trial does not care whose master it is.  :meth:`start` only checks
    that the master answers (one line naming the URI and how to start one otherwise);
    :meth:`stop` stops what was started *here* and leaves the master, and every node that
    was already running on it, alone.  The environment keeps the caller's ROS settings
    (``ROS_HOSTNAME``/``ROS_IP``, log and home folders) and only points ``ROS_MASTER_URI``
    at ``uri``.
    """

    def __init__(self, uri: str, base_env: Optional[Mapping[str, str]] = None,
                 work_dir: Optional[Path] = None) -> None:
        uri = str(uri).strip()
        host_port = uri[len("http://"):].rstrip("/") if uri.startswith("http://") else ""
        host, _, port = host_port.rpartition(":")
        if not host or not port.isdigit():
            raise MasterError(f"master URI {uri!r} is not of the form http://HOST:PORT/; "
                              "e.g. http://localhost:11311/ (echo $ROS_MASTER_URI in the lab's terminal)")
        env = dict(base_env if base_env is not None else os.environ)
        super().__init__(port=int(port), base_env=env, work_dir=work_dir)
        self.uri = f"http://{host_port}/"
        self.env = dict(env)
        self.env.update({"ROS_MASTER_URI": self.uri, "PYTHONUNBUFFERED": "1"})

    def start(self, timeout_s: float = 3.0, attempts: int = 1) -> "RunningMaster":
        """Wait for the running master (``attempts``: PrivateMaster's, nothing to retry here)."""
        deadline = time.monotonic() + timeout_s
        while not self.is_online():
            if time.monotonic() >= deadline:
                self.stop()
                raise MasterError(f"no ROS master is running at {self.uri}: start it with `roscore` in another "
                                  "terminal (or the lab's robot launch), check ROS_MASTER_URI, or record on a "
                                  "private roscore instead (leave out --lab / --master-uri)")
            time.sleep(0.1)
        return self

    def stop(self, quick: bool = False) -> None:
        """Stop what was started here; the master is somebody else's (``quick``: as PrivateMaster's)."""
        for child in reversed(self.children):
            child.stop()
        self.children.clear()
        if self._own_dir:
            shutil.rmtree(self.work_dir, ignore_errors=True)


def run_reporting(call: Callable[[], int], name: str = "demo") -> int:
    """Run a command-line job that starts ROS processes; its failures become one line.

    A MasterError (a roscore or launch that would not start or failed) is printed as
    ``name: message`` with exit status 1; Ctrl-C gives 130. Every process the job started
    is stopped by then (PrivateMaster's context manager and the exit hook).
    """
    try:
        return call()
    except MasterError as exc:
        print(f"{name}: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"{name}: interrupted; everything it started has been stopped", file=sys.stderr)
        return 130
