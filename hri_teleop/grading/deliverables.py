"""The registry's list: the course's graded deliverables, one exercise module (or folder) each.

Each entry names a module of ``hri_teleop/grading/exercises`` and the file it judges in the student's
hri_lab package ("" when it judges the package itself); its check's name is the module's with ``-``
for ``_`` (``mapping_node`` -> ``mapping-node``). Adding an exercise adds one line here
(docs/adding-an-exercise.md). It sits at the bottom of the grader, so the shared kit (``run/``,
``judge/``) may read it without importing any exercise.
"""

from __future__ import annotations

from typing import Dict, Mapping

from hri_teleop.grading.results import GradingError

__all__ = ["DELIVERABLE_FILES", "key_of"]

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


def key_of(sub: str, files: Mapping[str, str] = DELIVERABLE_FILES) -> str:
    """The key of the exercise that judges the file at ``sub`` in the package (``scripts/mapping_node.py``
    -> ``mapping_node``); ``files`` is the list to look in (the registry's own, or a test's)."""
    for key, path in files.items():
        if path and path == sub:  # an exercise that judges the package itself has no file
            return key
    raise GradingError(f"{sub} is no deliverable of the course (hri_teleop/grading/exercises lists them)")
