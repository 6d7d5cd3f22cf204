"""Ex. 5's check: the student's node for real on a private master: topics, type, every value, the range from the parameter."""

from __future__ import annotations

from pathlib import Path
from typing import Optional, Union

from hri_teleop.grading.exercise import Exercise
from hri_teleop.grading.exercises.mapping_node.cases import hidden_mapping_cases, public_mapping_case
from hri_teleop.grading.exercises.mapping_node.judge import PARTS, compare_mapping
from hri_teleop.grading.exercises.mapping_node.session import MappingCasePlan, MappingNodePlan
from hri_teleop.grading.exercises.mapping_node.traces import PUBLIC_TRACES
from hri_teleop.grading.judge.harness import (
    closing_scratch,
    finish_check,
    left_as_template,
    refuse_reference,
    require_ros,
    reusable,
    start_check,
)
from hri_teleop.grading.results import CheckResult

__all__ = ["EXERCISE", "grade_mapping_node"]

PathLike = Union[str, Path]


@reusable("mapping-node")
@closing_scratch
def grade_mapping_node(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None,
                       reference_allowed: bool = False) -> CheckResult:
    """Ex. 5: the node for real on a private master: topics, type, every value, the range from the parameter.

    ``reference_allowed``: judge a file that uses the lab's reference rule too (the lab's own
    node, when the grader's agreement with it is tested); students' files never are.
    """
    require_ros()
    run, seed = start_check(EXERCISE, path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    run.space.guarded = not reference_allowed  # the lab's own node imports the rule it is the reference of
    refused = None if reference_allowed else refuse_reference(run, EXERCISE, seed)
    if refused is not None:
        return refused
    cases = [public_mapping_case()] + hidden_mapping_cases(seed)
    plan = MappingNodePlan(script=str(run.space.file(EXERCISE.key)),
                           cases=[MappingCasePlan(c.label, c.max_sensor_force, list(c.counts)) for c in cases],
                           start_timeout_s=10.0, response_timeout_s=1.5)
    observation = run.session(plan, timeout_s=120.0)
    parts = compare_mapping(observation, cases, run.out_dir, str(run.space.package),
                            left_as_template(run, EXERCISE.key))
    return finish_check(EXERCISE, run, parts, seed=seed)


EXERCISE = Exercise(key="mapping_node", handout="Ex. 5", assignment="preparation", parts=PARTS,
                    grade=grade_mapping_node, hidden_inputs=True, hidden_parts=("hidden",), session_s=12.0,
                    notebook_calls={"mapping_node": grade_mapping_node}, whole_check_calls=("mapping_node",),
                    public_traces=PUBLIC_TRACES)
