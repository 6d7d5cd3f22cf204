"""Ex. 10: the grader drives the student's teleoperation node on the simulated arm itself and measures the hand.

The notebook's cell reads the hand's height in the student's kernel, where a hook could report any number. The
grader does not take that number: it starts the student's ``teleoperation.py`` (from the submission, boxed,
on the grader's clock) beside its own ``lab_sim``, plays the notebook's drive on the scripted pad and reads the
hand's height from what ``lab_sim`` publishes (``teleop-launch-sim`` session, one node in the launch).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, List, Sequence, Tuple

import yaml

from hri_teleop.grading.exercises.registry import by_file
from hri_teleop.grading.judge.harness import TWIST_TOPIC, grading_clock, require_ros, start_check
from hri_teleop.grading.judge.lab_sim import lab_rate_hz, lab_sim_argv, scripted_pad_launch
from hri_teleop.grading.results import CheckResult
from hri_teleop.grading.run.records import TeleopLaunchSimObservation, TeleopLaunchSimPlan

__all__ = ["EX10_DRIVE", "POSE_TOPIC", "ex10_plan_files", "ex10_values"]

#: The notebook's drive (ex10_teleoperate_robot.ipynb, its start cell): down at half speed for 1 s. Without its
#: last step, the quit: the grader's run goes on until the arm has come to rest (:data:`_RUN_S`), as the hand has
#: when the notebook reads its height; quitting is Ex. 9's rule, judged in the teleoperation check.
EX10_DRIVE: Tuple[Dict[str, Any], ...] = (
    {"t": 0.5, "axis": "right_y", "value": -0.5},
    {"t": 1.5, "axis": "right_y", "value": 0.0},
)
#: Where the simulated arm says where its hand is ([x, y, z] in the recorder's words).
POSE_TOPIC = "/lab_sim/ee_pose"
_NODE = "/teleoperation"
#: The file Ex. 10 drives: the node the student wrote in Ex. 9.
NODE_FILE = "scripts/teleoperation.py"
_RUN_S = 4.0  # s on the grader's clock: the stick is let go at 1.5 s, the arm at rest well before 4 s


def ex10_plan_files(grader_dir: Path, uid: Any) -> Tuple[Path, Path, Path]:
    """(the scenario, the launch that starts only the student's node, the pad's parameters) in ``grader_dir``."""
    scenario = grader_dir / "ex10.scenario.yaml"
    scenario.write_text(yaml.safe_dump({"description": "hri-grade: Ex. 10, the notebook's drive",
                                        "world": {"object": "none"}, "steps": [dict(s) for s in EX10_DRIVE]},
                                       sort_keys=False), encoding="utf-8")
    launch = grader_dir / "ex10.launch"
    launch.write_text('<launch>\n  <node pkg="hri_lab" type="teleoperation.py" name="teleoperation" output="screen"/>\n'
                      "</launch>\n", encoding="utf-8")
    params = grader_dir / "ex10.params.launch"
    params.write_text(scripted_pad_launch(_NODE, scenario), encoding="utf-8")
    for path in (scenario, launch, params):
        if uid is not None:
            os.chown(path, uid, uid)
    return scenario, launch, params


def _heights(observation: TeleopLaunchSimObservation) -> List[float]:
    found = []
    for message in observation.messages.get(POSE_TOPIC, []):
        value = message.value
        if isinstance(value, list) and len(value) == 3 and all(isinstance(v, (int, float)) for v in value):
            found.append(float(value[2]))
    return found


def _first_line(text: str) -> str:
    lines = [line for line in str(text).strip().splitlines() if line.strip()]
    line = lines[-1] if lines else "no output"
    return line if len(line) <= 200 else line[:197] + "..."


def ex10_values(folder: Path, timeout_s: float = 90.0) -> Dict[str, Any]:
    """The values the rule of ``ex10_drives`` judges (``z_start_m``, ``z_m``), measured by the grader with the
    submission's teleoperation.py in ``folder``; ``{"not_judged": why}`` when it could not measure them."""
    require_ros()
    run, _seed = start_check(by_file(NODE_FILE), folder, None, None)
    if isinstance(run, CheckResult):
        return {"not_judged": "the grader found no teleoperation.py in your hri_lab/scripts to drive (Ex. 9)"}
    try:
        scenario, launch, params = ex10_plan_files(run.space.grader_dir, run.uid)
        plan = TeleopLaunchSimPlan(
            launch_file=str(launch), params_launch=str(params), teleop_node=_NODE, twist_topic=TWIST_TOPIC,
            supply={}, set_max_sensor_force=None,
            lab_sim=lab_sim_argv(scenario),
            record=[POSE_TOPIC], start_timeout_s=20.0, run_s=_RUN_S, clock=grading_clock(), settle_timeout_s=10.0,
            applied_topic="/lab_sim/command_time_s", sensor_chain=[], expect_nodes=[_NODE],
            default_rate_hz=lab_rate_hz())
        observation = run.session(plan, timeout_s=timeout_s)
    finally:
        run.close()
    if observation.session_error:
        return {"not_judged": f"the grader's run of your teleoperation.py failed ({_first_line(observation.session_error)})"}
    if observation.problem:
        return {"not_judged": f"your teleoperation.py did not run: {_first_line(observation.problem)}"}
    others: Sequence[str] = [n for n in observation.publishers.get(POSE_TOPIC, []) if n != "/lab_sim"]
    if others:
        return {"not_judged": f"{', '.join(others)} published on {POSE_TOPIC}, which only the simulated arm may"}
    heights = _heights(observation)
    if not heights:
        return {"not_judged": "the simulated arm reported no hand position while your node ran"}
    return {"z_start_m": heights[0], "z_m": heights[-1]}
