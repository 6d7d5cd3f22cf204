"""Started in a student's processes under the grader's clock: time.sleep follows /clock there.

Then the next sitecustomize on the path runs, as it would have without this folder.
"""

import importlib.machinery
import importlib.util
import os
import sys

try:
    from hri_teleop.grading.run.clock_sleep import install
except ImportError:  # the toolkit is not importable here: time.sleep stays the wall clock's
    pass
else:
    install()

_here = os.path.dirname(os.path.abspath(__file__))
# the grader's site folders (this one, the clock's, the guard's) chain to each other: skip them all, or two of
# them on one path would run each other for ever
_ours = {os.path.join(os.path.dirname(_here), name) for name in ("clock_site", "guard_site")}
_spec = importlib.machinery.PathFinder.find_spec(
    "sitecustomize", [p for p in sys.path if os.path.abspath(p or ".") not in _ours])
if _spec is not None and _spec.loader is not None:
    _next = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(_next)
