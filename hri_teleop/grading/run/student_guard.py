"""The reference guard at run time: a graded student process cannot load the lab's reference rules.

Installed first in every process that runs a student's code (its sitecustomize, or the probe itself): an
audit hook and an import finder refuse the rule modules by name and their files by inode, the lab's nodes the
grader placed beside the student's, programs that would start without the guard, ctypes and code posing as the
toolkit's. What each refusal closes: docs/grading-internals.md, "Threat model". Python 3.8-compatible and
needing nothing of the toolkit: it runs before anything else.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import threading
from typing import Any, Dict, FrozenSet, Iterable, List, Mapping, Optional, Sequence, Set, Tuple

__all__ = ["GUARD_ENV", "SITE_DIR", "GuardError", "guard_policy", "install", "refused_spawn", "blocked_modules",
           "REFERENCE_RULES"]

#: The environment variable that carries the policy (JSON) into the student's processes.
GUARD_ENV = "HRI_STUDENT_GUARD"
#: The folder whose sitecustomize installs the guard (on PYTHONPATH of every student process).
SITE_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "guard_site")
#: Modules that hold the lab's reference rules: what students write (Ex. 4, 5, 8, 11) and the grader's cases.
REFERENCE_RULES = ("hri_teleop.core.mapping", "hri_teleop.core.teleop", "hri_teleop.core.paramfile",
                   "hri_teleop.sim.lab", "hri_teleop.grading.cases", "hri_teleop.grading.judge",
                   "hri_teleop.mapping", "hri_teleop.teleop", "hri_teleop.paramfile")
_ISOLATING_FLAGS = ("-I", "-E", "-S", "-s")
#: ROS's own programs roslaunch starts itself (``rosversion -d`` where ROS_DISTRO is not set): allowed when
#: the code asking is not the student's (a launch file's ``$(eval ...)`` is).
ROS_TOOLS = ("rosversion", "rospack", "rosmaster", "rosout")
_SPAWN_EVENTS = ("subprocess.Popen", "os.exec", "os.posix_spawn", "os.spawn", "os.system", "os.startfile",
                 "pty.spawn")


try:
    from hri_teleop.core.errors import HriTeleopError
except ImportError:  # loaded from its file by a Python without the toolkit on its path (the system's)
    class HriTeleopError(Exception):  # type: ignore[no-redef]
        """The toolkit's error base, where the toolkit cannot be imported."""


class GuardError(HriTeleopError, PermissionError):
    """What a guarded student process is refused: one line naming what and why (it ends up in the feedback)."""


def blocked_modules(names: Iterable[str] = REFERENCE_RULES) -> Tuple[str, ...]:
    return tuple(names)


def _module_files(module: str, toolkit_root: str) -> List[str]:
    """The source files and caches of ``module`` (a package: all of it) below ``toolkit_root``."""
    parts = module.split(".")
    if parts[0] != "hri_teleop":
        return []
    base = os.path.join(toolkit_root, *parts[1:])
    found: List[str] = []
    if os.path.isdir(base):
        for folder, _dirs, files in os.walk(base):
            found += [os.path.join(folder, f) for f in files if f.endswith((".py", ".pyc"))]
    folder, name = os.path.split(base)
    if os.path.isfile(base + ".py"):
        found.append(base + ".py")
    cache = os.path.join(folder, "__pycache__")
    if os.path.isdir(cache):
        found += [os.path.join(cache, f) for f in os.listdir(cache) if f.startswith(name + ".")]
    return found


#: Threads in which the guard itself reads a file (a script's first line, a placed file's hash): not refused.
_OWN_READS: Set[int] = set()


def _own_read(path: str, size: int = -1) -> bytes:
    """``path``'s bytes (``size`` at most), read by the guard itself past its own refusal of secret files."""
    me = threading.get_ident()
    _OWN_READS.add(me)
    try:
        with open(path, "rb") as fh:
            return fh.read(size)
    finally:
        _OWN_READS.discard(me)


def _sha256(path: str) -> str:
    return hashlib.sha256(_own_read(path)).hexdigest()


def guard_policy(package: str, placed: Sequence[str], toolkit_root: str,
                 modules: Iterable[str] = REFERENCE_RULES, secret: Optional[Sequence[str]] = None) -> str:
    """The policy (JSON) for the student processes of one run: ``package`` the student's package folder,
    ``placed`` the programs the grader put there (run as the lab's, unguarded), ``secret`` those of them no
    student code may open (the lab's versions of other deliverables; default: all of ``placed``; the provided
    nodes every student has are not), ``toolkit_root`` the ``hri_teleop`` folder whose reference modules are
    refused."""
    files = [f for m in modules for f in _module_files(m, toolkit_root)]
    hidden = list(placed if secret is None else secret)
    return json.dumps({"package": os.path.abspath(package), "modules": list(modules),
                       "files": files + [os.path.abspath(p) for p in hidden if os.path.isfile(p)],
                       "placed": {os.path.abspath(p): _sha256(p) for p in placed if os.path.isfile(p)},
                       "python": os.path.realpath(sys.executable)})


def _inode(path: Any) -> Optional[Tuple[int, int]]:
    try:
        st = os.stat(path)
    except (OSError, TypeError, ValueError):
        return None
    return st.st_dev, st.st_ino


class _Policy:
    def __init__(self, data: Mapping[str, Any]) -> None:
        self.package = str(data.get("package", ""))
        self.modules = tuple(str(m) for m in data.get("modules", ()))
        self.placed: Dict[str, str] = {str(k): str(v) for k, v in dict(data.get("placed", {})).items()}
        self.python = str(data.get("python", ""))
        self.inodes: Set[Tuple[int, int]] = set()
        for path in data.get("files", ()):
            found = _inode(path)
            if found is not None:
                self.inodes.add(found)
        self.env = {GUARD_ENV: json.dumps(dict(data))}

    def is_placed(self, path: str) -> bool:
        path = os.path.abspath(path)
        digest = self.placed.get(path)
        try:
            return digest is not None and _sha256(path) == digest
        except OSError:
            return False

    def module_refused(self, name: str) -> bool:
        return any(name == m or name.startswith(m + ".") for m in self.modules)


def _opened_path(args: Sequence[Any]) -> Any:
    path = args[0] if args else None
    return os.fsdecode(path) if isinstance(path, (str, bytes)) else None


def _is_proc_mem(path: str) -> bool:
    parts = os.path.abspath(path).split("/")
    return len(parts) >= 4 and parts[1] == "proc" and parts[-1] in ("mem", "pagemap")


def _python_flags(argv: Sequence[str]) -> List[str]:
    """The interpreter options before the script or -c/-m: those that would skip this guard."""
    found = []
    for arg in argv[1:]:
        if not arg.startswith("-") or arg in ("-c", "-m", "-"):
            break
        found += [f for f in _ISOLATING_FLAGS if arg == f or (arg.startswith("-") and not arg.startswith("--")
                                                               and f[1] in arg[1:])]
    return found


def refused_spawn(executable: str, argv: Sequence[str], env: Optional[Mapping[str, str]], python: str,
                  site_dir: str, policy_text: str, ros_tool: bool = False) -> str:
    """Why a guarded process may not start ``executable`` with ``argv`` and ``env`` ('' when it may): only this
    Python (no flag that skips the guard), a Python script whose first line is a plain python3 shebang, or
    (``ros_tool``) one of ROS's own programs roslaunch starts, each with this guard's environment."""
    env = env if env is not None else os.environ
    if env.get(GUARD_ENV) != policy_text or site_dir not in env.get("PYTHONPATH", "").split(os.pathsep):
        return "a program started without the grader's environment"
    if ros_tool:
        return ""
    exe = os.path.realpath(executable) if executable else ""
    if exe and os.path.realpath(python) == exe:
        flags = _python_flags(argv)
        return f"python {' '.join(flags)} (an option that skips the grader's checks)" if flags else ""
    if exe.endswith(".py") and os.path.isfile(exe):
        try:
            first = _own_read(exe, 200).split(b"\n", 1)[0].decode("utf-8", "replace").strip()
        except OSError:
            return f"{executable} (unreadable)"
        words = first[2:].split() if first.startswith("#!") else []
        plain = (words == ["/usr/bin/env", "python3"] or words == ["/usr/bin/env", "python"]
                 or (len(words) == 1 and os.path.basename(words[0]).startswith("python")))
        return "" if plain else f"{executable} (its first line must be #!/usr/bin/env python3, nothing more)"
    return f"{executable or argv[:1]} (a graded node is a Python script; no shell, no other program)"


_installed: Dict[str, Any] = {}


def install(policy_text: Optional[str] = None, main: Optional[str] = None) -> bool:
    """Install the guard in this process (once) when a policy is given or in :data:`GUARD_ENV`, unless ``main``
    (default: the main script) is a file the grader placed. True when installed."""
    text = policy_text if policy_text is not None else os.environ.get(GUARD_ENV, "")
    if not text or _installed:
        return bool(_installed)
    try:
        policy = _Policy(json.loads(text))
    except (ValueError, TypeError, AttributeError):
        raise GuardError(f"{GUARD_ENV} is not a guard policy; the grader sets it") from None
    script = main if main is not None else (sys.argv[0] if sys.argv and sys.argv[0] not in ("", "-c", "-m") else "")
    if script and policy.is_placed(script):
        return False  # the lab's own node, run in place of another exercise's deliverable
    os.environ[GUARD_ENV] = text
    if SITE_DIR not in os.environ.get("PYTHONPATH", "").split(os.pathsep):
        os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (SITE_DIR, os.environ.get("PYTHONPATH", "")) if p)
    for name in list(sys.modules):
        if policy.module_refused(name):
            del sys.modules[name]  # loaded before the guard (not by the student): out of reach by name
    sys.meta_path.insert(0, _Finder(policy))
    sys.addaudithook(_hook(policy, text))
    _installed["policy"] = policy
    return True


class _Finder:
    """Refuses the reference rules by name, with the reason (the audit hook refuses their files anyway)."""

    def __init__(self, policy: _Policy) -> None:
        self.policy = policy

    def find_spec(self, name: str, path: Any = None, target: Any = None) -> None:
        if self.policy.module_refused(name):
            raise ImportError(f"the grader refuses {name}: it holds the lab's reference rule, and writing "
                              "the rule is the exercise (use only hri_teleop.student)")
        return None


def _hook(policy: _Policy, text: str) -> Any:
    refused_modules: FrozenSet[str] = frozenset(policy.modules)
    inodes = policy.inodes

    def hook(event: str, args: Tuple[Any, ...]) -> None:
        if event == "open":
            path = _opened_path(args)
            if path is None or threading.get_ident() in _OWN_READS:
                return
            if _is_proc_mem(path):
                raise GuardError(f"the grader refuses to open {path}")
            if inodes and _inode(path) in inodes:
                raise GuardError(f"the grader refuses to open {path}: it is the lab's reference, not your work")
        elif event in ("os.rename", "os.link", "os.symlink", "shutil.copyfile", "shutil.copymode"):
            for path in args[:2]:
                if isinstance(path, (str, bytes)) and _inode(path) in inodes:
                    raise GuardError(f"the grader refuses to move or link {os.fsdecode(path)}")
        elif event == "import":
            name = args[0] if args else ""
            if isinstance(name, str) and any(name == m or name.startswith(m + ".") for m in refused_modules):
                raise ImportError(f"the grader refuses {name}: it holds the lab's reference rule")
        elif event.startswith("ctypes.") or event in ("compile", "code.__new__", "marshal.loads", "gc.get_objects",
                                                       "gc.get_referrers", "gc.get_referents"):
            if event == "compile" and len(args) > 1 and not _claims_elsewhere(args[1], policy):
                return  # compile() of the student's own text under its own (or no) name
            if _student_asks(policy, imports_pass=not event.startswith("ctypes.")):
                raise GuardError(f"the grader refuses {event} in a graded node")
        elif event in _SPAWN_EVENTS:
            _check_spawn(event, args, policy, text)

    return hook


_STDLIB = os.path.dirname(os.__file__)


def _in_stdlib(filename: str) -> bool:
    return filename.startswith(_STDLIB + os.sep) and "-packages" not in filename


def _is_students(filename: str, policy: _Policy) -> bool:
    """Whether code from ``filename`` is the student's: a file of their package (not one the grader placed),
    or text with no file (``exec``, ``eval``, ``-c``, a launch file's ``$(eval ...)``)."""
    if not os.path.isabs(filename):
        return not filename.startswith("<frozen")
    path = os.path.abspath(filename)
    return (path == policy.package or path.startswith(policy.package + os.sep)) and path not in policy.placed


def _student_asks(policy: _Policy, imports_pass: bool = False) -> bool:
    """Whether the innermost code that is neither this guard, the standard library nor the import system is the
    student's;
    ``imports_pass``: False when the import system is on the way (it compiles and unmarshals every module)."""
    try:
        frame: Any = sys._getframe(1)  # this guard's own frames are skipped below
    except ValueError:  # an event raised with no Python frame above the hook (a thread's start, the exit)
        return False
    while frame is not None:
        name = frame.f_code.co_filename
        if imports_pass and name.startswith("<frozen importlib"):
            return False
        if name == __file__ or name.startswith("<frozen") or _in_stdlib(name):
            frame = frame.f_back  # the standard library acts for whoever called it (subprocess, codeop, runpy)
            continue
        return _is_students(name, policy)
    return False


def _claims_elsewhere(filename: Any, policy: _Policy) -> bool:
    """A compile() under the name of a file outside the student's package: code posing as the toolkit's."""
    if not isinstance(filename, (str, bytes)):
        return False
    name = os.fsdecode(filename)
    return os.path.isabs(name) and not _is_students(name, policy)


def _check_spawn(event: str, args: Tuple[Any, ...], policy: _Policy, text: str) -> None:
    if event == "os.system":
        raise GuardError(f"the grader refuses os.system({str(args[0])[:80]!r}): a graded node starts no program")
    env: Optional[Mapping[str, str]] = None
    if event == "subprocess.Popen":
        executable, argv, _cwd, env = args[0], args[1], args[2], args[3]
        argv = [argv] if isinstance(argv, (str, bytes)) else list(argv or ())
        executable = executable or (argv[0] if argv else "")
    elif event in ("os.exec", "os.posix_spawn"):
        executable, argv, env = args[0], list(args[1] or ()), args[2]
    else:  # os.spawn: mode, path, args, env
        executable, argv, env = args[1], list(args[2] or ()), args[3] if len(args) > 3 else None
    executable = os.fsdecode(executable) if isinstance(executable, (str, bytes)) else ""
    if executable and not os.path.isabs(executable):
        from shutil import which  # noqa: PLC0415 - only when a program is named without its folder

        executable = which(executable) or executable
    strs = [os.fsdecode(a) if isinstance(a, (str, bytes)) else str(a) for a in argv]
    env_map = None if env is None else {os.fsdecode(k): os.fsdecode(v) for k, v in dict(env).items()}
    ros_tool = (os.path.basename(executable) in ROS_TOOLS and not _student_asks(policy)
                and os.path.dirname(executable) in ("/usr/bin", "/opt/ros/noetic/bin")) or policy.is_placed(executable)
    why = refused_spawn(executable, strs, env_map, policy.python, SITE_DIR, text, ros_tool)
    if why:
        raise GuardError(f"the grader refuses to start {why}")
