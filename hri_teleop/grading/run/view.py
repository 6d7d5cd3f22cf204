"""What student code sees of the machine when graded: a list of what is shown, never a list of what is hidden.

A box that binds the whole machine and hides some folders leaves in sight everything nobody thought of
(the checkout's .git and so the answer key, the course, other students, the grader's home). A box here starts
from an empty root and is shown, read-only, the system, its Python and the toolkit without the answers; its
own folders the caller adds. The rules are pure functions of paths; :func:`view_argv` makes bubblewrap's
arguments (docs/grading-internals.md, "Threat model").
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

from hri_teleop.core.paths import REPO

__all__ = ["NEVER_SHOWN", "SYSTEM", "TOOLKIT_SHOWN", "TOOLKIT_MASKED", "FOLDERS_MASKED", "SEARCH_PATH_KEYS", "View", "toolkit_view",
           "under", "shown_search_paths", "python_packages", "view_argv"]

#: The machine's own software, shown read-only (a link among them is made again as the same link).
SYSTEM = ("/usr", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32", "/etc", "/opt", "/sys")
#: What of the checkout student code runs on (relative to the checkout): what the student bundle's toolkit
#: holds of it, less its docs and setup (the notebooks' kernel starts through tools/kernel.sh).
TOOLKIT_SHOWN = ("hri_teleop", "hri_lab", "grading/traces", "tools/env.sh", "tools/kernel.sh")
#: Files of the checkout that stay out of sight inside what is shown: what students write (the lab's
#: completed deliverables and the CMakeLists whose lines are Ex. 9's answer).
TOOLKIT_MASKED = ("hri_lab/scripts/mapping_node.py", "hri_lab/scripts/teleoperation.py",
                  "hri_lab/launch/sensor.launch", "hri_lab/launch/teleoperation.launch",
                  "hri_lab/config/robot_params.yaml", "hri_lab/CMakeLists.txt", "hri_lab/graph.yaml")
#: Folders of the checkout masked inside what is shown: the Gradescope course (its notebooks' hidden tests).
FOLDERS_MASKED = ("hri_teleop/grading/gradescope",)
#: Environment variables whose folders a box may need (a ROS install elsewhere, a catkin workspace).
SEARCH_PATH_KEYS = ("PATH", "PYTHONPATH", "ROS_PACKAGE_PATH", "CMAKE_PREFIX_PATH", "LD_LIBRARY_PATH",
                    "PKG_CONFIG_PATH", "ROS_ROOT", "ROS_ETC_DIR")
#: Never shown, nor anything above them: shown search paths below them are refused.
NEVER_SHOWN = ("/home", "/root", "/tmp", "/var/tmp", "/run", "/mnt", "/media", "/srv", "/proc", "/dev")


def under(path: str, folder: str) -> bool:
    """Whether ``path`` is ``folder`` or inside it (by whole components: /srvdata is not under /srv)."""
    path, folder = os.path.normpath(path), os.path.normpath(folder)
    return path == folder or folder == "/" or path.startswith(folder + "/")


@dataclass(frozen=True)
class View:
    """A box's view of the machine: ``shown`` read-only, ``masked_files`` empty, ``masked_folders`` empty,
    ``links`` (path, target) made as links, ``writable`` bound read-write (the caller's own folders)."""

    shown: Tuple[str, ...]
    masked_files: Tuple[str, ...] = ()
    masked_folders: Tuple[str, ...] = ()
    links: Tuple[Tuple[str, str], ...] = ()
    writable: Tuple[str, ...] = ()


def _allowed(entry: str, repo: str, allowed_in_repo: Sequence[str]) -> bool:
    """Whether a search path's folder may be shown: not at or above the checkout, a home or /tmp, and inside
    the checkout only below ``allowed_in_repo``."""
    if entry == "/" or under(repo, entry) or any(under(entry, n) or under(n, entry) for n in NEVER_SHOWN):
        return False
    return not under(entry, repo) or any(under(entry, a) for a in allowed_in_repo)


def python_packages(entry: str, repo: str) -> bool:
    """Whether a folder of the running Python's own path is one of its package folders (``site-packages``,
    ``dist-packages``: a venv reused from a clone under /tmp, say) that may be shown wherever it lies, as long
    as it is not at or above the checkout, a home or /tmp."""
    if entry == "/" or under(repo, entry) or any(under(n, entry) for n in NEVER_SHOWN):
        return False
    return any(part.endswith("-packages") for part in entry.split("/"))


def shown_search_paths(env: Mapping[str, str], repo: str, allowed_in_repo: Sequence[str],
                       keys: Sequence[str] = SEARCH_PATH_KEYS, extra: Sequence[str] = ()) -> List[str]:
    """The absolute folders of ``env``'s search paths (and ``extra``) a box may see: none at or above the
    checkout, a home or /tmp (``PYTHONPATH=$HOME`` would show all of it), and inside the checkout only
    ``allowed_in_repo``."""
    found: List[str] = []
    entries = [e for key in keys for e in env.get(key, "").split(os.pathsep)] + list(extra)
    for entry in entries:
        if not os.path.isabs(entry):
            continue
        entry = os.path.normpath(entry)
        if _allowed(entry, repo, allowed_in_repo) and entry not in found:
            found.append(entry)
    return found


def _python_prefixes() -> List[str]:
    """The running Python's prefixes (its venv, its installation), wherever they lie."""
    exe = os.path.realpath(sys.executable)
    return [os.path.normpath(p) for p in (sys.prefix, sys.base_prefix, os.path.dirname(os.path.dirname(exe)))]


def toolkit_view(env: Mapping[str, str], writable: Sequence[str] = (), extra_shown: Sequence[str] = (),
                 repo: Optional[str] = None, cwd: Optional[str] = None) -> View:
    """The view of a box that runs student code with this toolkit: :data:`SYSTEM`, the running Python, the
    checkout's :data:`TOOLKIT_SHOWN` (with :data:`TOOLKIT_MASKED` and :data:`FOLDERS_MASKED` out of sight),
    ``env``'s search paths, ``extra_shown`` read-only and ``writable`` read-write. Only existing paths."""
    root = os.path.normpath(repo if repo is not None else str(REPO))
    in_repo = [os.path.join(root, p) for p in TOOLKIT_SHOWN]
    python = [p for p in _python_prefixes() if p != "/"]
    here = os.path.realpath(cwd or os.getcwd())  # python -m puts the folder it runs in on sys.path
    path_entries = [p for p in sys.path if os.path.isabs(p) and os.path.realpath(p) != here]
    links: List[Tuple[str, str]] = []
    shown: List[str] = []
    for path in SYSTEM:
        if os.path.islink(path):
            links.append((path, os.readlink(path)))
        elif os.path.isdir(path):
            shown.append(path)
    # the Python's folders inside the checkout (its .venv) are shown; any other part of the checkout is not
    python_ok = [p for p in python if not under(root, p)]
    packages = [os.path.normpath(p) for p in path_entries if python_packages(os.path.normpath(p), root)]
    candidates = python_ok + packages + in_repo + shown_search_paths(env, root, in_repo + python_ok, extra=path_entries)
    candidates += list(extra_shown)
    for path in candidates:
        path = os.path.realpath(path)  # /bin in PATH is /usr/bin, which the links above already lead to
        if (os.path.isdir(path) or os.path.isfile(path)) and not any(under(path, s) for s in shown):
            shown = [s for s in shown if not under(s, path)] + [path]
    masked_files = [os.path.join(root, p) for p in TOOLKIT_MASKED if os.path.isfile(os.path.join(root, p))]
    masked_folders = [os.path.join(root, p) for p in FOLDERS_MASKED if os.path.isdir(os.path.join(root, p))]
    return View(tuple(sorted(shown)), tuple(masked_files), tuple(masked_folders), tuple(links),
                tuple(os.path.normpath(w) for w in writable))


def view_argv(view: View, proc: Sequence[str] = ("--proc", "/proc"), tmp_bytes: int = 0) -> List[str]:
    """bubblewrap arguments that build ``view`` on an empty root: links, /dev and ``proc``, a private /tmp (of
    ``tmp_bytes`` when given), read-only binds (shallowest first), the masks, the writable binds; the root
    itself is left for the caller, who adds its own mounts and then ``--remount-ro /``."""
    argv: List[str] = []
    for path, target in view.links:
        argv += ["--symlink", target, path]
    # /dev, /proc and /tmp first: a folder shown below /tmp (a grading workspace) is bound on top of the tmpfs
    argv += ["--dev", "/dev", *proc]
    argv += (["--size", str(tmp_bytes)] if tmp_bytes else []) + ["--tmpfs", "/tmp"]
    for path in sorted(view.shown, key=lambda p: (p.count("/"), p)):
        argv += ["--ro-bind", path, path]
    for path in view.masked_files:
        argv += ["--ro-bind", "/dev/null", path]
    for path in view.masked_folders:
        argv += ["--tmpfs", path, "--remount-ro", path]
    for path in view.writable:
        argv += ["--bind", path, path]
    return argv


def mount_points(view: View) -> Dict[str, str]:
    """Each path the view mounts -> how ("ro", "rw", "mask", "link"): for tests and the threat model."""
    kinds: Dict[str, str] = {p: "ro" for p in view.shown}
    kinds.update({p: "mask" for p in (*view.masked_files, *view.masked_folders)})
    kinds.update({p: "link" for p, _t in view.links})
    kinds.update({p: "rw" for p in view.writable})
    return kinds
