"""What a launch would start, read with roslaunch's own loader before anything starts.

A notebook asks before it launches: which nodes (names for the duplicate check), which scripts
(a simulated board or robot), and which pad a teleoperation node would read. The loader runs in
a child process with the launch's environment (its ROS_PACKAGE_PATH), so ``$(find ...)``
resolves as it will for roslaunch itself.
"""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional, Sequence

from hri_teleop.core.errors import HriTeleopError

__all__ = ["LaunchInspectError", "LaunchedNode", "launched_nodes", "declared_args", "main"]


class LaunchInspectError(HriTeleopError, RuntimeError):
    """A launch file roslaunch's loader cannot read (one line: its error and the fix)."""


@dataclass(frozen=True)
class LaunchedNode:
    """One node of a launch: its full name, package and executable, and its private ``pad`` parameter."""

    name: str
    package: str
    type: str
    pad: Optional[str] = None


def _load(where: Sequence[str]) -> List[Dict[str, Any]]:
    import roslaunch.config  # noqa: PLC0415 - only in the child process that reads the launch
    import roslaunch.rlutil  # noqa: PLC0415 - as above
    import roslaunch.xmlloader  # noqa: PLC0415 - as above

    files = roslaunch.rlutil.resolve_launch_arguments(list(where))
    args = [a for a in where if ":=" in a]
    config = roslaunch.config.ROSLaunchConfig()
    loader = roslaunch.xmlloader.XmlLoader(resolve_anon=False)
    for path in files:
        loader.load(path, config, argv=["roslaunch", *args], verbose=False)
    nodes = []
    for node in config.nodes:
        full = (node.namespace or "/").rstrip("/") + "/" + node.name
        pad = config.params.get(full + "/pad")
        nodes.append({"name": full, "package": node.package, "type": node.type,
                      "pad": None if pad is None else str(pad.value)})
    return nodes


def launched_nodes(where: Sequence[str], env: Mapping[str, str], timeout_s: float = 60.0) -> List[LaunchedNode]:
    """The nodes ``roslaunch WHERE...`` would start (``WHERE``: a package and file, or a path, then ``arg:=value``)."""
    argv = [sys.executable, "-m", "hri_teleop.ros.launch_inspect", *where]
    try:
        proc = subprocess.run(argv, env=dict(env), capture_output=True, text=True, timeout=timeout_s)
    except subprocess.TimeoutExpired:
        raise LaunchInspectError(f"reading {' '.join(where)} took over {timeout_s:.0f} s: is the machine "
                                 "overloaded? run the cell again") from None
    if proc.returncode != 0:
        lines = [line.strip() for line in proc.stderr.splitlines() if line.strip()]
        raise LaunchInspectError(f"roslaunch cannot read {' '.join(where)}: {lines[-1] if lines else proc.returncode}"
                                 "; fix the launch file (or its arguments) first")
    return [LaunchedNode(**item) for item in json.loads(proc.stdout)]


def declared_args(where: Sequence[str], env: Mapping[str, str], timeout_s: float = 60.0) -> List[str]:
    """The ``<arg>`` names a launch file declares (``roslaunch --ros-args``): a student's file may
    declare none of the lab's (``feedback``, ``max_sensor_force``), and roslaunch refuses an unused one."""
    try:
        proc = subprocess.run(["roslaunch", "--ros-args", *where], env=dict(env), capture_output=True, text=True,
                              timeout=timeout_s)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise LaunchInspectError(f"roslaunch --ros-args {' '.join(where)} failed ({type(exc).__name__}): "
                                 "source the toolkit's env.sh (ROS on PATH) and try again") from None
    if proc.returncode != 0:
        lines = [line.strip() for line in (proc.stderr + proc.stdout).splitlines() if line.strip()]
        raise LaunchInspectError(f"roslaunch cannot read {' '.join(where)}: {lines[-1] if lines else proc.returncode}"
                                 "; fix the launch file first")
    names = []
    for line in proc.stdout.splitlines():
        if line.startswith("  ") and ":" in line:
            names.append(line.strip().split(":")[0].split(" (default")[0].strip())
    return names


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m hri_teleop.ros.launch_inspect WHERE...``: the nodes as JSON on standard output."""
    where = list(sys.argv[1:] if argv is None else argv)
    try:
        nodes = _load(where)
    except Exception as exc:  # noqa: BLE001 - roslaunch raises many kinds; the parent shows one line
        print(f"{type(exc).__name__}: {str(exc).strip().splitlines()[0] if str(exc).strip() else ''}",
              file=sys.stderr)
        return 1
    print(json.dumps(nodes))
    return 0


if __name__ == "__main__":
    sys.exit(main())
