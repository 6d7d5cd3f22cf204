"""Started first in every graded student process: the reference guard (hri_teleop.grading.run.student_guard).

Loaded from its file, so it installs under any Python (the system's, which roslaunch and a node's shebang may
start, has no toolkit on its path); a process the guard is meant for but cannot guard ends at once. Then the
next sitecustomize on the path runs (the grader's clock, the system's), as it would without this folder.
"""

import importlib.machinery
import importlib.util
import os
import sys

_here = os.path.dirname(os.path.abspath(__file__))
try:
    _file = importlib.util.spec_from_file_location("hri_student_guard", os.path.join(os.path.dirname(_here),
                                                                                      "student_guard.py"))
    if _file is None or _file.loader is None:
        raise ImportError("student_guard.py is not there")
    _guard = importlib.util.module_from_spec(_file)
    sys.modules["hri_student_guard"] = _guard
    _file.loader.exec_module(_guard)
    _guard.install()
except Exception as _exc:  # whatever it was, this process must not run unguarded
    if os.environ.get("HRI_STUDENT_GUARD"):
        sys.stderr.write(f"hri-grade: the reference guard could not start ({type(_exc).__name__}: {_exc}); "
                         "the grader runs no student code without it\n")
        sys.stderr.flush()
        os._exit(3)
    raise

# the grader's site folders (this one, the clock's, the guard's) chain to each other: skip them all, or two of
# them on one path would run each other for ever
_ours = {os.path.join(os.path.dirname(_here), name) for name in ("clock_site", "guard_site")}
_spec = importlib.machinery.PathFinder.find_spec(
    "sitecustomize", [p for p in sys.path if os.path.abspath(p or ".") not in _ours])
if _spec is not None and _spec.loader is not None:
    _next = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(_next)
