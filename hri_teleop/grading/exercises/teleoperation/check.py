"""Ex. 8-9's check: the student's Teleoperation class against pad-event traces, then the node with a scripted pad.

Ex. 8's notebook shows the class's parts, Ex. 9's the node's; both are one check of one file, whose
points count once, with the files.
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path
from typing import Any, List, Optional, Set, Union

import yaml

from hri_teleop.core.gamepad.events import pad_events
from hri_teleop.grading.exercise import Exercise
from hri_teleop.grading.exercises.teleoperation.cases import (
    hidden_teleop_node_case,
    hidden_teleop_parts_case,
    public_teleop_parts_case,
)
from hri_teleop.grading.exercises.teleoperation.judge_node import compare_teleop_node, real_time_note
from hri_teleop.grading.exercises.teleoperation.judge_parts import compare_teleop_parts
from hri_teleop.grading.exercises.teleoperation.parts import NODE_PARTS, PARTS
from hri_teleop.grading.exercises.teleoperation.session import TeleopNodePlan
from hri_teleop.grading.exercises.teleoperation.traces import PUBLIC_TRACES
from hri_teleop.grading.judge.harness import (
    TWIST_TOPIC,
    clock_notes,
    closing_scratch,
    finish_check,
    grading_clock,
    refuse_reference,
    require_ros,
    reusable,
    start_check,
)
from hri_teleop.grading.results import CheckResult, not_judged
from hri_teleop.grading.run.records import PartsPlanCase, PartsPlanTick, TeleopPartsPlan, TeleopPartsResult

__all__ = ["EXERCISE", "grade_teleoperation", "parts_result", "node_result"]

PathLike = Union[str, Path]


@reusable("teleoperation")
@closing_scratch
def grade_teleoperation(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                        node: bool = True) -> CheckResult:
    """Ex. 8-9: the student's parts against pad-event traces, then the node with the virtual pad."""
    require_ros()
    run, seed = start_check(EXERCISE, path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    refused = refuse_reference(run, EXERCISE, seed)
    if refused is not None:
        return refused
    cases = [public_teleop_parts_case(), hidden_teleop_parts_case(seed)]
    notes: List[str] = []
    plan_cases = []
    for case in cases:
        ticks, previous = [], None
        for tick in case.ticks:
            state = tick.state()
            ticks.append(PartsPlanTick(pad_events(previous, state), tick.force))
            previous = state
        plan_cases.append(PartsPlanCase(case.label, case.gains, ticks))
    plan_path = run.space.grader_dir / "teleop-parts.plan.json"
    plan_path.write_text(json.dumps(TeleopPartsPlan(plan_cases).to_json()), encoding="utf-8")
    if run.uid is not None:
        os.chown(plan_path, run.uid, run.uid)
    data, facts = run.probe("teleop-parts", run.space.file(EXERCISE.key), "teleop-parts", TeleopPartsResult,
                            plan_path)
    parts = compare_teleop_parts(data or TeleopPartsResult(), cases, run.out_dir, facts)
    if not node:
        parts += [not_judged(*PARTS[k], "the node was not run (node=False)") for k in NODE_PARTS]
    elif data is None or not data.ok:
        parts += [not_judged(*PARTS[k], "the file could not be imported (see above)") for k in NODE_PARTS]
    else:
        node_case = hidden_teleop_node_case(seed)
        script_path = run.space.grader_dir / "pad_script.yaml"
        script_path.write_text(yaml.safe_dump([dict(step) for step in node_case.script]), encoding="utf-8")
        if run.uid is not None:
            os.chown(script_path, run.uid, run.uid)
        plan = TeleopNodePlan(script=str(run.space.file(EXERCISE.key)), pad_script=str(script_path),
                              gains=node_case.gains, force=node_case.force, start_timeout_s=10.0,
                              run_s=node_case.quit_s + 4.0, quit_grace_s=5.0, record=[TWIST_TOPIC, "/gripper_width"],
                              clock=grading_clock())
        observation = run.session(plan, timeout_s=90.0)
        parts += compare_teleop_node(observation, node_case, TWIST_TOPIC, run.out_dir, str(run.space.package))
        notes += clock_notes(observation, note=real_time_note(observation, node_case, TWIST_TOPIC))
    return finish_check(EXERCISE, run, parts, notes, seed=seed)


def _node_part_names() -> Set[str]:
    return {PARTS[key][0] for key in NODE_PARTS}


def parts_result(package: PathLike, **kwargs: Any) -> CheckResult:
    """Ex. 8: the teleoperation check's parts of the class (gripper, sticks, toggle, rumble), no ROS node."""
    result = grade_teleoperation(package, node=False, **kwargs)
    node = _node_part_names()
    return dataclasses.replace(result, parts=[p for p in result.parts if p.name not in node])


def node_result(package: PathLike, **kwargs: Any) -> CheckResult:
    """Ex. 9: the teleoperation check's parts of the ROS node (topics, types, values with the virtual pad)."""
    result = grade_teleoperation(package, **kwargs)
    node = _node_part_names()
    failed_ex8 = [p.name for p in result.parts if p.name not in node and not p.passed]
    notes = tuple(result.notes) + ((f"Ex. 8 parts still failing (see notebook 08): {'; '.join(failed_ex8)}",)
                                   if failed_ex8 else ())
    return dataclasses.replace(result, parts=[p for p in result.parts if p.name in node], notes=notes)


EXERCISE = Exercise(key="teleoperation", handout="Ex. 8-9", assignment="lab", parts=PARTS, grade=grade_teleoperation,
                    hidden_inputs=True, hidden_parts=("node_twist", "node_width", "node_rumble", "node_quit"),
                    session_s=20.0,
                    notebook_calls={"teleoperation_parts": parts_result, "teleoperation_node": node_result},
                    whole_check_calls=("teleoperation_node",), public_traces=PUBLIC_TRACES)
