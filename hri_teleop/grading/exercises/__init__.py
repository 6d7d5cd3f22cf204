"""The course's graded deliverables, one module (or folder) each: docs/adding-an-exercise.md.

Everything the grader knows about one deliverable (its hidden inputs, the session that runs it, its
judge, its parts and points, its feedback) lives in its module, which ends with an
:class:`~hri_teleop.grading.exercises.exercise.Exercise`. This list is the registry: each entry names
such a module and the file it judges in the student's hri_lab package ("" when it judges the package
itself). Its check's name is the module's, with ``-`` for ``_`` (``mapping_node`` -> ``mapping-node``).
The run, the judge, the points, the reports, Gradescope, ``make check`` and the course read it through
:mod:`~hri_teleop.grading.exercises.registry`; the grader's kit (``run/``, ``judge/``) reads only this list.
"""

from __future__ import annotations

from typing import Dict

__all__ = ["DELIVERABLE_FILES"]

#: module name -> the file it judges, in the order reports and the answer key's results list them.
DELIVERABLE_FILES: Dict[str, str] = {
    "robot_params": "config/robot_params.yaml",
    "mapping_node": "scripts/mapping_node.py",
    "sensor_launch": "launch/sensor.launch",
    "teleoperation": "scripts/teleoperation.py",
    "teleoperation_launch": "launch/teleoperation.launch",
    "graph": "graph.yaml",
    "catkin_package": "",
}
