"""The lab twin: a private master that looks to every notebook and node like the lab PC's, and counts what reaches it.

:class:`LabTwin` starts a roscore on a free port (never 11311), the board on a pty and the lab's
nodes under the lab's names -- nothing else on the graph -- and carries the lab PC's installed
franka_control and rosserial_python, so a student's launch runs on it (``nodes_running=False``: the
lab PC before anybody launched anything). ``env`` is what a kernel gets; ``report()`` what reached
the hardware; ``press``/``set_activated`` play the person at the piston and at the user stop.
"""

from __future__ import annotations

import sys
import time
import xmlrpc.client
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence

from hri_teleop.core.config import DEFAULT_TWIST_TOPIC
from hri_teleop.core.rosserial_frames import ROSSERIAL_BAUD
from hri_teleop.hardware.sim.rosserial_board import FULL_PRESS_COUNT
from hri_teleop.ros.lab_twin.board import COUNTS_NODE, request_press
from hri_teleop.ros.lab_twin.counts import TWIN_DIR_ENV, counts_path, read_json, write_activated
from hri_teleop.ros.lab_twin.packages import PACKAGES_DIR, found_elsewhere, write_packages
from hri_teleop.ros.lab_twin.report import NODES, TwinReport, read_report
from hri_teleop.ros.master import (
    OWN_MASTER_ENV,
    ManagedProcess,
    MasterError,
    PrivateMaster,
    lab_shell_env,
    stop_side_by_side,
)
from hri_teleop.ros.master_api import running_nodes

__all__ = ["LabTwin", "MODULES", "DEFAULT_PUBLISH_PERIOD_MS", "START_TIMEOUT_S"]

#: The module each twin node runs.
MODULES = {"/franka_control": "hri_teleop.ros.lab_twin.franka_control",
           "/franka_gripper": "hri_teleop.ros.lab_twin.franka_gripper",
           "/joint_state_publisher": "hri_teleop.ros.lab_twin.joint_state_publisher",
           "/serial_node": "hri_teleop.ros.lab_twin.serial_node"}
#: serial_node's ~publish_period_ms, as teleoperation.launch sets it (10 ms: 100 Hz).
DEFAULT_PUBLISH_PERIOD_MS = 10
#: How long the whole twin may take to come up (s): four Python nodes on a busy 2-core machine.
START_TIMEOUT_S = 90.0
#: How long press() and set_activated() wait for the twin to take them (s).
ACK_TIMEOUT_S = 10.0
_GRIPPER_ACTIONS = ("move", "grasp", "homing", "stop")


class LabTwin:
    """The twin in ``work_dir`` (its counts files, logs, installed packages and the master's folder); a
    context manager. ``nodes_running`` False: only the master and the board (the packages' nodes
    come up when something launches them); ``publish_period_ms`` then is the launch's business."""

    def __init__(self, work_dir: Path, *, activated: bool = True, publish_period_ms: Optional[int] = DEFAULT_PUBLISH_PERIOD_MS,
                 base_env: Optional[Mapping[str, str]] = None, python: str = sys.executable,
                 nodes_running: bool = True) -> None:
        self.work_dir = Path(work_dir).resolve()
        self.folder = self.work_dir / "counts"
        self.packages = self.work_dir / PACKAGES_DIR
        self.nodes_running = nodes_running
        self.activated = activated
        self.publish_period_ms = publish_period_ms
        self.python = python
        self._base_env = lab_shell_env(base_env)
        self.master: Optional[PrivateMaster] = None
        self.board: Optional[ManagedProcess] = None
        self.processes: Dict[str, ManagedProcess] = {}
        self.uris: Dict[str, str] = {}  # node -> the XML-RPC URI of the twin's own process
        self.board_port = ""

    # -- lifecycle -------------------------------------------------------------------
    def start(self, timeout_s: float = START_TIMEOUT_S) -> "LabTwin":
        self.folder.mkdir(parents=True, exist_ok=True)
        for stale in self.folder.glob("*.json"):
            stale.unlink()
        write_activated(self.folder, self.activated)
        master = self.master = PrivateMaster(base_env=self._base_env, work_dir=self.work_dir / "ros", roscore=True)
        try:
            master.start()
            deadline = time.monotonic() + timeout_s
            self.board = master.run([self.python, "-m", "hri_teleop.ros.lab_twin.board", str(self.folder)], "board")
            master.wait_for(lambda: bool(self._board_counts().get("port")) or not self._board_running(),
                            self._left(deadline), "the board's pty")
            self._check_running(self.board, "board")
            self.board_port = str(self._board_counts()["port"])
            write_packages(self.packages, self.folder, self.board_port, self.python)
            if self.nodes_running:
                self._start_nodes(master, deadline)
        except BaseException:
            self.stop()
            raise
        return self

    def _start_nodes(self, master: PrivateMaster, deadline: float) -> None:
        """The twin's own four nodes, with serial_node's parameters; back once all are up."""
        master.set_param("/serial_node/port", self.board_port)
        master.set_param("/serial_node/baud", ROSSERIAL_BAUD)
        if self.publish_period_ms is not None:
            master.set_param("/serial_node/publish_period_ms", int(self.publish_period_ms))
        for node, module in MODULES.items():
            self.processes[node] = master.run([self.python, "-m", module], node.strip("/"),
                                              extra_env={TWIN_DIR_ENV: str(self.folder)})
        master.wait_for(lambda: self._ready() or self._any_exited(), self._left(deadline), "the lab twin's nodes")
        for node, proc in self.processes.items():
            self._check_running(proc, node)
        self.uris = {node: self._lookup(node) or "" for node in NODES}

    def stop(self) -> None:
        """Stop every process the twin started (side by side: each takes about 1 s), then its master;
        the counts stay in the folder."""
        if self.master is not None:
            stop_side_by_side(list(self.master.children))
            self.master.stop()

    def __enter__(self) -> "LabTwin":
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    @staticmethod
    def _left(deadline: float) -> float:
        return max(0.1, deadline - time.monotonic())

    def _board_counts(self) -> Dict[str, Any]:
        return read_json(counts_path(self.folder, COUNTS_NODE))

    def _board_running(self) -> bool:
        return self.board is not None and self.board.running

    def _any_exited(self) -> bool:
        return not self._board_running() or any(not proc.running for proc in self.processes.values())

    @staticmethod
    def _check_running(proc: ManagedProcess, name: str) -> None:
        if not proc.running:
            raise MasterError(f"the lab twin's {name} exited: {proc.output().strip()[-600:]}")

    def _ready(self) -> bool:
        """Every node has registered its interfaces, the board speaks on /pub_force, and each node wrote its counts
        (franka_control's with the arm's joints)."""
        master = self._master()
        pubs, subs, _srvs = master.system_state()
        published = {topic: nodes for topic, nodes in pubs}
        subscribed = {topic: nodes for topic, nodes in subs}
        wanted = [("/franka_control" in subscribed.get(DEFAULT_TWIST_TOPIC, [])),
                  ("/franka_control" in published.get("/franka_control/error_recovery/status", [])),
                  ("/franka_control" in published.get("/franka_state_controller/joint_states", [])),
                  ("/joint_state_publisher" in published.get("/joint_states", [])),
                  ("/serial_node" in published.get("/pub_force", []))]
        wanted += ["/franka_gripper" in published.get(f"/franka_gripper/{a}/status", []) for a in _GRIPPER_ACTIONS]
        # Each node's counts hold what it records at its start (franka_control's joints last).
        return all(wanted) and "joint_positions_rad" in read_json(counts_path(self.folder, "/franka_control")) and all(
            counts_path(self.folder, node).is_file() for node in NODES)

    def _master(self) -> PrivateMaster:
        if self.master is None or self.master.core is None:
            raise MasterError("the lab twin is not running: call start() first (or use it as a context manager)")
        return self.master

    def _lookup(self, node: str) -> Optional[str]:
        proxy: Any = xmlrpc.client.ServerProxy(self._master().uri)  # XML-RPC answers are untyped lists
        try:
            code, _msg, uri = proxy.lookupNode("/hri_probe", node)
        except (OSError, xmlrpc.client.Error):
            return None
        return str(uri) if code == 1 else None

    # -- what a kernel sees --------------------------------------------------------------
    @property
    def master_uri(self) -> str:
        return self._master().uri

    @property
    def env(self) -> Dict[str, str]:
        """The environment a notebook kernel or ``make check`` gets on the lab PC, pointed at the twin.

        ROS_MASTER_URI and ROS_HOSTNAME, logs in the twin's folder, the twin's installed packages
        last on ROS_PACKAGE_PATH (as an installed ROS's); nothing that says the master is private or
        a twin (``HRI_OWN_MASTER`` empty, no ``HRI_MODE``: the caller sets the mode it tests).
        """
        env = dict(self._base_env)
        paths = [p for p in env.get("ROS_PACKAGE_PATH", "").split(":") if p and p != str(self.packages)]
        env["ROS_PACKAGE_PATH"] = ":".join([*paths, str(self.packages)])
        env.update({"ROS_MASTER_URI": self.master_uri, "ROS_HOSTNAME": "127.0.0.1",
                    "ROS_LOG_DIR": str(self.work_dir / "client-log"), "ROS_HOME": str(self.work_dir / "client-home")})
        env.pop("ROS_IP", None)
        env.pop(TWIN_DIR_ENV, None)
        env.pop("HRI_MODE", None)
        env[OWN_MASTER_ENV] = ""  # as a lab terminal: no process of this environment started the master
        return env

    # -- what reached it -------------------------------------------------------------------
    def report(self) -> TwinReport:
        """The counts now; ``replaced``/``stopped`` only ever name nodes the twin itself started,
        ``launched`` those running from its installed packages (see :mod:`.report`)."""
        master = self._master()
        replaced, stopped = [], []
        registered = running_nodes(among=list(NODES), uri=master.uri)  # a dead node's registration is none
        for node in NODES:
            uri = self._lookup(node)
            own = self.uris.get(node)
            if own and uri is not None and uri != own:
                replaced.append(node)
            proc = self.processes.get(node)
            if proc is not None and not proc.running:
                stopped.append(node)
        return read_report(self.folder, master.publishers("/pub_force"), replaced, stopped, registered)

    # -- the person at the piston and at the user stop ------------------------------------------
    def press(self, count: int = FULL_PRESS_COUNT, hold_s: float = 2.0, wait: bool = True) -> None:
        """Press the piston to ``count`` for ``hold_s`` s (a full press near 700); waits until the board took it."""
        seq = request_press(self.folder, count, hold_s)
        if wait:
            self._master().wait_for(lambda: int(self._board_counts().get("presses", 0)) >= seq, ACK_TIMEOUT_S,
                                    "the board to take the press")

    def set_activated(self, activated: bool, wait: bool = True) -> None:
        """Release (True) or engage (False) the robot's user stop, in the twin's folder: it holds for
        whichever franka_control runs now or starts later. ``wait``: until a running one took it."""
        master = self._master()
        write_activated(self.folder, activated)
        self.activated = bool(activated)
        if wait and running_nodes(among=["/franka_control"], uri=master.uri):
            master.wait_for(lambda: self.report().activated is bool(activated), ACK_TIMEOUT_S,
                            f"franka_control to take the user stop {'released' if activated else 'engaged'}")

    def run(self, argv: Sequence[str], name: str, extra_env: Optional[Mapping[str, str]] = None) -> ManagedProcess:
        """Start a process (a student's node, a launch) with :attr:`env`; it is stopped with the twin."""
        env = self.env
        env.update(extra_env or {})
        return self._master().run(argv, name, extra_env=env)

    def started(self) -> List[ManagedProcess]:
        """Every process the twin ever started (the master's included), for leak checks."""
        return list(self.master.started) if self.master is not None else []

    def describe(self) -> List[str]:
        """What runs, for a person: the nodes, the master and packages to export, the board's pty."""
        pids = {node: proc.popen.pid for node, proc in self.processes.items()}
        if self.nodes_running:
            nodes = [f"node     {node:<23} pid {pids.get(node, '?')}" for node in NODES]
            board = (f"board    rosserial sketch stand-in on {self.board_port} (serial_node's ~port), ~publish_period_ms "
                     f"{self.publish_period_ms if self.publish_period_ms is not None else 'unset'}")
        else:
            nodes = [f"nodes    none yet (bare): {', '.join(NODES)} come up when a launch starts them, e.g. "
                     "roslaunch hri_lab teleoperation.launch"]
            board = f"board    rosserial sketch stand-in on {self.board_port} (any serial_node.py of the twin's opens it)"
        shadowed = found_elsewhere(self.packages, self._base_env.get("ROS_PACKAGE_PATH", ""))
        return ([f"master   export ROS_MASTER_URI={self.master_uri}  (and ROS_HOSTNAME=127.0.0.1)",
                 f"packages export ROS_PACKAGE_PATH=$ROS_PACKAGE_PATH:{self.packages}  (franka_control, "
                 "rosserial_python as the lab PC has them installed)"]
                + [f"warning  {found} comes first on ROS_PACKAGE_PATH: a launch starts that one, not the twin's"
                   for found in shadowed]
                + nodes + [board, f"counts   {self.folder}/*.json"])
