"""``python -m hri_teleop.course``: the instructor's course commands (:mod:`hri_teleop.course.cli`)."""

import sys

from hri_teleop.course.cli import main

sys.exit(main())
