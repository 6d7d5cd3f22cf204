"""Ex. 6-7's check: sensor.launch parsed with roslaunch's loader, then launched: /force_mapped flows and stays in [0, 1]."""

from __future__ import annotations

from pathlib import Path
from typing import Optional, Union

from hri_teleop.grading.cases.inputs import PUBLIC_MAX_SENSOR_FORCE
from hri_teleop.grading.exercise import Exercise
from hri_teleop.grading.exercises.sensor_launch.judge import PARTS, compare_sensor_launch
from hri_teleop.grading.exercises.sensor_launch.session import SensorLaunchObservation, SensorLaunchPlan
from hri_teleop.grading.judge.compare_common import STUDENT_PACKAGES
from hri_teleop.grading.judge.compare_launch import check_max_param
from hri_teleop.grading.judge.harness import (
    clock_notes,
    closing_scratch,
    finish_check,
    grading_clock,
    parse_launch,
    require_ros,
    reusable,
    start_check,
)
from hri_teleop.grading.results import CheckResult
from hri_teleop.sim.sensor_profile import FSR_SENSOR_RATE_HZ

__all__ = ["EXERCISE", "grade_sensor_launch"]

PathLike = Union[str, Path]


@reusable("sensor-launch")
@closing_scratch
def grade_sensor_launch(path: PathLike, *, seed: Optional[int] = None, out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 6-7: parsed with roslaunch's loader, then launched: /force_mapped flows and stays in [0, 1]."""
    require_ros()
    run, seed = start_check(EXERCISE, path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    parsed, facts = parse_launch(run, EXERCISE.key)
    observation: Optional[SensorLaunchObservation] = None
    if parsed.ok:
        scripts = {n.type for n in parsed.nodes if n.package in STUDENT_PACKAGES}  # another package's: supplied
        param_ok, _ = check_max_param(parsed.params)
        package = run.space.package
        run_mapping = "mapping_node.py" not in scripts and (package / "scripts" / "mapping_node.py").is_file()
        plan = SensorLaunchPlan(
            launch_file=str(run.space.file(EXERCISE.key)),
            set_max_sensor_force=None if param_ok else PUBLIC_MAX_SENSOR_FORCE,
            run_fsr_sensor="FSR_sensor.py" not in scripts, fsr_sensor=str(package / "scripts" / "FSR_sensor.py"),
            run_mapping_node=run_mapping, mapping_script=str(package / "scripts" / "mapping_node.py"),
            start_timeout_s=15.0, record_s=3.0, record_messages=10, clock=grading_clock(), settle_timeout_s=10.0,
            fsr_node=next((n.full_name for n in parsed.nodes if n.type == "FSR_sensor.py"), "/FSR_sensor"),
            default_fsr_rate_hz=FSR_SENSOR_RATE_HZ,
            mapping_node_name=next((n.full_name for n in parsed.nodes if n.type == "mapping_node.py"), "/mapping_node"),
            expect_nodes=sorted({n.full_name for n in parsed.nodes}
                                | ({"/FSR_sensor"} if "FSR_sensor.py" not in scripts else set())
                                | ({"/mapping_node"} if run_mapping else set())))
        observation = run.session(plan, timeout_s=90.0)
    parts = compare_sensor_launch(parsed, observation, facts)
    return finish_check(EXERCISE, run, parts, clock_notes(observation, "sensor.launch: "))


EXERCISE = Exercise(key="sensor_launch", handout="Ex. 6-7", assignment="preparation", parts=PARTS,
                    grade=grade_sensor_launch, lab_stand_ins=("scripts/mapping_node.py", "config/robot_params.yaml"),
                    session_s=8.0, notebook_calls={"sensor_launch": grade_sensor_launch},
                    whole_check_calls=("sensor_launch",))
