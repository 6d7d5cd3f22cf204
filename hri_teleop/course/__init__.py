"""What the course's notebooks import: the facade of the Task 4 notebooks.

A notebook's setup cell starts the kernel's ROS master (``ensure_ros``); its cells start
nodes (``run_provided_node``, ``run_student_node``, ``rosrun_student``, ``launch_student``),
wait for them (``wait_for_publisher``), stop them (``stop_nodes``), show and load the
student's files (``show_file``, ``import_student_file``) and score them (``score``,
``grade_teleoperation_parts``, ``grade_teleoperation_node``); ``seconds`` shortens real-time
cells under tests and grading. The widgets are in :mod:`hri_teleop.course.widgets`, the
instructor's release tools in :mod:`hri_teleop.course.release` (``python -m hri_teleop.course``).
"""

from __future__ import annotations

from hri_teleop.course.cells import (
    grade_teleoperation_node,
    grade_teleoperation_parts,
    import_student_file,
    score,
    seconds,
    show_file,
)
from hri_teleop.course.errors import CourseError
from hri_teleop.course.nodes import (
    launch_student,
    rosrun_student,
    run_provided_node,
    run_student_node,
    stop_nodes,
    wait_for_publisher,
)
from hri_teleop.course.notebook_ros import ensure_ros

__all__ = [
    "CourseError", "ensure_ros", "score", "seconds", "show_file", "import_student_file",
    "grade_teleoperation_parts", "grade_teleoperation_node", "run_provided_node", "run_student_node",
    "rosrun_student", "launch_student", "wait_for_publisher", "stop_nodes",
]
