"""The grader's inputs and their expected outputs, public and hidden (seeded), from the lab's rules.

The public traces and the hidden inputs come from the same ROS-free functions (a public trace is
the hidden generator with fixed choices), and the expected outputs always from the reference
implementation (``map_force``, ``TeleopController``), never from a second copy of the rules.
Hidden cases differ per student (``student_seed``; a folder graded alone: ``seed_for``) and use other
parameter values than the public.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import Union

from hri_teleop.core.config import lab_max_sensor_force
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.grading.run.gains import TeleopGains

__all__ = [
    "CasesError", "SEED_ENV", "seed_for", "student_seed", "default_seed", "PUBLIC_MAX_SENSOR_FORCE",
    "TeleopGains",
]

#: The value of /max_sensor_force in the public traces (the lab's typical calibration).
PUBLIC_MAX_SENSOR_FORCE = lab_max_sensor_force()  # the lab's calibration (hri_lab/config/calibration.yaml)
PUBLIC_SEED = 20240415  # fixed: the public traces must be the same on every machine


class CasesError(HriTeleopError, ValueError):
    """A case was asked for with impossible parameters (one line with the fix)."""


def seed_for(submission: Union[str, Path]) -> int:
    """A stable seed from a submission's folder: its last three path components.

    ``submitted/alice/task4/hri_lab`` and ``submitted/bob/task4/hri_lab`` differ, and the
    same submission graded twice (or moved to another disk) gets the same hidden inputs.
    """
    parts = Path(submission).expanduser().resolve().parts[-3:]
    digest = hashlib.sha256("/".join(parts).encode("utf-8")).hexdigest()
    return int(digest[:8], 16)


#: Set by make grade and the Gradescope autograder for nbgrader's kernels: the student's seed
#: (:func:`student_seed`), which the notebooks' check cells take instead of their folder's.
SEED_ENV = "HRI_GRADE_SEED"


def student_seed(student: str) -> int:
    """The seed of one student's hidden inputs, from their id alone.

    make grade (the files job and the notebooks' check cells, by nbgrader's student id) and the
    Gradescope autograder (by the roster's student id) derive it the same way, so a student meets
    the same hidden inputs whichever way the course grades, in every assignment and on every rerun.
    """
    digest = hashlib.sha256(f"student:{student}".encode("utf-8")).hexdigest()
    return int(digest[:8], 16)


def default_seed(submission: Union[str, Path]) -> int:
    """The seed when none is given: ``$HRI_GRADE_SEED`` (a kernel make grade or Gradescope runs for a
    student), else the submission folder's (:func:`seed_for`)."""
    value = os.environ.get(SEED_ENV, "").strip()
    if not value:
        return seed_for(submission)
    try:
        return int(value)
    except ValueError:
        raise CasesError(f"{SEED_ENV}={value!r} is not a whole number; unset it (the seed then comes from "
                         "the folder) or give the student's seed") from None


# -- mapping_node (Ex. 5) ----------------------------------------------------------------


# -- teleoperation.py, the student's parts (Ex. 8) ---------------------------------------


# -- teleoperation.py as a node with the virtual pad (Ex. 9) --------------------------


# -- teleoperation.launch in simulation (Ex. 12-13) -------------------------------------


