"""Nodes started from a notebook cell, on the kernel's master, stopped with ``stop_nodes``.

Each node runs in its own process group with its output in a log file (``proc.output()``),
so a cell never blocks on a node; :func:`hri_teleop.course.notebook_ros.ensure_ros` points
``ROS_MASTER_URI`` at the kernel's master first. Whatever is left stops with the kernel.
"""

from __future__ import annotations

import atexit
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Union

from hri_teleop.core.modes import NODE_DEFAULT_PAD, SIMULATED_SCRIPTS, Start, duplicate_refusal
from hri_teleop.course.errors import CourseError
from hri_teleop.course.master_mode import NotStarted, master_mode, start_refusal
from hri_teleop.grading.run.workspace import REFERENCE_PACKAGE, prepare_workspace, ros_package_path
from hri_teleop.ros.launch_inspect import LaunchedNode, LaunchInspectError, launched_nodes
from hri_teleop.ros.master import ManagedProcess, stop_side_by_side
from hri_teleop.ros.master_api import master_call, running_nodes

__all__ = ["STARTED", "start_gated", "STUDENT_PACKAGE", "stop_nodes", "run_provided_node", "run_student_node", "rosrun_student", "launch",
           "wait_for_publisher", "student_workspace", "launch_student", "node_start", "launch_starts"]

PathLike = Union[str, Path]
#: The student's package folder beside the notebooks of every assignment.
STUDENT_PACKAGE = "hri_lab"

#: The nodes this kernel started (stop_nodes stops them) and its scratch folders (gone at exit).
STARTED: List[Any] = []
_SCRATCH: List[Path] = []


def _remove_scratch() -> None:
    for folder in _SCRATCH:
        shutil.rmtree(folder, ignore_errors=True)


def _scratch(prefix: str) -> Path:
    """A temporary folder of this kernel (node logs, workspaces), removed when the kernel stops."""
    if not _SCRATCH:
        atexit.register(_remove_scratch)
    folder = Path(tempfile.mkdtemp(prefix=prefix))
    _SCRATCH.append(folder)
    return folder


def _ros_args(params: Dict[str, Any]) -> List[str]:
    return [f"_{name}:={value}" for name, value in params.items()]


def start_gated(argv: Sequence[str], name: str, starts: Sequence[Start], extra_env: Optional[Dict[str, str]] = None,
           cwd: Optional[Path] = None, nodes: Optional[Sequence[str]] = None) -> Any:
    """Start ``argv`` (its ROS node names ``nodes``, default ``[name]``; what they are, ``starts``).

    Refused, with the one line printed and returned as a :class:`NotStarted`, where the rules
    of :mod:`hri_teleop.core.modes` forbid one of ``starts`` on this master; an error when
    one of the names runs already.
    """
    if not os.environ.get("ROS_MASTER_URI"):
        raise CourseError("no ROS master for this kernel: run ensure_ros() (hri_teleop.course.notebook_ros) first; "
                          "it says in one line what is missing")
    refusal = start_refusal(starts)
    if refusal:
        print(refusal)
        return NotStarted(refusal)
    wanted = list(nodes) if nodes is not None else [name]
    refusal = duplicate_refusal(wanted, running_nodes(among=wanted))
    if refusal:
        raise CourseError(refusal)
    env = dict(os.environ)
    env.update({"PYTHONUNBUFFERED": "1", **(extra_env or {})})
    log = _scratch("hri-notebook-node-") / f"{name}.log"
    proc = ManagedProcess(list(argv), env, log, cwd=cwd)
    STARTED.append(proc)
    return proc


def stop_nodes() -> None:
    """Stop every node and launch this notebook started, side by side (the master keeps running)."""
    procs = list(STARTED)
    STARTED.clear()
    stop_side_by_side(procs)


def run_provided_node(script: str, **params: Any) -> Any:
    """Start one of the lab's own nodes (``FSR_sensor.py``, ``lab_sim.py``, ...) with private parameters."""
    path = REFERENCE_PACKAGE / "scripts" / script
    if not path.is_file():
        raise CourseError(f"{script}: not one of the lab's nodes in {path.parent}")
    return start_gated([sys.executable, str(path), *_ros_args(params)], Path(script).stem,
                       [node_start(script, Path(script).stem, params)])


def node_start(script: str, node: str, params: Dict[str, Any]) -> Start:
    """What starting ``script`` as ``node`` with ``params`` is: simulated hardware, or a node reading a pad."""
    name = Path(script).name
    reads_pad = "pad" in params or Path(name).stem == "teleoperation" or node.lstrip("/") == "teleoperation"
    return Start(f"{name} (node /{node.lstrip('/')})", simulated=name in SIMULATED_SCRIPTS,
                 pad=str(params.get("pad", NODE_DEFAULT_PAD)) if reads_pad else None)


def launch_starts(nodes: Sequence[LaunchedNode], what: str) -> List[Start]:
    """What each node of a launch is (:func:`node_start`), named as part of ``what``."""
    return [Start(f"{what}, whose node {n.name} runs {n.type}", simulated=Path(n.type).name in SIMULATED_SCRIPTS,
                  pad=(n.pad or NODE_DEFAULT_PAD) if Path(n.type).stem == "teleoperation" else None)
            for n in nodes]


def run_student_node(path: PathLike, name: str = "", **params: Any) -> Any:
    """Start the student's node file (``hri_lab/scripts/...py``) as ``rosrun`` would; ``name`` renames the node."""
    script = Path(path)
    if not script.is_file():
        raise CourseError(f"{script}: no such file next to this notebook")
    node = name or script.stem
    return start_gated([sys.executable, str(script.resolve()), f"__name:={node}", *_ros_args(params)], node,
                       [node_start(script.name, node, params)], cwd=script.resolve().parent)


def rosrun_student(workspace: Any, script: str, name: str = "", **params: Any) -> Any:
    """``rosrun hri_lab SCRIPT`` in the student's built workspace (:func:`hri_teleop.ros.catkin_ws.build_workspace`)."""
    node = name or Path(script).stem
    return start_gated(["rosrun", "hri_lab", script, f"__name:={node}", *_ros_args(params)], node,
                       [node_start(script, node, params)], extra_env=workspace.env())


def _start_launch(where: Sequence[str], label: str, extra_env: Optional[Dict[str, str]] = None) -> Any:
    """``roslaunch --wait WHERE...``, once roslaunch's loader has said what it would start."""
    env = dict(os.environ, **(extra_env or {}))
    try:
        nodes = launched_nodes(where, env)
    except LaunchInspectError as exc:
        raise CourseError(str(exc)) from None
    # --disable-title: roslaunch sets the terminal's title (ESC ] 2; ... BEL), which a notebook shows as boxes.
    return start_gated(["roslaunch", "--wait", "--disable-title", *where], label, launch_starts(nodes, label),
                       extra_env=extra_env, nodes=[n.name for n in nodes])


def launch(package: str, launch_file: str, **args: Any) -> Any:
    """``roslaunch PACKAGE FILE name:=value ...`` of an installed package (the lab's ``hri_lab``)."""
    where = [package, launch_file, *[f"{k}:={v}" for k, v in args.items()]]
    return _start_launch(where, Path(launch_file).name)


def wait_for_publisher(topic: str, process: Any = None, timeout_s: float = 20.0) -> bool:
    """Wait until somebody publishes ``topic`` (False after ``timeout_s`` or when ``process`` ended)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if any(name == topic and nodes for name, nodes in master_call("getSystemState")[0]):
            return True
        if process is not None and not process.running:
            return False
        time.sleep(0.1)
    return False



def student_workspace(package: PathLike = STUDENT_PACKAGE, standins: bool = True) -> Path:
    """A ROS workspace with the student's package as ``hri_lab`` plus the lab's provided nodes.

    The grader's own workspace (the student's files never change; a fresh copy each call),
    so ``roslaunch`` of the student's launch file finds *their* nodes, and FSR_sensor.py,
    gripper_manager.py and (``standins``) the grader's franka_control and rosserial_python.
    """
    return prepare_workspace(package, _scratch("hri-notebook-ws-"), standins=standins).ws


def launch_student(launch_file: str, package: PathLike = STUDENT_PACKAGE, **args: Any) -> Any:
    """``roslaunch hri_lab FILE`` with the student's package (their nodes, the lab's provided ones).

    On a master this kernel did not start (the lab's) the real franka_control and
    rosserial_python are used, never the grader's stand-ins of them.
    """
    ws = student_workspace(package, standins=master_mode().own)
    path = ws / "hri_lab" / "launch" / launch_file
    if not path.is_file():
        raise CourseError(f"{Path(package) / 'launch' / launch_file}: no such file; write it first")
    where = [str(path), *[f"{k}:={v}" for k, v in args.items()]]
    return _start_launch(where, Path(launch_file).name, {"ROS_PACKAGE_PATH": ros_package_path(ws)})

