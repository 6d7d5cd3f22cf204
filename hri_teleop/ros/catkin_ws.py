"""The student's catkin workspace, built from a notebook as the handout has it built in a terminal.

Ex. 9: "make the file executable ... then build the workspace". ``catkin_ws/`` lies beside the
assignment's ``hri_lab`` and ``catkin_ws/src/hri_lab`` links back to it, so students keep editing
their files where the notebooks show them. ``catkin_make``'s log goes to ``catkin_ws/build.log``, a
failure is one line with cause and fix, and nbgrader never collects the workspace.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Union

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.ros.catkin_files import explain_build_failure
from hri_teleop.ros.master import finds_hri_lab

__all__ = ["CatkinError", "CatkinWorkspace", "build_workspace", "WORKSPACE_NAME"]

WORKSPACE_NAME = "catkin_ws"
#: What ``devel/setup.bash`` may change for the nodes started from it.
_PATH_VARIABLES = ("ROS_PACKAGE_PATH", "CMAKE_PREFIX_PATH", "LD_LIBRARY_PATH", "PKG_CONFIG_PATH", "PYTHONPATH", "PATH")
PathLike = Union[str, Path]


class CatkinError(HriTeleopError, RuntimeError):
    """The workspace could not be built (one line: the cause and the fix)."""

    def _render_traceback_(self) -> List[str]:  # IPython shows the one line, not a traceback
        return [f"{type(self).__name__}: {self}"]


@dataclass
class CatkinWorkspace:
    """A built workspace: its folder, how long ``catkin_make`` took, and the environment of ``devel/setup.bash``."""

    root: Path
    package: Path
    seconds: float
    _env: Dict[str, str] = field(default_factory=dict, repr=False)

    @property
    def setup(self) -> Path:
        return self.root / "devel" / "setup.bash"

    def env(self) -> Dict[str, str]:
        """The variables ``source catkin_ws/devel/setup.bash`` sets (ROS_PACKAGE_PATH, CMAKE_PREFIX_PATH, ...)."""
        if not self._env:
            out = subprocess.run(["bash", "-c", f'. "{self.setup}" && env -0'], capture_output=True, timeout=60,
                                 env=dict(os.environ))
            if out.returncode != 0:
                raise CatkinError(f"{self.setup} could not be sourced: build the workspace again (build_workspace())")
            pairs = (item.split("=", 1) for item in out.stdout.decode(errors="replace").split("\0") if "=" in item)
            # Only the search paths: setup.bash also sets ROS_MASTER_URI (to 11311), and a node must stay
            # on the notebook's master.
            self._env = {k: v for k, v in pairs if k in _PATH_VARIABLES and v and os.environ.get(k) != v}
            # devel/setup.bash puts src/ alone on the package path: keep the system's packages after it
            # (rosserial_python, ...), but never another hri_lab (the lab's) that would shadow the student's.
            others = [e for e in os.environ.get("ROS_PACKAGE_PATH", "").split(":") if e and not finds_hri_lab(e)]
            self._env["ROS_PACKAGE_PATH"] = ":".join(dict.fromkeys([str(self.root / "src"), *others]))
        return dict(self._env)

    def describe(self) -> str:
        return (f"catkin_make: {self.root} built in {self.seconds:.1f} s; in a terminal: "
                f"source {self.setup} && rosrun hri_lab <script>")


def _link_package(src: Path, package: Path) -> None:
    link = src / package.name
    target = Path(os.path.relpath(package.resolve(), src.resolve()))
    if link.is_symlink():
        if Path(os.readlink(link)) == target:
            return
        link.unlink()
    elif link.exists():
        raise CatkinError(f"{link} is a folder of its own, not the link to your {package.name}: move your work "
                          f"into {package} and delete {link}")
    link.symlink_to(target, target_is_directory=True)


def build_workspace(package: PathLike = "hri_lab", root: Optional[PathLike] = None,
                    timeout_s: float = 300.0) -> CatkinWorkspace:
    """``catkin_make`` in ``root`` (default: ``catkin_ws`` beside the package) with the package in ``src/``."""
    package = Path(package)
    if not (package / "package.xml").is_file() or not (package / "CMakeLists.txt").is_file():
        missing = "package.xml" if not (package / "package.xml").is_file() else "CMakeLists.txt"
        raise CatkinError(f"{package / missing}: not found; a catkin package needs it (restore it from the "
                          "released version of the assignment)")
    if shutil.which("catkin_make") is None:
        raise CatkinError("catkin_make is not installed: run `make setup` (it installs Debian's catkin), or source "
                          "/opt/ros/noetic/setup.bash on the lab PCs")
    ws = Path(root) if root is not None else Path(os.path.abspath(package)).parent / WORKSPACE_NAME
    src = ws / "src"
    src.mkdir(parents=True, exist_ok=True)
    _link_package(src, package)
    log = ws / "build.log"
    started = time.monotonic()
    try:
        proc = subprocess.run(["catkin_make"], cwd=str(ws), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              timeout=timeout_s, env=dict(os.environ, PWD=str(ws)))  # catkin_make reads $PWD
    except subprocess.TimeoutExpired:
        raise CatkinError(f"catkin_make took longer than {timeout_s:.0f} s; see {log}") from None
    text = proc.stdout.decode(errors="replace")
    log.write_text(text, encoding="utf-8")
    if proc.returncode != 0:
        raise CatkinError(f"{explain_build_failure(text, str(package))} (full log: {log})")
    return CatkinWorkspace(ws, package, time.monotonic() - started)
