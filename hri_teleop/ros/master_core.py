"""What ``roscore`` starts, started without it: ``rosmaster``, ``rosout`` and roscore's three parameters.

roscore is a roslaunch process that starts two programs and sets three parameters; it costs 0.4 s
of CPU and 0.5 s of wall time per start (measured in docs/benchmarks.md). A private master of a
test, a grading session or a notebook kernel needs only what it starts, so
:class:`~hri_teleop.ros.master.PrivateMaster` starts those itself, and looks the same to every node
and tool (``rosnode list``, ``rosparam dump``). Where the pieces cannot be found, roscore is used.
"""

from __future__ import annotations

import os
import re
import uuid
from pathlib import Path
from typing import Dict, List, Mapping, Optional

__all__ = ["ROSMASTER_WORKERS", "rosmaster_argv", "rosout_argv", "rosout_program", "core_params", "PORT_TAKEN"]

#: roscore's own ``-w``: the master's XML-RPC worker threads.
ROSMASTER_WORKERS = 3
#: What rosmaster prints when its port is taken (it then waits forever instead of exiting).
PORT_TAKEN = "is already in use"
_DEBIAN_ROSOUT = "/usr/lib/rosout/rosout"


def _path_list(env: Mapping[str, str], key: str) -> List[str]:
    return [p for p in env.get(key, "").split(":") if p]


def rosout_program(env: Mapping[str, str]) -> Optional[str]:
    """The ``rosout`` binary roscore would run: ``lib/rosout/rosout`` under a catkin prefix (ROS Noetic's
    ``/opt/ros/noetic``), else Debian's; None when there is none (then roscore is used)."""
    prefixes = _path_list(env, "CMAKE_PREFIX_PATH")
    root = env.get("ROS_ROOT", "")
    if root:
        prefixes.append(str(Path(root).parent.parent))  # /opt/ros/noetic/share/ros -> /opt/ros/noetic
    for candidate in [str(Path(p) / "lib" / "rosout" / "rosout") for p in prefixes] + [_DEBIAN_ROSOUT]:
        if os.access(candidate, os.X_OK):
            return candidate
    return None


def rosmaster_argv(port: int) -> List[str]:
    """roscore's rosmaster command line for ``port``."""
    return ["rosmaster", "--core", "-p", str(port), "-w", str(ROSMASTER_WORKERS)]


def rosout_argv(program: str, log_dir: Path) -> List[str]:
    """roscore's rosout command line (its aggregated log in ``log_dir``)."""
    return [program, "__name:=rosout", f"__log:={log_dir / 'rosout-1.log'}"]


def _roslaunch_version(env: Mapping[str, str]) -> str:
    """``rosversion roslaunch``: the version in roslaunch's package.xml on the package path."""
    folders = _path_list(env, "ROS_PACKAGE_PATH") + [str(Path(p) / "share") for p in _path_list(env, "CMAKE_PREFIX_PATH")]
    for folder in folders + ["/usr/share"]:
        manifest = Path(folder) / "roslaunch" / "package.xml"
        try:
            found = re.search(r"<version>\s*([^<\s]+)\s*</version>", manifest.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError):
            continue
        if found:
            return found.group(1)
    return "<unversioned>"


def core_params(env: Mapping[str, str]) -> Dict[str, str]:
    """The parameters a roscore sets, as it sets them: ``/rosversion`` and ``/rosdistro`` are the output
    of ``rosversion roslaunch`` and ``rosversion -d`` (with their newline), ``/run_id`` a fresh uuid."""
    return {"/rosversion": _roslaunch_version(env) + "\n",
            "/rosdistro": (env.get("ROS_DISTRO") or "Debian") + "\n",
            "/run_id": str(uuid.uuid1())}
