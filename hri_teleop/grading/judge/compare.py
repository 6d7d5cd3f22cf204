"""Judging what a student's code did: observations in, :class:`~hri_teleop.grading.results.Part` out.

Sessions and probes only observe; every rule of what is right lives here, ROS-free, next to the
reference rules it calls, so a message can be unit-tested without a master. Each part fails only
for what it judges (``not judged: ...`` otherwise). The one name the checks use: the judges live in
``compare_nodes`` (Ex. 5, 8, 9), ``compare_launch`` (Ex. 6-7, 12-13), ``compare_graph`` (Ex. 15) and ``compare_common``.
"""

from __future__ import annotations

from hri_teleop.grading.judge.compare_common import (
    GRAPH,
    MAPPING,
    SENSOR_LAUNCH,
    TELEOP,
    TELEOP_LAUNCH,
    TOLERANCE,
    explain_process,
    process_hints,
)
from hri_teleop.grading.judge.compare_graph import compare_graph
from hri_teleop.grading.judge.compare_launch import (
    board_rate_note,
    check_max_param,
    compare_sensor_launch,
    compare_teleop_launch,
    compare_teleop_launch_sim,
    nodes_by_script,
    teleop_node_name,
)
from hri_teleop.grading.judge.compare_nodes import (
    compare_mapping,
    compare_teleop_node,
    compare_teleop_parts,
)

__all__ = [
    "TOLERANCE", "MAPPING", "TELEOP", "SENSOR_LAUNCH", "TELEOP_LAUNCH", "GRAPH",
    "process_hints", "compare_mapping", "compare_teleop_parts", "compare_teleop_node",
    "compare_sensor_launch", "compare_teleop_launch", "compare_teleop_launch_sim", "compare_graph",
    "check_max_param", "board_rate_note", "nodes_by_script", "explain_process", "teleop_node_name",
]
