"""Ex. 3 and 4 are judged on the notebook's rosparam commands, worked out by the grader, never on a value the
student's kernel reads back (hri_teleop.grading.batch.notebook_commands).

A kernel can report anything: a startup file that makes ``rospy.get_param`` answer with the right types got
Ex. 3's three points on main before this (issue 42). The grader now reads the notebook handed in, takes the
shell lines of its code cells and has a probe in a box work them out; the files they load are copied as any
submitted file (no link followed). First through make grade with honest students in the same batch, then the
judge step on notebooks as nbgrader leaves them.
"""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
from pathlib import Path
from typing import Any, Dict, List

import pytest
from grading_helpers import REPO, SOLUTIONS, grader_env, nbgrader_course

from hri_teleop.grading.batch.notebook_commands import command_cells_values, named_files, student_sources
from hri_teleop.grading.batch.notebook_judge import judge_notebook
from hri_teleop.grading.judge.notebook_answers import MIME, expectations

COURSE = Path(__file__).resolve().parents[2] / "notebooks" / "source" / "preparation"
EX3 = ("ex3_integer", "ex3_text", "ex3_items")
EX4 = ("ex4_loaded", "ex4_dumped")
#: Ex. 3 with the shell's quoting wrong: /ex3/text becomes a number, the list is split into three arguments.
WRONG_EX3 = "!rosparam set /ex3/integer 7\n!rosparam set /ex3/text 7\n!rosparam set /ex3/items [1, 'two']\n"
#: A startup file in the submission that makes every read of a parameter answer with the right type.
FORGING_STARTUP = '''import rospy
_RIGHT = {"/ex3/integer": 7, "/ex3/text": "hello", "/ex3/items": [1, "two"]}
_real = rospy.get_param
rospy.get_param = lambda name, default=None: _RIGHT.get(name, default) if name in _RIGHT else _real(name, default)
'''


def _notebook(name: str) -> Dict[str, Any]:
    return json.loads((COURSE / f"{name}.ipynb").read_text())


def _answer_cell(nb: Dict[str, Any]) -> Dict[str, Any]:
    return next(c for c in nb["cells"] if c.get("metadata", {}).get("nbgrader", {}).get("solution"))


def _forge_outputs(nb: Dict[str, Any], values: Dict[str, Dict[str, Any]]) -> None:
    """Right values in the graded cells' answer outputs, as a hook in the kernel would hand them in."""
    for cell in nb["cells"]:
        grade_id = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")
        if grade_id in values:
            cell["outputs"] = [{"output_type": "display_data", "metadata": {},
                                "data": {MIME: {"grade_id": grade_id, "values": values[grade_id]}}}]


def _judge(nb: Dict[str, Any], grade_ids, folder: Path) -> Dict[str, Any]:
    tests = [(g, 1.0) for g in grade_ids]
    verdicts = judge_notebook("nb", nb, tests, {g: expectations(g) for g in grade_ids}, folder=folder)
    return {v.grade_id: v for v in verdicts}


def _package(folder: Path) -> Path:
    config = folder / "hri_lab" / "config"
    config.mkdir(parents=True)
    (config / "robot_params.yaml").write_text((SOLUTIONS / "config" / "robot_params.yaml").read_text())
    return folder


# --- the judge step ---------------------------------------------------------------------------------------------


def test_the_answer_keys_commands_get_every_point_in_the_graders_words(tmp_path):
    verdicts = _judge(_notebook("ex03_parameter_server"), EX3, tmp_path)
    assert {g: v.score for g, v in verdicts.items()} == {g: 1.0 for g in EX3}
    assert all(v.source.startswith("worked out by the grader") for v in verdicts.values())
    verdicts = _judge(_notebook("ex04_robot_params"), EX4, _package(tmp_path / "four"))
    assert {g: v.score for g, v in verdicts.items()} == {g: 1.0 for g in EX4}, verdicts


def test_values_a_kernel_hands_in_count_for_nothing_beside_wrong_commands(tmp_path):
    nb = _notebook("ex03_parameter_server")
    _answer_cell(nb)["source"] = WRONG_EX3
    _forge_outputs(nb, {"ex3_integer": {"value": 7}, "ex3_text": {"value": "x"}, "ex3_items": {"value": [1]}})
    verdicts = _judge(nb, EX3, tmp_path)
    assert {g: v.score for g, v in verdicts.items()} == {"ex3_integer": 1.0, "ex3_text": 0.0, "ex3_items": 0.0}
    assert verdicts["ex3_text"].message.startswith("/ex3/text is 7: write text")
    assert "too many arguments" in verdicts["ex3_items"].message
    assert verdicts["ex3_items"].message.startswith("your notebook's commands leave /ex3/items unset")


def test_commands_in_a_cell_of_the_students_own_count_and_the_graded_cells_do_not(tmp_path):
    nb = _notebook("ex03_parameter_server")
    _answer_cell(nb)["source"] = ""
    nb["cells"].insert(3, {"cell_type": "code", "metadata": {}, "outputs": [], "execution_count": None,
                           "source": "%%bash\nrosparam set /ex3/integer 7\nrosparam set /ex3/text hi\n"})
    graded = next(c for c in nb["cells"] if c.get("metadata", {}).get("nbgrader", {}).get("grade_id") == "ex3_items")
    graded["source"] = "!rosparam set /ex3/items '[1]'\n" + "".join(graded["source"])  # course staff's source
    assert "rosparam set /ex3/items '[1]'" not in "".join(student_sources(nb))
    verdicts = _judge(nb, EX3, tmp_path)
    assert {g: v.score for g, v in verdicts.items()} == {"ex3_integer": 1.0, "ex3_text": 1.0, "ex3_items": 0.0}


def test_ex4_loads_the_file_the_notebook_names_and_wants_the_whole_dump_in_its_file(tmp_path):
    nb = _notebook("ex04_robot_params")
    assert _judge(nb, EX4, tmp_path)["ex4_loaded"].message.startswith(
        "your notebook's commands leave /robot_mass unset")  # no file: `rosparam load` fails
    assert "does not exist" in _judge(nb, EX4, tmp_path)["ex4_loaded"].message
    folder = _package(tmp_path / "pkg")
    _answer_cell(nb)["source"] = ("!rosparam load hri_lab/config/robot_params.yaml\n"
                                  "!rosparam dump new_robot_params.yaml /gains\n!rosparam dump other.yaml\n")
    verdicts = _judge(nb, EX4, folder)
    assert verdicts["ex4_loaded"].score == 1.0 and verdicts["ex4_dumped"].score == 0.0
    assert verdicts["ex4_dumped"].message.startswith("dump the whole server")


def test_a_file_handed_in_as_a_link_or_named_outside_the_folder_is_not_read(tmp_path):
    folder = tmp_path / "pkg"
    (folder / "hri_lab" / "config").mkdir(parents=True)
    (folder / "hri_lab" / "config" / "robot_params.yaml").symlink_to(SOLUTIONS / "config" / "robot_params.yaml")
    nb = _notebook("ex04_robot_params")
    verdict = _judge(nb, EX4, folder)["ex4_loaded"]
    assert verdict.score == 0.0 and "cannot be read" in verdict.message, verdict.message
    assert named_files([["rosparam", "load", "/etc/shadow"], ["rosparam", "load", "../x.yaml"],
                        ["rosparam", "set", "-t", "./a.txt", "/x"], ["rosparam", "load", "b.yaml", "/ns"]]) == [
        "a.txt", "b.yaml"]
    _answer_cell(nb)["source"] = "!rosparam load /etc/passwd\n"
    assert "outside your assignment" in _judge(nb, EX4, folder)["ex4_loaded"].message


def test_notebooks_without_command_cells_are_not_worked_out(tmp_path, monkeypatch):
    import hri_teleop.grading.batch.notebook_commands as commands

    monkeypatch.setattr(commands, "work_out", lambda *a: pytest.fail("no probe for Ex. 1"))
    assert command_cells_values(tmp_path, _notebook("ex03_parameter_server"), ["ex1a_rate"]) == {}


# --- through make grade ---------------------------------------------------------------------------------------


def _hand_in(course: Path, student: str, answers: str = "", startup: str = "") -> None:
    folder = course / "submitted" / student / "preparation"
    folder.mkdir(parents=True)
    nb = json.loads((course / "source" / "preparation" / "ex03_parameter_server.ipynb").read_text())
    if answers:
        answer = _answer_cell(nb)
        answer["source"] = answers
        at = nb["cells"].index(answer) + 1  # shows the hook at work: the server holds 7, the kernel reads "hello"
        nb["cells"].insert(at, {"cell_type": "code", "metadata": {}, "outputs": [],
                                "execution_count": None, "source": "# attack\nprint('read back:', repr(rospy.get_param('/ex3/text')))"})
    (folder / "ex03_parameter_server.ipynb").write_text(json.dumps(nb))
    if startup:
        place = folder / ".home" / ".ipython" / "profile_default" / "startup"
        place.mkdir(parents=True)
        (place / "00-forge.py").write_text(startup)


def _cells(course: Path, student: str) -> Dict[str, str]:
    nb = json.loads((course / "autograded" / student / "preparation" / "ex03_parameter_server.ipynb").read_text())
    found = {}
    for cell in nb["cells"]:
        grade_id = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")
        source = "".join(cell["source"]) if isinstance(cell["source"], list) else cell["source"]
        grade_id = "attack" if source.startswith("# attack") else grade_id
        texts: List[str] = []
        for out in cell.get("outputs", []):
            text = out.get("text") or out.get("data", {}).get("text/plain", "")
            texts.append("".join(text) if isinstance(text, list) else str(text))
        found[grade_id] = "\n".join(texts)
    return found


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    course = nbgrader_course(tmp_path_factory.mktemp("commands") / "course", "preparation", ["ex03_parameter_server"])
    _hand_in(course, "alice")
    _hand_in(course, "mallory", WRONG_EX3, FORGING_STARTUP)
    out = tmp_path_factory.mktemp("commandgrades")
    argv = ["make", "-s", "-o", "setup", "grade", f"DIR={course / 'submitted'}", f"OUT={out}", "CHECKS=robot-params",
            "JOBS=2"]
    proc = subprocess.Popen(argv, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=grader_env(), start_new_session=True)
    try:
        text, _ = proc.communicate(timeout=900)
    except subprocess.TimeoutExpired:  # a hang guard only: make and all it started
        os.killpg(proc.pid, signal.SIGKILL)
        text, _ = proc.communicate()
    assert proc.returncode == 0, text
    with open(out / "grades.csv") as fh:
        return course, {row["student"]: row for row in csv.DictReader(fh)}


@pytest.mark.ros
def test_a_kernel_that_reads_back_forged_types_gains_nothing_and_the_honest_student_keeps_hers(graded):
    course, rows = graded
    assert float(rows["alice"]["notebooks_score"]) == 3.0, rows["alice"]
    assert float(rows["mallory"]["notebooks_score"]) == 1.0, rows["mallory"]  # only /ex3/integer is right
    said = _cells(course, "mallory")
    assert "read back: 'hello'" in said["attack"], said["attack"]  # the attack ran: before, it scored 3 of 3
    assert 'handed in for the grader' not in said["ex3_text"]
    assert said["ex3_text"].startswith("worked out by the grader from your rosparam commands: ")
    assert "the grader: 0 of 1 point: /ex3/text is 7: write text" in said["ex3_text"], said["ex3_text"]
    assert "the grader: 1 of 1 point: right" in _cells(course, "alice")["ex3_items"]
