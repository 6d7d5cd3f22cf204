"""Ex. 12-13's check: the launch file's nodes, serial_node's port, /max_sensor_force and the controller's include.

Then it is launched in simulation (the simulated lab in place of robot and board).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Dict, List, Optional, Union

import yaml

from hri_teleop.grading.cases.inputs import PUBLIC_MAX_SENSOR_FORCE
from hri_teleop.grading.deliverables import key_of
from hri_teleop.grading.exercise import Exercise
from hri_teleop.grading.exercises.teleoperation_launch.cases import launch_sim_case
from hri_teleop.grading.exercises.teleoperation_launch.judge import (
    PARTS,
    compare_teleop_launch,
    compare_teleop_launch_sim,
    teleop_node_name,
)
from hri_teleop.grading.judge.compare_launch import check_max_param, nodes_by_script
from hri_teleop.grading.judge.harness import (
    TWIST_TOPIC,
    CheckRun,
    clock_notes,
    closing_scratch,
    finish_check,
    grading_clock,
    left_as_template,
    parse_launch,
    require_ros,
    reusable,
    start_check,
)
from hri_teleop.grading.judge.lab_sim import lab_rate_hz, lab_sim_argv, scripted_pad_launch
from hri_teleop.grading.results import CheckResult
from hri_teleop.grading.run.records import LaunchParseResult, TeleopLaunchSimObservation, TeleopLaunchSimPlan
from hri_teleop.grading.run.standins import BOARD_TOPIC
from hri_teleop.grading.run.workspace import find_package_root

__all__ = ["EXERCISE", "grade_teleoperation_launch"]

PathLike = Union[str, Path]
#: The lab's mapping node runs in place of the student's; a template left there is named (Ex. 12 d).
MAPPING_SCRIPT = "scripts/mapping_node.py"
TEMPLATE_NOTE = ("scripts/mapping_node.py is still the template as handed out (the lab's ran in its place here): "
                 "Ex. 12 d) asks for the mapping_node.py you wrote in the preparation in this package")


def _launch_sim_plan(run: CheckRun, parsed: LaunchParseResult) -> Optional[TeleopLaunchSimPlan]:
    """The ``teleop-launch-sim`` session for a parsed teleoperation.launch; None without a teleoperation node."""
    node = teleop_node_name(parsed)
    if node is None:
        return None
    scripts = nodes_by_script(parsed)
    case = launch_sim_case()
    grader_dir = run.space.grader_dir
    scenario = grader_dir / "launch-sim.scenario.yaml"
    scenario.write_text(yaml.safe_dump(case.scenario(), sort_keys=False), encoding="utf-8")
    params = grader_dir / "launch-sim.params.launch"
    params.write_text(scripted_pad_launch(node, scenario), encoding="utf-8")
    for path in (scenario, params):
        if run.uid is not None:
            os.chown(path, run.uid, run.uid)
    package = run.space.package
    supply: Dict[str, List[str]] = {}
    if not [n for n in scripts.get("serial_node.py", []) if n.package == "rosserial_python"]:
        supply["serial_node"] = [str(run.space.ws / "rosserial_python" / "scripts" / "serial_node.py"),
                                 "_port:=/dev/ttyACM0"]
    for script in ("mapping_node.py", "gripper_manager.py"):
        if not [n for n in scripts.get(script, []) if n.package == "hri_lab"] and (package / "scripts" / script).is_file():
            supply[script[:-3]] = [str(package / "scripts" / script)]
    param_ok, _ = check_max_param(parsed.params)
    return TeleopLaunchSimPlan(
        launch_file=str(run.space.file(EXERCISE.key)), params_launch=str(params), teleop_node=node,
        twist_topic=TWIST_TOPIC, supply=supply, set_max_sensor_force=None if param_ok else PUBLIC_MAX_SENSOR_FORCE,
        lab_sim=lab_sim_argv(scenario),
        record=[TWIST_TOPIC, "/force_mapped", "/pub_force", "/gripper_width", "/franka_gripper/joint_states",
                "/lab_sim/ee_pose", "/lab_sim/object", f"{node}/rumble"],
        start_timeout_s=20.0, run_s=case.quit_s + 12.0, clock=grading_clock(), settle_timeout_s=10.0,
        applied_topic="/lab_sim/command_time_s", sensor_chain=[BOARD_TOPIC, "/pub_force", "/force_mapped"],
        expect_nodes=sorted({n.full_name for n in parsed.nodes} | {f"/{name}" for name in supply}),
        default_rate_hz=lab_rate_hz())


@reusable("teleoperation-launch")
@closing_scratch
def grade_teleoperation_launch(path: PathLike, *, seed: Optional[int] = None,
                               out_dir: Optional[PathLike] = None) -> CheckResult:
    """Ex. 12-13: node set, serial_node with its port, /max_sensor_force, the controller include;
    then launched in simulation (the simulated lab in place of robot and board)."""
    require_ros()
    run, seed = start_check(EXERCISE, path, out_dir, seed)
    if isinstance(run, CheckResult):  # the file is missing
        return run
    parsed, facts = parse_launch(run, EXERCISE.key)
    parts = compare_teleop_launch(parsed, facts)
    plan = _launch_sim_plan(run, parsed) if parsed.ok else None
    observation: Optional[TeleopLaunchSimObservation] = run.session(plan, timeout_s=120.0) if plan is not None else None
    parts.append(compare_teleop_launch_sim(parsed, observation, launch_sim_case(), run.out_dir))
    notes = clock_notes(observation, "teleoperation.launch: ")
    if left_as_template(run, key_of(MAPPING_SCRIPT), find_package_root(path)):
        notes.append(TEMPLATE_NOTE)  # the lab's ran in its place: Ex. 12 d) would go unnoticed
    return finish_check(EXERCISE, run, parts, notes)


EXERCISE = Exercise(key="teleoperation_launch", handout="Ex. 12-13", assignment="lab", parts=PARTS,
                    grade=grade_teleoperation_launch,
                    lab_stand_ins=(MAPPING_SCRIPT, "scripts/teleoperation.py"), session_s=30.0,
                    notebook_calls={"teleoperation_launch": grade_teleoperation_launch},
                    whole_check_calls=("teleoperation_launch",))
