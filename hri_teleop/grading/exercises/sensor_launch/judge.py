"""Judging ``sensor.launch`` (Ex. 6-7): what roslaunch's loader makes of it, then what flowed when it ran."""

from __future__ import annotations

import dataclasses
from typing import Dict, List, Optional, Tuple

from hri_teleop.grading.cases.handout import TABLE_1
from hri_teleop.grading.exercises.sensor_launch.session import SensorLaunchObservation
from hri_teleop.grading.judge.compare_common import (
    STUDENT_PACKAGES,
    as_float,
    explain_process,
    fmt_value,
    judged_part,
    not_judged_part,
)
from hri_teleop.grading.judge.compare_launch import check_max_param, parse_parts, script_problem, supplied_note
from hri_teleop.grading.results import Part
from hri_teleop.grading.run.records import LaunchParseResult, ProcessFacts

__all__ = ["PARTS", "compare_sensor_launch"]

#: Part key -> (name as students read it, points; tests refer to the keys).
PARTS: Dict[str, Tuple[str, float]] = {
    "parse": ("parses with roslaunch", 1),
    "nodes": ("starts FSR_sensor.py and mapping_node.py", 3),
    "param": ("sets /max_sensor_force (a count, 0 < value <= 1023)", 2),
    "yaml": ("Ex. 7 (voluntary): loads config/robot_params.yaml", 0),
    "flow": ("launched: /force_mapped flows as std_msgs/Float32 and stays in [0, 1]", 4),
}


def compare_sensor_launch(parsed: LaunchParseResult, observation: Optional[SensorLaunchObservation],
                          parse_facts: Optional[ProcessFacts] = None) -> List[Part]:
    """sensor.launch: what roslaunch's loader makes of it, then what flowed when it ran."""
    T = PARTS
    parts, final = parse_parts(T, parsed, parse_facts, ("nodes", "param", "yaml", "flow"), "Ex. 6")
    if final:
        return parts
    missing = [m for m in (script_problem(parsed, s, STUDENT_PACKAGES, "at home and in the lab", "Ex. 6")
                           for s in ("FSR_sensor.py", "mapping_node.py")) if m]
    parts.append(judged_part(T, "nodes", not missing, "\n".join(missing)))
    ok, message = check_max_param(parsed.params)
    parts.append(judged_part(T, "param", ok, message))
    keys = [k for k in TABLE_1 if f"/{k}" in parsed.params or any(p.startswith(f"/{k}/") for p in parsed.params)]
    parts.append(judged_part(T, "yaml", True, note=("Ex. 7 done: robot_params.yaml is loaded" if keys else
                                              "Ex. 7 (voluntary) not done: robot_params.yaml is not loaded")))
    if observation is None or observation.session_error:
        reason = observation.session_error if observation is not None else "it was not launched"
        parts.append(not_judged_part(T, "flow", f"the grader could not launch it ({reason})"))
        return parts
    values = observation.force_mapped
    kinds = {k for _, k, _ in values}
    numbers = [as_float(v) for _, _, v in values]
    problems = []
    note = supplied_note(observation, "the flow")
    if {"FSR_sensor.py", "mapping_node.py"} <= set(observation.supplied):
        parts.append(not_judged_part(T, "flow", "the file starts neither node (the nodes part): the grader started "
                                               "both, so nothing that flowed came from your launch file"))
        return parts
    if not values:
        launch = dataclasses.replace(observation.launch, problem=observation.problem)
        problems.append("nothing arrived on /force_mapped while the launch file ran: "
                        + explain_process(launch, "roslaunch"))
    else:
        if kinds != {"std_msgs/Float32"}:
            problems.append(f"/force_mapped is {', '.join(sorted(kinds))}, not std_msgs/Float32")
        outside = [v for v in numbers if v is None or not 0.0 <= v <= 1.0]
        if outside:
            problems.append(f"{len(outside)} of {len(values)} values on /force_mapped were outside [0, 1] "
                            f"(e.g. {fmt_value(outside[0])}): check mapping_node.py's range and clipping")
        if len(values) < 3:
            problems.append(f"only {len(values)} messages on /force_mapped in the recording: the sensor publishes "
                            "10 per second")
    parts.append(judged_part(T, "flow", not problems, "\n".join(problems), note=note))
    return parts
