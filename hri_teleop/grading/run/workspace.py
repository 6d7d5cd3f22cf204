"""Where a student's files are, and the catkin-free package the grader runs them in.

The grader builds an hri_lab package (launch files say ``pkg="hri_lab"``) with the student's files
at the handout's places, the lab-provided files from the instructor and stand-ins for the hardware
packages, on a copy. Nothing of the submission is followed or opened special: folders are walked
with ``lstat``, files read through :mod:`hri_teleop.grading.run.untrusted_files`, and a deliverable
that is a link, FIFO or device is refused in one line (:func:`refusal_for`), never read.
"""

from __future__ import annotations

import os
import shutil
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple, Union

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.paths import LAB_PACKAGE, REPO
from hri_teleop.grading.deliverables import DELIVERABLE_FILES
from hri_teleop.grading.run.standins import SERIAL_NODE_SCRIPT
from hri_teleop.grading.run.student_guard import guard_policy
from hri_teleop.grading.run.untrusted_files import (
    FILE_CAP_BYTES,
    UntrustedFileError,
    copy_regular,
    kind_of,
    refusal,
    regular_size,
)
from hri_teleop.ros.master import finds_hri_lab

__all__ = ["WorkspaceError", "DELIVERABLES", "REPO", "REFERENCE_PACKAGE", "PROVIDED", "given_path", "find_package_root",
           "locate", "refusal_for", "package_files", "Workspace", "prepare_workspace", "ros_package_path", "FRANKA_MARKER_PARAM"]

REFERENCE_PACKAGE = LAB_PACKAGE
#: The toolkit's package folder (hri_teleop), whose reference rules the guard keeps from student code.
TOOLKIT = Path(__file__).resolve().parents[2]

#: What students hand in, by key, at the handout's place in the hri_lab package (the exercises' registry).
DELIVERABLES: Dict[str, str] = {key: sub for key, sub in DELIVERABLE_FILES.items() if sub}
#: Files the lab provides; the grader always uses the instructor's.
PROVIDED = ("scripts/FSR_sensor.py", "scripts/gripper_manager.py", "package.xml", "CMakeLists.txt",
            "config/teleop.yaml")
#: The stand-in franka_control's launch file sets this parameter, so an include is visible.
FRANKA_MARKER_PARAM = "/hri_grader/franka_control_cartesian_velocity_included"
_MAX_COPY_BYTES = 20 * 1024 * 1024
_SKIP_DIRS = {".git", "__pycache__", ".ipynb_checkpoints", ".ros", "build", "devel"}


class WorkspaceError(HriTeleopError, RuntimeError):
    """A submission path does not exist or cannot be copied (one line with the fix)."""


def _mode(path: Path) -> Optional[int]:
    """``path``'s own mode (a link's, not its target's), or None when there is nothing there."""
    try:
        return os.lstat(path).st_mode
    except OSError:
        return None


def _is_dir(path: Path) -> bool:
    mode = _mode(path)
    return mode is not None and stat.S_ISDIR(mode)


def _is_regular(path: Path) -> bool:
    mode = _mode(path)
    return mode is not None and stat.S_ISREG(mode)


def _entries(root: Path, depth: int) -> List[Tuple[Path, int]]:
    """(path, own mode) of everything below ``root`` down to ``depth`` folders, entering no link and no
    hidden or build folder; links and special files are listed (to be refused), not entered."""
    found: List[Tuple[Path, int]] = []
    if depth < 0 or not _is_dir(root):
        return found
    try:
        names = sorted(os.listdir(root))
    except OSError:
        return found
    for name in names:
        if name in _SKIP_DIRS or name.startswith("."):
            continue
        entry = root / name
        mode = _mode(entry)
        if mode is None:
            continue
        found.append((entry, mode))
        if stat.S_ISDIR(mode):
            found.extend(_entries(entry, depth - 1))
    return found


def _walk(root: Path, depth: int) -> List[Path]:
    """The regular files below ``root`` (links and special files left out, no link entered)."""
    return [path for path, mode in _entries(root, depth) if stat.S_ISREG(mode)]


def given_path(path: Union[str, Path]) -> Path:
    """The folder or file the caller named: a link to a folder there is the caller's (a course's source
    folder links hri_lab to the answer key), so it is resolved once; nothing below it is followed. A
    student cannot place such a link: files-only mode refuses a student's folder that is a link, the
    course mode a submission with links out of it, and Gradescope copies an upload without its links."""
    path = Path(path).expanduser()
    return Path(os.path.realpath(path)) if path.is_symlink() and path.is_dir() else path


def find_package_root(path: Union[str, Path]) -> Path:
    """The folder holding the student's package: the one under which the deliverables sit.

    A file inside scripts/, config/ or launch/ -> that folder's parent; another file -> its
    folder; a folder -> the shallowest folder below it (3 levels) that has a deliverable
    at its handout place, else the folder itself.
    """
    path = given_path(path)
    if _mode(path) is None:
        raise WorkspaceError(f"{path}: no such file or folder; give the student's file or hri_lab folder")
    if not _is_dir(path):  # a file, or a link to one, which the checks refuse
        return path.parent.parent if path.parent.name in ("scripts", "config", "launch") else path.parent
    below = [p for p, mode in _entries(path, 2) if stat.S_ISDIR(mode)]
    candidates = [path] + sorted(below, key=lambda p: (len(p.relative_to(path).parts), str(p)))
    for folder in candidates:
        if any(_reachable(folder, sub) for sub in DELIVERABLES.values()):
            return folder
    return path


def _reachable(root: Path, sub: str) -> bool:
    """Whether ``root/sub`` is a regular file reached through real folders (no link on the way)."""
    here = root
    for part in Path(sub).parts[:-1]:
        here = here / part
        if not _is_dir(here):
            return False
    return _is_regular(root / sub)


def locate(root: Path, key: str) -> Optional[Path]:
    """The student's file for ``key``: at its handout place, or anywhere below by its name."""
    sub = DELIVERABLES[key]
    if _is_dir(root) and _reachable(root, sub):
        return root / sub
    name = Path(sub).name
    matches = [p for p in _walk(root, 3) if p.name == name]
    return matches[0] if matches else None


def refusal_for(root: Path, key: str, found: Optional[Path] = None) -> str:
    """Why deliverable ``key`` of the package at ``root`` is not read (one line naming what to hand in
    instead), or "": ``found`` (:func:`locate`'s file, or a file given alone) is a link, a FIFO, a
    device or too large; or nothing was found but a link or special file stands in its place (at its
    handout place, by its name below ``root``, ``root`` itself or a folder below it)."""
    sub = DELIVERABLES[key]
    if found is not None:
        inside = Path(os.path.abspath(found)).is_relative_to(os.path.abspath(root)) and _is_dir(root)
        why = refusal(found, root if inside else None)
        if not why and (regular_size(found) or 0) > FILE_CAP_BYTES:
            why = f"{found} is larger than {FILE_CAP_BYTES // 1024 ** 2} MB; hand in the file itself, not a data dump"
        return why
    mode = _mode(root)
    if mode is not None and not stat.S_ISDIR(mode):
        return f"{root} is {kind_of(mode)}; hand in the hri_lab folder itself, not a link to it"
    why = refusal(root / sub, root) if mode is not None else ""
    if why and "No such file" not in why:  # a link or a special file at the handout place, or on the way
        return why
    entries = _entries(root, 3)
    for path, mode in entries:
        if path.name == Path(sub).name and not stat.S_ISREG(mode):
            return refusal(path, root) or f"{path} is {kind_of(mode)}; hand in the file itself"
    for path, mode in entries:
        if stat.S_ISLNK(mode) and os.path.isdir(path):
            return f"{path} is a link; hand in the folder itself, not a link to it"
    return ""


@dataclass
class Workspace:
    """A ROS package path (``ws``) with the student's package as ``ws/hri_lab``."""

    session_dir: Path
    ws: Path
    package: Path
    files: Dict[str, Optional[Path]] = field(default_factory=dict)  # key -> copied file (or None)
    originals: Dict[str, Optional[Path]] = field(default_factory=dict)
    #: deliverables of other exercises run as the lab's reference, not the student's (see prepare_workspace)
    substituted: List[str] = field(default_factory=list)
    #: False only where the lab's own files are graded as the reference (checks' reference_allowed)
    guarded: bool = True
    _guard: Optional[str] = field(default=None, repr=False)

    @property
    def grader_dir(self) -> Path:
        """Inside the student's folder: probe plans and outputs (the student process writes them)."""
        return self.package / ".grader"

    def placed(self) -> List[Path]:
        """The files the grader put in the workspace to run as the lab's (other exercises' deliverables, the
        provided nodes and config, the stand-in board): the reference guard trusts them and keeps them from
        the student's code (:mod:`hri_teleop.grading.run.student_guard`)."""
        found = [self.package / DELIVERABLES[key] for key in self.substituted]
        found += [self.package / sub for sub in PROVIDED] + [self.ws / "rosserial_python" / "scripts" / "serial_node.py"]
        return [p for p in found if p.is_file()]

    @property
    def guard(self) -> str:
        """The reference guard's policy for the student processes of this workspace (JSON; StudentProcess's guard=)."""
        if not self.guarded:
            return ""
        if self._guard is None:
            # the lab's nodes and launch files are answers; its robot_params.yaml is the handout's Table 1
            secret = [str(self.package / DELIVERABLES[key]) for key in self.substituted
                      if DELIVERABLES[key].endswith((".py", ".launch"))]
            self._guard = guard_policy(str(self.package), [str(p) for p in self.placed()], str(TOOLKIT),
                                       secret=secret)
        return self._guard

    def file(self, key: str) -> Path:
        """The copy of deliverable ``key`` (a check's own is always there)."""
        path = self.files.get(key)
        if path is None:
            raise WorkspaceError(f"{DELIVERABLES[key]} is not in the grading workspace {self.package}")
        return path


def _manifest(name: str, description: str) -> str:
    return ('<?xml version="1.0"?>\n<package format="2"><name>' + name + '</name><version>0.0.0</version>'
            f"<description>{description}</description>"
            '<maintainer email="lab@example.org">hri-lab</maintainer><license>BSD</license></package>\n')


def _fake_rosserial_python(ws: Path) -> None:
    pkg = ws / "rosserial_python"
    (pkg / "scripts").mkdir(parents=True, exist_ok=True)
    (pkg / "package.xml").write_text(_manifest("rosserial_python", "grader stand-in: serial_node.py forwards the "
                                                                   "simulated sensor board to /pub_force"))
    script = pkg / "scripts" / "serial_node.py"
    script.write_text(SERIAL_NODE_SCRIPT)
    script.chmod(0o755)


def _fake_franka_control(ws: Path) -> None:
    pkg = ws / "franka_control"
    (pkg / "launch").mkdir(parents=True, exist_ok=True)
    (pkg / "package.xml").write_text(_manifest("franka_control", "grader stand-in: marks that "
                                                                 "franka_control_cartesian_velocity.launch was included"))
    (pkg / "launch" / "franka_control_cartesian_velocity.launch").write_text(
        '<launch>\n  <arg name="robot_ip" default="172.16.0.2"/>\n  <arg name="load_gripper" default="true"/>\n'
        f'  <param name="{FRANKA_MARKER_PARAM}" value="true"/>\n</launch>\n')


def _ros_intro_alias(ws: Path, package: Path) -> None:
    """ws/ros_intro: the same scripts, config and launch files under the package name of Ex. 2-6.

    The handout has the preparation done in the package ros_intro, so a student's
    sensor.launch may say pkg="ros_intro"; both names then find the same files.
    """
    alias = ws / "ros_intro"
    for sub in ("scripts", "config", "launch"):
        if (package / sub).is_dir():
            shutil.copytree(package / sub, alias / sub)
    alias.mkdir(exist_ok=True)
    (alias / "package.xml").write_text(_manifest("ros_intro", "grader alias of the student's hri_lab package"))


def _looks_like_package(root: Path) -> bool:
    """A folder laid out like hri_lab (not, say, the home folder a single file was taken from)."""
    if (root / "package.xml").is_file() or any((root / sub).is_file() for sub in DELIVERABLES.values()):
        return True
    return sum((root / d).is_dir() for d in ("scripts", "config", "launch")) >= 2


def package_files(root: Path) -> List[Path]:
    """The student's files a check's workspace gets from ``root`` (sorted; no caches, no hidden
    folders, nothing past 20 MB in all: a stray bag or video is not part of the package)."""
    files, total = [], 0
    for path in _walk(root, 4):
        size = regular_size(path)
        if size is None or size > FILE_CAP_BYTES or total + size > _MAX_COPY_BYTES:
            continue
        total += size
        files.append(path)
    return files


def _copy_package(root: Path, target: Path) -> None:
    for path in package_files(root):
        try:
            copy_regular(path, target / path.relative_to(root), root=root)
        except UntrustedFileError:
            continue  # swapped for a link since the walk: left out, as links are


def prepare_workspace(submission: Union[str, Path], session_dir: Path, uid: Optional[int] = None,
                      single_file: Optional[Path] = None, single_key: str = "",
                      reference: Sequence[str] = (), standins: bool = True) -> Workspace:
    """Copy the student's package into ``session_dir/ws/hri_lab``, with the lab's provided files.

    ``single_file``/``single_key``: grade exactly this file as that deliverable (the
    ``hri-grade CHECK FILE`` form), wherever it lies. ``reference``: keys of other
    exercises' deliverables the run needs (a launch file starts mapping_node.py, loads
    robot_params.yaml): the lab's own versions are put in their place, so that a file is
    judged on its own, the same alone as in its package, and a mistake in another
    exercise costs points there only. ``standins``: the grader's franka_control and
    rosserial_python (False in the lab, where the real packages must be found).
    """
    root = find_package_root(single_file or submission)
    inside = single_file is not None and Path(os.path.abspath(single_file)).is_relative_to(os.path.abspath(root))
    ws = session_dir / "ws"
    package = ws / "hri_lab"
    package.mkdir(parents=True, exist_ok=True)
    if _looks_like_package(root):
        _copy_package(root, package)  # the student's other files (a YAML their launch file loads...)
    space = Workspace(session_dir, ws, package)
    for key, sub in DELIVERABLES.items():
        original = Path(single_file) if (single_file is not None and key == single_key) else locate(root, key)
        space.originals[key] = original
        if original is None:
            space.files[key] = None
            continue
        dest = package / sub
        if os.path.abspath(original) != os.path.abspath(dest):
            alone = single_file is not None and key == single_key
            try:  # never through a link, never a FIFO or /proc file (the checks refused those already)
                copy_regular(original, dest, root=(root if inside else None) if alone else root)
            except UntrustedFileError as exc:
                raise WorkspaceError(str(exc)) from None
        space.files[key] = dest
    for key in reference:
        dest = package / DELIVERABLES[key]
        if key == single_key:
            continue
        if not (REFERENCE_PACKAGE / DELIVERABLES[key]).is_file():
            # The student bundle's toolkit has no lab deliverables: the student's own run. A YAML
            # the launch file loads (Ex. 7) and nobody has is an empty one, so Ex. 7 counts as not
            # done instead of the whole file failing to parse.
            if DELIVERABLES[key].endswith(".yaml") and not dest.exists():
                dest.parent.mkdir(parents=True, exist_ok=True)
                dest.write_text("{}\n", encoding="utf-8")
            continue
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(REFERENCE_PACKAGE / DELIVERABLES[key], dest)
        space.substituted.append(key)
    for sub in PROVIDED:
        source = REFERENCE_PACKAGE / sub
        if source.is_file():
            (package / sub).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(source, package / sub)
    for script in (package / "scripts").glob("*.py") if (package / "scripts").is_dir() else []:
        script.chmod(0o755)
    if standins:
        _fake_franka_control(ws)
        _fake_rosserial_python(ws)
    _ros_intro_alias(ws, package)
    space.grader_dir.mkdir(parents=True, exist_ok=True)
    _open_up(session_dir, package, uid)
    return space


def _open_up(session_dir: Path, package: Path, uid: Optional[int]) -> None:
    """The student's uid may enter the session folder and owns its package copy."""
    for folder in [session_dir] + list(package.parents)[: len(package.relative_to(session_dir).parts) - 1]:
        folder.chmod(0o755)
    for path in [package] + list(package.rglob("*")):
        if uid is not None:
            os.chown(path, uid, uid, follow_symlinks=False)
        if path.is_dir():
            path.chmod(0o755)


def ros_package_path(ws: Path, environ: Optional[Dict[str, str]] = None) -> str:
    """``ws`` first, then the system's ROS packages; never the repository (its hri_lab would shadow)."""
    env = environ if environ is not None else dict(os.environ)
    keep: List[str] = [str(ws)]
    for entry in env.get("ROS_PACKAGE_PATH", "").split(":"):
        if not entry or Path(entry).resolve() == REPO or finds_hri_lab(entry):
            continue
        if entry not in keep:
            keep.append(entry)
    if not env.get("ROS_DISTRO") and "/usr/share" not in keep:
        keep.append("/usr/share")
    return ":".join(keep)
