"""The checks of the notebooks: each judges one deliverable, prints its feedback, returns its points.

A check is the last line of a read-only check cell: the student sees the points and the feedback
that ``hri-grade`` and ``make grade`` give the same files. nbgrader gives the cell no points: a
deliverable's points are counted once, with the files (:mod:`hri_teleop.grading.points`).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Set, Union

from hri_teleop.grading.judge.checks import (
    grade_mapping_node,
    grade_robot_params,
    grade_sensor_launch,
    grade_teleoperation,
    grade_teleoperation_launch,
)
from hri_teleop.grading.judge.compare import TELEOP
from hri_teleop.grading.judge.graph import grade_graph
from hri_teleop.grading.judge.package_check import grade_catkin_package
from hri_teleop.grading.results import CheckResult, feedback_text

__all__ = ["robot_params", "mapping_node", "sensor_launch", "teleoperation_parts", "teleoperation_node",
           "catkin_package", "teleoperation_launch", "graph"]

PathLike = Union[str, Path]

#: The functions below whose check cell runs its whole check as the files' half of ``make check`` runs it
#: (the package alone, no other argument), so that the files' half takes the cell's result
#: (:mod:`hri_teleop.grading.judge.reuse`). ``teleoperation_parts`` (Ex. 8, no node) and
#: ``catkin_package`` (one exercise's parts) judge less than their check: the files' half runs those.
KEEPS_RESULT = {"robot_params": "robot-params", "mapping_node": "mapping-node", "sensor_launch": "sensor-launch",
                "teleoperation_node": "teleoperation", "teleoperation_launch": "teleoperation-launch",
                "graph": "graph"}


#: The last line a check cell prints: where its points count (hri_teleop.grading.points).
POINTS_NOTE = ("these points are your hri_lab files': the course counts them once, with the files you hand in "
               "(this notebook cell adds none)")


def score(result: CheckResult) -> float:
    """Print a check's feedback and return its points: the last line of a check cell.

    The points are the files' (a failing part costs its points, the rest are kept, as ``hri-grade``
    and ``make grade`` score them); the cell itself is read-only and worth no nbgrader points.
    """
    print(feedback_text([result]))
    print(f"note: {POINTS_NOTE}")
    return float(result.score)


def _node_part_names() -> Set[str]:
    return {name for key, (name, _points) in TELEOP.items() if key.startswith("node_")}


def teleoperation_parts_result(package: PathLike, **kwargs: Any) -> CheckResult:
    """Ex. 8: the teleoperation check's parts of the class (gripper, sticks, toggle, rumble), no ROS node."""
    result = grade_teleoperation(package, node=False, **kwargs)
    node = _node_part_names()
    return dataclasses.replace(result, parts=[p for p in result.parts if p.name not in node])


def teleoperation_node_result(package: PathLike, **kwargs: Any) -> CheckResult:
    """Ex. 9: the teleoperation check's parts of the ROS node (topics, types, values with the virtual pad)."""
    result = grade_teleoperation(package, **kwargs)
    node = _node_part_names()
    failed_ex8 = [p.name for p in result.parts if p.name not in node and not p.passed]
    notes = tuple(result.notes) + ((f"Ex. 8 parts still failing (see notebook 08): {'; '.join(failed_ex8)}",)
                                   if failed_ex8 else ())
    return dataclasses.replace(result, parts=[p for p in result.parts if p.name in node], notes=notes)


def robot_params(package: PathLike) -> float:
    """Ex. 4: ``config/robot_params.yaml`` loads with rosparam and holds Table 1."""
    return score(grade_robot_params(package))


def mapping_node(package: PathLike) -> float:
    """Ex. 5: ``scripts/mapping_node.py`` run as a node, fed counts, its /force_mapped compared."""
    return score(grade_mapping_node(package))


def sensor_launch(package: PathLike) -> float:
    """Ex. 6-7: ``launch/sensor.launch`` launched, its nodes and parameters and /force_mapped."""
    return score(grade_sensor_launch(package))


def teleoperation_parts(package: PathLike) -> float:
    """Ex. 8: the Teleoperation class of ``scripts/teleoperation.py``, without ROS."""
    return score(teleoperation_parts_result(package))


def teleoperation_node(package: PathLike) -> float:
    """Ex. 9: ``scripts/teleoperation.py`` as a ROS node driven by the virtual pad."""
    return score(teleoperation_node_result(package))


def catkin_package(package: PathLike, exercise: int) -> float:
    """Ex. 9 and 12: the scripts executable and listed in ``CMakeLists.txt``."""
    return score(grade_catkin_package(package, exercise=exercise))


def teleoperation_launch(package: PathLike) -> float:
    """Ex. 12-13: ``launch/teleoperation.launch`` launched with the simulated lab in place of the hardware."""
    return score(grade_teleoperation_launch(package))


def graph(package: PathLike) -> float:
    """Ex. 15: ``graph.yaml``, the student's flowchart, against the running pipeline."""
    return score(grade_graph(package))
