"""nbgrader configuration of the HRI lab's Task 4 course (this folder is the course directory).

Run nbgrader through the Makefile from a fresh shell (``make release``, ``make grade``, ``make formgrader``,
``make feedback``, ``make release-feedback``, ``make nbgrader ARGS="..."``: nbgrader is in .venv only);
notebooks/README.md describes the course.
"""

import os
import sys

c = get_config()  # noqa: F821 - nbgrader's config loader defines it

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))  # the toolkit, also when it is not installed
from hri_teleop.course.release import exclude_overwriting  # noqa: E402 - after the path above

c.CourseDirectory.course_id = "hri-task4-teleoperation"
c.CourseDirectory.root = here

# Each assignment folder holds the student's hri_lab package beside the notebooks
# (robot_params.yaml, mapping_node.py, sensor.launch, teleoperation.py,
# teleoperation.launch, graph.yaml). Autograde must grade the student's files, never
# replace them with the instructor's.
c.Autograde.exclude_overwriting = exclude_overwriting()

# Files the notebooks write next to themselves while they run (a parameter dump, pad
# scripts, plots) are the student's scratch, never part of a release.
c.CourseDirectory.ignore = [".ipynb_checkpoints", "*.pyc", "__pycache__", "feedback", "catkin_ws",
                            "new_robot_params.yaml", "ex[0-9][0-9]_*.yaml", "ex[0-9][0-9]_*.png"]

# Execution: a check runs the student's nodes on a private ROS master (up to ~30 s on a
# busy machine); a notebook starts its own roscore. Generous per-cell limits, and a
# kernel that is given time to start on a loaded grading server.
c.Execute.timeout = 300
c.Execute.startup_timeout = 120
c.Execute.interrupt_on_timeout = True

# The student's stub in code solution cells (the same hint the file templates use).
c.ClearSolutions.code_stub = {"python": "# YOUR CODE HERE\nraise NotImplementedError()"}
c.ClearSolutions.text_stub = "YOUR ANSWER HERE"
