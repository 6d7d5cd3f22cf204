"""Judging what a student's code did: observations in, :class:`~hri_teleop.grading.results.Part` out.

Why ROS-free and separate from running things: the sessions and probes only observe (what
was subscribed, advertised, published, printed); every rule of what is right lives here
as plain functions over plain data, next to the reference rules they call
(:func:`hri_teleop.core.mapping.map_force` through the cases, TeleopController), so a message
can be unit-tested without a master and a notebook can show the same words.

Each part fails only for what it judges; when it cannot be judged because something it
depends on failed, it says so (``not judged: ...``). Messages name the topic, the type,
the value expected and what arrived, and end with the most likely fix.

This module is the one name the checks use; the judges live in ``compare_nodes`` (Ex. 5, 8,
9), ``compare_launch`` (Ex. 6-7, 12-13, 15) and what they share in ``compare_common``.
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
from hri_teleop.grading.judge.compare_launch import (
    check_max_param,
    compare_graph,
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
    "check_max_param", "nodes_by_script", "explain_process", "teleop_node_name",
]
