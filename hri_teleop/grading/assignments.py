"""The course's nbgrader assignments, the grader's checks of each, and the environment nbgrader runs in.

The release tools (:mod:`hri_teleop.course.release`) and ``make grade`` both need these; they
live here, below both.
"""

from __future__ import annotations

import os
from typing import Dict, Mapping, Optional, Tuple

from hri_teleop.grading.exercises import registry

__all__ = ["ASSIGNMENTS", "ASSIGNMENT_CHECKS", "nbgrader_env"]

#: nbgrader assignments: the preparation at home (Ex. 1-7), the lab session (Ex. 8-15).
ASSIGNMENTS = ("preparation", "lab")
#: The grader's checks of the student files each assignment's notebooks grade (``make grade`` runs
#: them on ``submitted/<student>/<assignment>/hri_lab`` beside nbgrader's autograde): each exercise
#: names its assignment (``hri_teleop/grading/exercises``).
ASSIGNMENT_CHECKS: Dict[str, Tuple[str, ...]] = {name: registry.by_assignment().get(name, ()) for name in ASSIGNMENTS}


def nbgrader_env(base: Optional[Mapping[str, str]] = None) -> Dict[str, str]:
    """The environment nbgrader runs in (``base``: default this process's): no Python warnings, since
    nbgrader scores a cell that wrote to stderr with 0 points (a DeprecationWarning must not cost a
    student a grade)."""
    return dict(os.environ if base is None else base, PYTHONWARNINGS="ignore")
