"""Every course notebook run on the lab twin as on the lab PC, with nothing set: nothing scripted or
simulated reaches the robot or the board; with a person's pad stood in, the lab path works.

The twin (hri_teleop.ros.lab_twin) is a master this test process started and the notebooks' kernels
did not: to them it is the lab PC's. Each notebook runs top to bottom in its own kernel
(twin_notebook_runner.py) with the twin's environment -- no HRI_MODE, no marker of a private master.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Dict, List

import pytest
import yaml

from hri_teleop.course.release import prepare_course_copy, source_notebooks
from hri_teleop.ros.lab_twin import LabTwin

pytestmark = pytest.mark.ros

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
RUNNER = HERE / "twin_notebook_runner.py"
STANDIN = HERE / "pad_standin"
#: What each notebook must refuse on the lab's master (a line of its output starts with it).
REFUSED = {
    "ex02_fsr_sensor_node": ["refused to start FSR_sensor.py"],
    "ex05_mapping_node": ["refused to start FSR_sensor.py"],
    "ex06_07_sensor_launch": ["refused to start sensor.launch, whose node /FSR_sensor runs FSR_sensor.py"],
    "ex10_teleoperate_robot": ["refused to start the simulated Franka (lab_sim.py)"],
    "ex11_calibration": ["refused to start the simulated board (FSR_sensor.py)"],
    "ex15_computation_graph": ["refused to start the pipeline without hardware"],
}
#: A person at the lab's pad: right stick down at half speed for 1.5 s (the hand goes about 7 cm down), square.
PERSON = [{"t": 1.0, "axis": "right_y", "value": -0.5}, {"t": 2.5, "axis": "right_y", "value": 0.0},
          {"t": 3.0, "tap": "west", "hold": 0.1}]


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    return prepare_course_copy(tmp_path_factory.mktemp("twin-course"), release=False)


@pytest.fixture(scope="module")
def twin(module_lab_twin):
    return module_lab_twin


def _run(notebook: Path, env: Dict[str, str], out: Path) -> dict:
    proc = subprocess.run([sys.executable, str(RUNNER), str(notebook), str(out)], env=env, capture_output=True,
                          text=True, timeout=1200)
    assert proc.returncode == 0, f"{notebook.name}: {proc.stderr[-3000:]}"
    return json.loads(out.read_text(encoding="utf-8"))


def _kernel_env(twin: LabTwin, **more: str) -> Dict[str, str]:
    env = dict(twin.env, HRI_NOTEBOOK_FAST="1", **more)
    env.pop("NBGRADER_EXECUTION", None)
    return env


@pytest.fixture(scope="module")
def headless(course, twin, tmp_path_factory):
    """Every source notebook on the twin, nobody at the pad: the preparation, Ex. 8-11 and Ex. 12-15 side by
    side (their nodes' names do not meet), each in order. Returns ({name: result}, the twin's report)."""
    out = tmp_path_factory.mktemp("headless")
    lanes: Dict[str, List[Path]] = {}
    for notebook in source_notebooks(course):  # the lab's second half starts no node of the first's
        lane = notebook.parent.name
        if lane == "lab" and notebook.stem >= "ex12":
            lane = "lab-launch"
        lanes.setdefault(lane, []).append(notebook)

    def lane(notebooks: List[Path]) -> Dict[str, dict]:
        return {nb.stem: _run(nb, _kernel_env(twin), out / f"{nb.stem}.json") for nb in notebooks}

    results: Dict[str, dict] = {}
    with ThreadPoolExecutor(max_workers=len(lanes)) as pool:
        for done in pool.map(lane, lanes.values()):
            results.update(done)
    return results, twin.report()


def _lines(result: dict) -> List[str]:
    return [line for cell in result["cells"] for line in cell["stdout"].splitlines()]


def test_every_course_notebook_ran_on_the_twin(headless):
    results, _report = headless
    assert sorted(results) == sorted(nb.stem for nb in source_notebooks())


def test_run_on_the_lab_pcs_master_with_nothing_set_no_notebook_moves_the_robot_or_fakes_the_board(headless):
    _results, report = headless
    assert report.nonzero_twists == 0, report.lines()
    assert sum(report.gripper_goals.values()) == 0, report.lines()
    assert report.pub_force_publishers == ["/serial_node"], report.lines()
    assert report.replaced == [] and report.stopped == [], report.lines()
    assert report.arm_moved_m < 1e-6, report.lines()


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_each_simulated_start_is_refused_in_one_line_naming_what_why_and_the_fix(headless, name):
    results, _report = headless
    lines = _lines(results[name])
    for start in REFUSED[name]:
        refusal = [line for line in lines if line.startswith(start)]
        assert refusal, f"{name}: no line starts with {start!r}: {lines}"
        assert "this master runs real hardware (/franka_control, /franka_gripper, /serial_node)" in refusal[0]
        assert refusal[0].endswith("the notebook starts its own)") or 'set PAD = "pygame"' in refusal[0]


def test_no_refusal_is_a_traceback_and_the_notebooks_went_on_to_their_last_cell(headless):
    results, _report = headless
    for name, result in results.items():
        for cell in result["cells"]:
            assert "Traceback" not in cell["stderr"] + cell["error"], (name, cell)
        assert result["cells"][-1]["number"] >= 1


def test_with_a_person_at_the_labs_pad_the_students_node_drives_the_real_robot(course, twin, headless, tmp_path):
    """Ex. 9 and Ex. 10 as written, in the lab: the node reads the lab's pad (pygame; here its stand-in),
    the arm goes down, Ex. 10's check reads the real robot's joint states and gives its points."""
    before = twin.report()
    script = tmp_path / "person.yaml"
    script.write_text(yaml.safe_dump({"steps": PERSON}))
    path = os.environ.get("PYTHONPATH", "")
    env = _kernel_env(twin, PYTHONPATH=f"{STANDIN}:{REPO}" + (f":{path}" if path else ""),
                      HRI_PAD_STANDIN_SCRIPT=str(script), HRI_PAD_STANDIN_LOG=str(tmp_path / "pad.log"))
    lab = course / "source" / "lab"
    ex10 = _run(lab / "ex10_teleoperate_robot.ipynb", env, tmp_path / "ex10.json")
    after = twin.report()
    assert after.nonzero_twists > before.nonzero_twists, after.lines()
    assert ex10["grades"]["ex10_drives"][0] == ex10["grades"]["ex10_drives"][1], ex10["cells"]
    assert not [line for line in _lines(ex10) if line.startswith("refused to start teleoperation")]
    ex09 = _run(lab / "ex09_teleoperation_node.ipynb", env, tmp_path / "ex09.json")
    assert twin.report().nonzero_twists > after.nonzero_twists, twin.report().lines()
    assert ex09["checks"]["ex9_node"][0] == ex09["checks"]["ex9_node"][1] > 0, ex09["cells"]
    assert twin.report().replaced == [] and twin.report().pub_force_publishers == ["/serial_node"]


#: Ex. 14's person: tries the sticks while the robot is not activated, waits for the rumble of a full
#: press of the piston, then drives the (by then activated) robot down and quits.
EX14_PERSON = [{"t": 1.0, "axis": "right_y", "value": -0.5}, {"t": 2.0, "axis": "right_y", "value": 0.0},
               {"t": 2.5, "axis": "right_y", "value": -0.5, "when": "rumble", "above": 0.5, "max_wait": 300},
               {"t": 4.0, "axis": "right_y", "value": 0.0}, {"t": 4.5, "tap": "west", "hold": 0.1}]


#: The lab PC's nodes a student's teleoperation.launch starts from the installed packages.
LAUNCHED = {"/franka_control", "/franka_gripper", "/serial_node"}


def test_ex14_in_the_lab_the_students_launch_file_runs_first_without_then_with_the_robot(course, tmp_path):
    """Ex. 14 as the handout has it, from the notebook: the student's own teleoperation.launch on the lab PC
    (a bare twin: nothing launched yet, the robot not activated), the pad tried in vain, the piston pressed
    and felt, the robot activated, the egg's place reached; no scripted node, the student's launch only."""
    twin = LabTwin(tmp_path / "twin", nodes_running=False, activated=False)
    twin.start()
    done = threading.Event()
    during = []

    def launched() -> bool:  # the whole launch is up (its nodes register in any order) and the sticks were tried
        report = twin.report()
        return report.ignored_twists > 0 and LAUNCHED <= set(report.launched)

    def person() -> None:  # at the robot and the piston: each act waits for the one before
        while not done.is_set() and not launched():
            time.sleep(0.2)
        if not done.is_set():
            during.append(twin.report())  # the student's launch is up
            twin.set_activated(True)
            twin.press(700, 3.0)

    helper = threading.Thread(target=person, daemon=True)
    try:
        script = tmp_path / "person.yaml"
        script.write_text(yaml.safe_dump({"steps": EX14_PERSON}))
        path = os.environ.get("PYTHONPATH", "")
        env = _kernel_env(twin, PYTHONPATH=f"{STANDIN}:{REPO}" + (f":{path}" if path else ""),
                          HRI_PAD_STANDIN_SCRIPT=str(script), HRI_PAD_STANDIN_LOG=str(tmp_path / "pad.log"))
        helper.start()
        result = _run(course / "source" / "lab" / "ex14_force_feedback.ipynb", env, tmp_path / "ex14.json")
        report = twin.report()
    finally:
        done.set()
        helper.join(30)
        twin.stop()
    lab_cells = {c["grade_id"]: c for c in result["cells"] if c["grade_id"].startswith("lab_")}
    assert all(not c["error"] for c in lab_cells.values()), lab_cells
    assert "your node quit: True" in lab_cells["lab_wait"]["stdout"], lab_cells
    # Started by the student's launch from the lab PC's installed packages (stopped again by lab.stop()).
    assert during and LAUNCHED <= set(during[0].launched), json.dumps(
        [report.lines(), lab_cells], indent=1)
    assert report.ignored_twists > 0, report.lines()  # the sticks while the robot was not activated
    assert report.board_presses >= 1 and report.arm_moved_m > 0.03, report.lines()
    assert during[0].pub_force_publishers == ["/serial_node"], during[0].lines()

