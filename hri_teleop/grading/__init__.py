"""The autograder of handout Task 4: student files checked against the lab's reference rules.

Entry points (grading/README.md): ``hri-grade`` (``apps/grade.py``), ``make grade`` (``batch``) and the names
below: ``grade`` returns a check's result, ``check`` raises AssertionError with the student's feedback unless
every part passes. Each deliverable's check lives in its module of ``exercises`` (docs/adding-an-exercise.md).
No lab node imports it; rospy is needed only by the parts that run ROS. The names below are imported when
first used, so a grading session or probe does not load the checks (0.2 s of CPU per process).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any, Dict

if TYPE_CHECKING:
    from hri_teleop.grading.checks import CHECKS, check, grade, grade_submission
    from hri_teleop.grading.results import CheckResult, GradingError, Part, feedback_text, gradescope_json

__all__ = ["CHECKS", "CheckResult", "GradingError", "Part", "feedback_text", "gradescope_json", "grade", "check",
           "grade_submission"]

_RESULTS = ("CheckResult", "GradingError", "Part", "feedback_text", "gradescope_json")
#: Where each name of ``__all__`` lives.
_HOME: Dict[str, str] = {name: "hri_teleop.grading.checks" for name in __all__ if name not in _RESULTS}
_HOME.update({name: "hri_teleop.grading.results" for name in _RESULTS})


def __getattr__(name: str) -> Any:
    """A name of ``__all__``, imported from its module the first time it is asked for."""
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(home), name)
    globals()[name] = value
    return value
