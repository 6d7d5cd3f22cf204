"""The kernel reports, the grader judges: no notebook point depends on the student's kernel deciding pass or fail.

The graded cells hand the student's values out as plain data (``hand_in``); after nbgrader's autograde the
grader reads each graded cell's last answer output and applies the cell's rule in its own process
(hri_teleop.grading.batch.notebook_judge, hri_teleop.grading.judge.notebook_answers).

The attacks are graded through the real make grade course path, in one batch with honest students, on the
preparation with Ex. 1 only (it runs no ROS): wrong answers with an AST transformer installed when
NBGRADER_EXECUTION is set that wraps every later cell in try/except (in a cell of the notebook, and in an
IPython startup file of the submission); wrong answers with a pre_run_cell hook that prints forged answer
outputs in other cells; the untouched release (no value handed in). Then every rule at its thresholds.
"""

from __future__ import annotations

import csv
import json
import math
import os
import shutil
import signal
import subprocess
from pathlib import Path
from typing import Any, Dict, List

import pytest
from grading_helpers import REPO, SOLUTIONS, grader_env, nbgrader_course

from hri_teleop.grading.batch.notebook_judge import handed_in, judge_cell, judge_notebook
from hri_teleop.grading.judge.notebook_answers import MIME, RULES, TOLERANCES, Verdict, apply_rule, expectations

ASSIGNMENT = "preparation"
NOTEBOOK = "ex01_fsr_and_arduino"
GRADED = ("ex1a_rate", "ex1a_voltage", "ex1a_count")
WRONG = "sketch_rate_hz = 1.0\na0_voltage_at_1n_v = 1.0\na0_count_at_1n = 1\n"
#: Wraps every later cell in try/except, only while nbgrader grades (the attack of issue 42).
SWALLOW = '''import ast, os
class _Swallow(ast.NodeTransformer):
    def visit_Module(self, node):
        handler = ast.ExceptHandler(type=ast.Name(id="BaseException", ctx=ast.Load()), name=None, body=[ast.Pass()])
        wrapped = ast.Try(body=node.body or [ast.Pass()], handlers=[handler], orelse=[], finalbody=[])
        return ast.fix_missing_locations(ast.Module(body=[wrapped], type_ignores=[]))
if os.environ.get("NBGRADER_EXECUTION"):
    get_ipython().ast_transformers.append(_Swallow())
'''
#: A later cell that raises: with the transformer live it ends without an error (proof the attack ran).
PROBE = "raise RuntimeError('the cells are not wrapped')"


def _forging_hook() -> str:
    """A pre_run_cell hook that prints the right answers, as answer outputs, in every cell but the graded ones."""
    from hri_teleop.core import fsr

    volts = float(fsr.resistance_to_voltage(6e3))
    forged = {"ex1a_rate": {"sketch_rate_hz": 1 / 0.3}, "ex1a_voltage": {"a0_voltage_at_1n_v": volts},
              "ex1a_count": {"a0_count_at_1n": int(fsr.voltage_to_count(volts))}}
    return f'''from IPython.display import publish_display_data
FORGED = {forged!r}
def _forge(info):
    if "hand_in(" in (info.raw_cell or ""):
        return
    for grade_id, values in FORGED.items():
        publish_display_data({{{MIME!r}: {{"grade_id": grade_id, "values": values}}, "text/plain": "forged"}})
get_ipython().events.register("pre_run_cell", _forge)
'''


@pytest.fixture(scope="module")
def course(tmp_path_factory) -> Path:
    return nbgrader_course(tmp_path_factory.mktemp("reportcourse") / "course", ASSIGNMENT, [NOTEBOOK])


def _package(folder: Path) -> None:
    from hri_teleop.grading.cases.templates import generate_answers

    generate_answers(SOLUTIONS, folder / "hri_lab")


def _hand_in(course: Path, student: str, answers: str = "", extra: str = "", probe: bool = False,
             release: bool = False, others: bool = False) -> Path:
    """A submission: the answer key's notebook (``release``: the student version, untouched) with its answers
    replaced by ``answers``, the cell ``extra`` after them and, with ``probe``, a cell that raises after that;
    ``others``: a plain cell after ``extra`` and one at the end."""
    import nbformat

    folder = course / "submitted" / student / ASSIGNMENT
    folder.mkdir(parents=True)
    _package(folder)
    source = course / ("release" if release else "source") / ASSIGNMENT / f"{NOTEBOOK}.ipynb"
    nb = nbformat.read(str(source), as_version=4)
    first = next(i for i, c in enumerate(nb.cells) if c.metadata.get("nbgrader", {}).get("solution"))
    if answers:
        nb.cells[first].source = answers
    added = [nbformat.v4.new_code_cell(f"# attack: extra\n{extra}")] if extra else []
    if probe:
        added.append(nbformat.v4.new_code_cell(f"# attack: probe\n{PROBE}"))
    if others:
        added.append(nbformat.v4.new_code_cell("# attack: other\nprint('another cell')"))
    last = [nbformat.v4.new_code_cell("# attack: last\nprint('the last cell')")] if others else []
    for cell in added + last:
        cell.pop("id", None)  # the course's notebooks are nbformat 4.4, without cell ids
    nb.cells[first + 1:first + 1] = added
    nb.cells.extend(last)
    nbformat.write(nb, str(folder / f"{NOTEBOOK}.ipynb"))
    return folder


def _make_grade(submitted: Path, out: Path, timeout_s: float = 900):
    argv = ["make", "-s", "-o", "setup", "grade", f"DIR={submitted}", f"OUT={out}", "CHECKS=robot-params", "JOBS=2"]
    proc = subprocess.Popen(argv, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=grader_env(), start_new_session=True)
    try:
        stdout, stderr = proc.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:  # a hang guard only: make and all it started
        os.killpg(proc.pid, signal.SIGKILL)
        stdout, stderr = proc.communicate()
    return proc.returncode, stdout + "\n" + stderr


def _cells(course: Path, student: str) -> Dict[str, Dict[str, Any]]:
    """grade id or attack name -> the autograded cell."""
    nb = json.loads((course / "autograded" / student / ASSIGNMENT / f"{NOTEBOOK}.ipynb").read_text())
    found = {}
    for cell in nb["cells"]:
        source = "".join(cell["source"]) if isinstance(cell["source"], list) else cell["source"]
        grade_id = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")
        if source.startswith("# attack: "):
            found[source.split("\n", 1)[0][len("# attack: "):]] = cell
        elif grade_id:
            found[grade_id] = cell
    return found


def _text(cell: Dict[str, Any]) -> str:
    parts = []
    for out in cell.get("outputs", []):
        if out["output_type"] == "stream":
            parts.append("".join(out["text"]) if isinstance(out["text"], list) else out["text"])
        elif out["output_type"] == "error":
            parts.append(f"{out['ename']}: {out['evalue']}")
        elif "text/plain" in out.get("data", {}):
            text = out["data"]["text/plain"]
            parts.append("".join(text) if isinstance(text, list) else text)
    return "\n".join(parts)


def _cell_scores(course: Path, student: str) -> Dict[str, float]:
    from nbgrader.api import Gradebook

    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gb:
        return {g.name: float(g.score) for g in gb.find_submission_notebook(NOTEBOOK, ASSIGNMENT, student).grades
                if g.name in GRADED}


@pytest.fixture(scope="module")
def graded(course, tmp_path_factory):
    """One make grade batch of every submission below: (course, grades.csv rows by student)."""
    for kind in ("submitted", "autograded", "feedback"):
        shutil.rmtree(course / kind, ignore_errors=True)
    _hand_in(course, "alice")                                         # (d) the answer key
    _hand_in(course, "mallory_ast", WRONG, SWALLOW, probe=True)       # (a) wrong answers, every cell wrapped
    startup = _hand_in(course, "mallory_startup", WRONG, probe=True)  # (b) the same from a startup file
    folder = startup / ".home" / ".ipython" / "profile_default" / "startup"
    folder.mkdir(parents=True)
    (folder / "00.py").write_text(SWALLOW.replace("get_ipython()", "__import__('IPython').get_ipython()"))
    _hand_in(course, "mallory_hook", WRONG, _forging_hook(), others=True)  # (c) forged answers in other cells
    _hand_in(course, "nobody", release=True)                          # nothing handed in
    out = tmp_path_factory.mktemp("reportgrades")
    code, text = _make_grade(course / "submitted", out)
    print(text)
    assert code == 0, text
    with open(out / "grades.csv") as fh:
        return course, {row["student"]: row for row in csv.DictReader(fh)}


def _gained_nothing(course: Path, rows: Dict[str, Dict[str, str]], student: str) -> None:
    """Every graded cell of ``student`` at 0, judged by the grader from the wrong values handed in, in its words."""
    assert rows[student]["status"] == "graded", rows[student]
    assert float(rows[student]["notebooks_score"]) == 0.0, rows[student]
    assert _cell_scores(course, student) == {g: 0.0 for g in GRADED}
    said = _text(_cells(course, student)["ex1a_rate"])
    assert said.startswith('handed in: {"sketch_rate_hz": 1.0}\nthe grader: 0 of 1 point: sketch_rate_hz is 1 Hz'), said
    feedback = (course / "feedback" / student / ASSIGNMENT / f"{NOTEBOOK}.html").read_text()
    assert "the grader: 0 of 1 point: sketch_rate_hz is 1 Hz" in feedback


@pytest.mark.ros
def test_a_an_ast_transformer_that_swallows_every_error_gains_nothing(graded):
    course, rows = graded
    assert "RuntimeError" not in _text(_cells(course, "mallory_ast")["probe"])  # the attack ran
    _gained_nothing(course, rows, "mallory_ast")


@pytest.mark.ros
def test_b_the_same_from_an_ipython_startup_file_in_the_submission_gains_nothing(graded):
    course, rows = graded
    assert "RuntimeError" not in _text(_cells(course, "mallory_startup")["probe"])  # the attack ran
    _gained_nothing(course, rows, "mallory_startup")


@pytest.mark.ros
def test_c_answers_a_hook_forges_in_other_cells_are_ignored(graded):
    course, rows = graded
    cells = _cells(course, "mallory_hook")
    assert "forged" in _text(cells["other"]) and "forged" in _text(cells["last"])  # the attack ran
    _gained_nothing(course, rows, "mallory_hook")


@pytest.mark.ros
def test_d_honest_students_in_the_same_batch_keep_every_point_in_the_graders_words(graded):
    course, rows = graded
    assert rows["alice"]["status"] == "graded" and float(rows["alice"]["notebooks_score"]) == 3.0, rows["alice"]
    assert _cell_scores(course, "alice") == {g: 1.0 for g in GRADED}
    for grade_id in GRADED:
        assert _text(_cells(course, "alice")[grade_id]).endswith("the grader: 1 of 1 point: right\n")


@pytest.mark.ros
def test_a_cell_that_handed_in_nothing_scores_zero_saying_why(graded):
    course, rows = graded
    assert float(rows["nobody"]["notebooks_score"]) == 0.0, rows["nobody"]
    said = _text(_cells(course, "nobody")["ex1a_rate"])
    assert said.startswith("the grader: 0 of 1 point: not judged: the cell handed in no value (it raised "
                           "NameError"), said


# --- the judge step on notebooks as nbgrader leaves them -------------------------------------------------------


def _answer(values: Any, grade_id: str = "ex1a_rate") -> Dict[str, Any]:
    return {"output_type": "display_data", "metadata": {},
            "data": {MIME: {"grade_id": grade_id, "values": values}, "text/plain": "handed in"}}


def _error(ename: str = "NameError", evalue: str = "name 'x' is not defined") -> Dict[str, Any]:
    return {"output_type": "error", "ename": ename, "evalue": evalue, "traceback": []}


def _graded(grade_id: str, outputs: List[Dict[str, Any]], count: Any = 1) -> Dict[str, Any]:
    return {"cell_type": "code", "execution_count": count, "source": f"hand_in({grade_id!r}, ...)", "outputs": outputs,
            "metadata": {"nbgrader": {"grade": True, "solution": False, "grade_id": grade_id, "points": 1}}}


RIGHT_RATE = {"sketch_rate_hz": 1 / 0.3}


def test_the_last_answer_of_the_cell_counts_whether_it_raised_or_not():
    forged_first = _graded("ex1a_rate", [_answer(RIGHT_RATE), _answer({"sketch_rate_hz": 1.0}), _error("WrongAnswer")])
    assert handed_in(forged_first) == ({"sketch_rate_hz": 1.0}, "")
    right_then_raised = _graded("ex1a_rate", [_answer(RIGHT_RATE), _error("WrongAnswer")])
    assert handed_in(right_then_raised) == (RIGHT_RATE, "")


def test_answers_printed_in_other_cells_are_ignored():
    other = {"cell_type": "code", "execution_count": 1, "source": "x = 1", "metadata": {},
             "outputs": [_answer(RIGHT_RATE)] * 3}
    graded = _graded("ex1a_rate", [_error()])
    nb = {"cells": [other, graded, dict(other)]}
    expected = {"ex1a_rate": expectations("ex1a_rate")}
    [verdict] = judge_notebook(NOTEBOOK, nb, [("ex1a_rate", 1.0)], expected)
    assert verdict.score == 0.0
    assert verdict.message == "not judged: the cell handed in no value (it raised NameError: name 'x' is not defined)"
    assert graded["outputs"] == [{"output_type": "stream", "name": "stdout", "text": "the grader: 0 of 1 point: "
                                  + verdict.message + "\n"}]
    assert nb["cells"][0]["outputs"] == [_answer(RIGHT_RATE)] * 3  # other cells stay as they ran


@pytest.mark.parametrize("cell, why", [
    (_graded("ex1a_rate", [], None), "not judged: the cell handed in no value (it did not run)"),
    (_graded("ex1a_rate", [{"output_type": "stream", "name": "stdout", "text": "hi"}]),
     "not judged: the cell handed in no value (it ran without calling hand_in)"),
    (_graded("ex1a_rate", [_answer("a string")]), "not judged: the cell's answer holds no named values"),
    (_graded("ex1a_rate", [_answer({"s": "x" * 70000})]), "not judged: the cell handed in 70046 bytes, more than 65536"),
])
def test_a_cell_without_an_answer_to_judge_scores_zero_saying_why(cell, why):
    verdict = judge_cell(NOTEBOOK, "ex1a_rate", 1.0, cell, expectations("ex1a_rate"))
    assert (verdict.score, verdict.message) == (0.0, why)


def test_a_cell_without_a_rule_or_missing_gets_no_point():
    assert judge_cell(NOTEBOOK, "mine", 2.0, _graded("mine", [_answer({})]), None).score == 0.0
    assert judge_cell(NOTEBOOK, "ex1a_rate", 1.0, None, expectations("ex1a_rate")).message.startswith("not judged")
    assert [v.message for v in judge_notebook(NOTEBOOK, None, [("ex1a_rate", 1.0)], {})] == [
        "not judged: the notebook was not handed in"]


# --- every rule at its thresholds --------------------------------------------------------------------------


def _rule(grade_id: str, **values: Any) -> Verdict:
    return apply_rule(grade_id, values, expectations(grade_id))


def _edges(grade_id: str, name: str) -> List[float]:
    """Values just inside and just outside the tolerance on each side of the expected value."""
    expected = float(expectations(grade_id)[name])
    rtol, atol = TOLERANCES[grade_id]
    band = atol + rtol * abs(expected)
    return [expected - 0.99 * band, expected + 0.99 * band, expected - 1.01 * band, expected + 1.01 * band]


@pytest.mark.parametrize("grade_id, name", [("ex1a_rate", "sketch_rate_hz"), ("ex1a_voltage", "a0_voltage_at_1n_v"),
                                            ("ex1a_count", "a0_count_at_1n"), ("ex2_rate", "pub_force_rate_hz")])
def test_a_number_passes_inside_its_tolerance_on_each_side_and_fails_outside(grade_id, name):
    inside_low, inside_high, outside_low, outside_high = _edges(grade_id, name)
    assert _rule(grade_id, **{name: inside_low}).passed and _rule(grade_id, **{name: inside_high}).passed
    for value in (outside_low, outside_high):
        verdict = _rule(grade_id, **{name: value})
        assert not verdict.passed and verdict.message.startswith(f"{name} is {value:g}"), verdict
    for bad in (True, "3.3", None, math.nan):
        assert not _rule(grade_id, **{name: bad}).passed
    assert _rule(grade_id).message.startswith(f"{name} was not handed in")


def test_the_rules_name_the_cause_and_never_the_answer():
    expected = expectations("ex1a_rate")["sketch_rate_hz"]
    assert f"{expected:.2f}" not in _rule("ex1a_rate", sketch_rate_hz=1.0).message
    assert "0.3" not in _rule("ex1a_rate", sketch_rate_hz=1.0).message
    assert "Int16" not in _rule("ex2_type", pub_force_type="std_msgs/Float32").message
    assert "rostopic type /pub_force" in _rule("ex2_type", pub_force_type="std_msgs/Float32").message
    assert "10" not in _rule("ex2_rate", pub_force_rate_hz=3.0).message.replace("3 Hz", "")
    assert "18" not in _rule("ex4_loaded", robot_mass=17.0).message
    full = expectations("ex11_value")["max_sensor_force"]
    assert str(full) not in _rule("ex11_value", max_sensor_force=100).message
    p_value = expectations("ex14_test")["p_value"]
    assert f"{p_value}" not in _rule("ex14_test", p_crush=0.5, significant=False).message
    rates = expectations("ex14_crush_rates")["crush_rate"]
    message = _rule("ex14_crush_rates", crush_rate={"feedback": 0.5, "no_feedback": 0.5}).message
    assert all(f"{rate:.2f}" not in message for rate in rates.values() if rate > 0)


def test_ex2_type_takes_what_rostopic_prints():
    assert _rule("ex2_type", pub_force_type="std_msgs/Int16").passed
    assert _rule("ex2_type", pub_force_type="std_msgs/Int16\n").passed
    assert not _rule("ex2_type", pub_force_type="Int16").passed and not _rule("ex2_type", pub_force_type=16).passed


@pytest.mark.parametrize("grade_id, right, wrong", [
    ("ex3_integer", [7, -1, 0], [7.0, True, "7", None, [7]]),
    ("ex3_text", ["hello", "7", ""], [7, None, ["a"], 7.5]),
    ("ex3_items", [[1, "two"], []], ["[1, 2]", None, {"a": 1}, 3]),
])
def test_ex3_judges_the_type_yaml_gave_the_value(grade_id, right, wrong):
    assert all(_rule(grade_id, value=v).passed for v in right)
    assert not any(_rule(grade_id, value=v).passed for v in wrong)


def test_ex4_judges_the_loaded_mass_and_the_whole_dump():
    assert _rule("ex4_loaded", robot_mass=18).passed and _rule("ex4_loaded", robot_mass=18.0).passed
    assert not _rule("ex4_loaded", robot_mass=18.000001).passed and not _rule("ex4_loaded", robot_mass="18").passed
    assert _rule("ex4_loaded", robot_mass=None).message.startswith("your notebook's commands leave /robot_mass unset")
    assert _rule("ex4_dumped", file=True, keys=["gains", "robot_name", "rosdistro", "run_id"]).passed
    assert not _rule("ex4_dumped", file=True, keys=["robot_name"]).passed
    assert not _rule("ex4_dumped", file=True, keys=None).passed
    assert _rule("ex4_dumped", file=False, keys=None).message.startswith(
        "your notebook's commands write no new_robot_params.yaml")
    noted = _rule("ex4_dumped", file=False, keys=None, notes=["`rosparam dump` fails: x"]).message
    assert noted.endswith("(in your commands, `rosparam dump` fails: x)")


def test_ex10_wants_the_hand_3_cm_down():
    assert _rule("ex10_drives", z_start_m=0.5, z_m=0.5 - 0.0301).passed
    assert not _rule("ex10_drives", z_start_m=0.5, z_m=0.5 - 0.0299).passed
    assert not _rule("ex10_drives", z_start_m=0.5, z_m=0.6).passed
    assert not _rule("ex10_drives", z_start_m="0.5", z_m=0.4).passed


def test_ex11_wants_an_int_within_8_counts_of_full_travel():
    full = int(expectations("ex11_value")["max_sensor_force"])
    for value in (full - 8, full, full + 8):
        assert _rule("ex11_value", max_sensor_force=value).passed, value
    for value in (full - 9, full + 9, float(full), True):
        assert not _rule("ex11_value", max_sensor_force=value).passed, value
    assert "an int" in _rule("ex11_value", max_sensor_force=float(full)).message


def _scenario_steps(name: str) -> List[Dict[str, Any]]:
    import yaml

    from hri_teleop.core.paths import SCENARIOS

    data = yaml.safe_load((SCENARIOS / f"{name}.yaml").read_text())
    return list(data["steps"] if isinstance(data, dict) else data)


def test_ex14_the_grader_runs_the_operator_and_judges_the_egg_itself():
    assert _rule("ex14_lifts_egg", steps=_scenario_steps("default")).passed      # the careful operator
    crushed = _rule("ex14_lifts_egg", steps=_scenario_steps("squeeze"))         # holds cross past the rumble
    assert not crushed.passed and crushed.message.startswith("the egg was crushed"), crushed
    assert not _rule("ex14_lifts_egg", lifted=True, crushed=False, outcome="lifted").passed  # a report is no run
    broken = _rule("ex14_lifts_egg", steps=[{"t": -1, "press": "south"}])
    assert not broken.passed and broken.message.startswith("your operator could not run: my_steps: step 1"), broken
    assert not _rule("ex14_lifts_egg", steps="not a list").passed


def test_ex14_crush_rates_within_1e_9_of_the_seeded_study():
    rates = expectations("ex14_crush_rates")["crush_rate"]
    assert set(rates) == {"feedback", "no_feedback"}
    near = {c: r + 0.9e-9 for c, r in rates.items()}
    assert _rule("ex14_crush_rates", crush_rate=near).passed
    assert _rule("ex14_crush_rates", crush_rate={c: r - 0.9e-9 for c, r in rates.items()}).passed
    for condition in rates:
        off = dict(rates, **{condition: rates[condition] + 1.1e-9})
        assert not _rule("ex14_crush_rates", crush_rate=off).passed
    assert not _rule("ex14_crush_rates", crush_rate=dict(rates, extra=0.0)).passed
    assert not _rule("ex14_crush_rates", crush_rate=list(rates.values())).passed


def test_ex14_test_wants_the_p_value_and_its_verdict():
    p_value = expectations("ex14_test")["p_value"]
    significant = p_value < 0.05
    assert _rule("ex14_test", p_crush=p_value + 0.9e-12, significant=significant).passed
    assert _rule("ex14_test", p_crush=p_value - 0.9e-12, significant=significant).passed
    assert not _rule("ex14_test", p_crush=p_value + 1.1e-12, significant=significant).passed
    assert not _rule("ex14_test", p_crush=p_value - 1.1e-12, significant=significant).passed
    assert not _rule("ex14_test", p_crush=p_value, significant=not significant).passed
    assert not _rule("ex14_test", p_crush=p_value, significant=int(significant)).passed


def test_no_rule_raises_on_what_a_student_hands_in():
    oddities: List[Any] = [None, True, -1, 1e308, "x", [], [1, [2]], {"a": {"b": None}}]
    for grade_id in RULES:
        for value in oddities:
            names = ["value", "sketch_rate_hz", "crush_rate", "p_crush", "z_m", "keys", "steps", "max_sensor_force"]
            verdict = apply_rule(grade_id, {name: value for name in names}, expectations(grade_id))
            assert isinstance(verdict, Verdict) and verdict.message
        assert not apply_rule(grade_id, ["not", "a", "dict"], expectations(grade_id)).passed


# --- the course's graded cells and hand_in at home ------------------------------------------------------------


def _graded_cells():
    from hri_teleop.core.paths import NOTEBOOKS

    for path in sorted((NOTEBOOKS / "source").glob("*/*.ipynb")):
        for cell in json.loads(path.read_text(encoding="utf-8"))["cells"]:
            meta = cell.get("metadata", {}).get("nbgrader", {})
            if meta.get("grade") and not meta.get("solution") and cell["cell_type"] == "code":
                yield path.name, meta["grade_id"], "".join(cell["source"])


def test_every_graded_cell_hands_in_to_its_own_rule_and_decides_nothing():
    cells = list(_graded_cells())
    assert len(cells) == len(RULES) == 15
    for notebook, grade_id, source in cells:
        assert grade_id in RULES, (notebook, grade_id)
        assert f'hand_in("{grade_id}", ' in source, (notebook, grade_id)
        assert "assert" not in source and "BEGIN HIDDEN TESTS" not in source, (notebook, grade_id)


def test_hand_in_at_home_shows_the_graders_verdict(capsys):
    from hri_teleop.course import hand_in
    from hri_teleop.course.answers import WrongAnswer, plain
    from hri_teleop.course.errors import CourseError

    hand_in("ex1a_rate", sketch_rate_hz=1 / 0.3)
    assert capsys.readouterr().out == ("handed in for the grader: sketch_rate_hz = 3.33333\n"
                                       "the grader's rule says: right\n")
    with pytest.raises(WrongAnswer, match="^sketch_rate_hz is 1 Hz: "):
        hand_in("ex1a_rate", sketch_rate_hz=1.0)
    with pytest.raises(CourseError, match="no graded cell 'nope'"):
        hand_in("nope", x=1)
    with pytest.raises(CourseError, match="more than 65536"):
        hand_in("ex1a_rate", sketch_rate_hz=["x" * 1000] * 100)
    np = pytest.importorskip("numpy")
    assert plain({"a": np.float64(1.5), "b": np.int64(3), "c": np.array([1, 2]), "d": math.inf, "e": (1, None)}) == \
        {"a": 1.5, "b": 3, "c": [1, 2], "d": "inf", "e": [1, None]}


def test_make_grade_and_gradescope_refuse_a_course_whose_autograded_cell_has_no_rule(tmp_path):
    from hri_teleop.core.paths import NOTEBOOKS
    from hri_teleop.grading.points import check_cell_problems

    assert check_cell_problems(NOTEBOOKS / "source") == []
    target = tmp_path / "source" / ASSIGNMENT / f"{NOTEBOOK}.ipynb"
    target.parent.mkdir(parents=True)
    nb = json.loads((NOTEBOOKS / "source" / ASSIGNMENT / target.name).read_text(encoding="utf-8"))
    for cell in nb["cells"]:
        if cell.get("metadata", {}).get("nbgrader", {}).get("grade_id") == "ex1a_rate":
            cell["metadata"]["nbgrader"]["grade_id"] = "ex1a_mine"
    target.write_text(json.dumps(nb), encoding="utf-8")
    [problem] = check_cell_problems(tmp_path / "source")
    assert problem.startswith(f"{ASSIGNMENT}/{NOTEBOOK}.ipynb: autograded cell ex1a_mine has no rule in the grader")
    assert "hand_in" in problem and "\n" not in problem


def _gradebook(tmp_path: Path, students: List[str]) -> str:
    """A gradebook with Ex. 1's three autograded cells and a submission of each of ``students``; its URL."""
    from nbgrader.api import Gradebook

    db = f"sqlite:///{tmp_path / 'gradebook.db'}"
    with Gradebook(db, "course") as gb:
        gb.add_assignment(ASSIGNMENT)
        gb.add_notebook(NOTEBOOK, ASSIGNMENT)
        for grade_id in GRADED:
            gb.add_grade_cell(grade_id, NOTEBOOK, ASSIGNMENT, max_score=1, cell_type="code")
        for student in students:
            gb.add_student(student)
            gb.add_submission(ASSIGNMENT, student)
    return db


def test_an_autograded_notebook_the_grader_cannot_read_scores_zero_and_is_left_as_it_is(tmp_path):
    pytest.importorskip("nbgrader.api")
    from hri_teleop.grading.batch.notebook_judge import judge_submission

    db = _gradebook(tmp_path, ["s", "t"])
    path = tmp_path / "autograded" / "s" / ASSIGNMENT / f"{NOTEBOOK}.ipynb"
    path.parent.mkdir(parents=True)
    path.write_text("{not json")
    verdicts = judge_submission(tmp_path, db, "course", "s", ASSIGNMENT)
    assert {(v.score, v.message) for v in verdicts} == {
        (0.0, "not judged: the autograded notebook could not be read (JSONDecodeError)")}
    assert path.read_text() == "{not json"
    assert {v.message for v in judge_submission(tmp_path, db, "course", "t", ASSIGNMENT)} == {
        "not judged: the notebook was not handed in"}


def test_the_grader_writes_its_scores_into_the_gradebook_and_keeps_grades_given_by_hand(tmp_path):
    """judge_submission on a gradebook and an autograded notebook as nbgrader leaves them."""
    nbgrader_api = pytest.importorskip("nbgrader.api")
    from hri_teleop.grading.batch.notebook_judge import judge_submission

    db = _gradebook(tmp_path, ["s"])
    with nbgrader_api.Gradebook(db, "course") as gb:
        gb.find_grade("ex1a_voltage", NOTEBOOK, ASSIGNMENT, "s").manual_score = 0.5  # a TA's, before a regrade
        gb.db.commit()
    volts = float(expectations("ex1a_voltage")["a0_voltage_at_1n_v"])
    cells = [_graded("ex1a_rate", [_answer(RIGHT_RATE)]),
             _graded("ex1a_voltage", [_answer({"a0_voltage_at_1n_v": volts / 2}, "ex1a_voltage"), _error("WrongAnswer")]),
             _graded("ex1a_count", [_error()])]
    path = tmp_path / "autograded" / "s" / ASSIGNMENT / f"{NOTEBOOK}.ipynb"
    path.parent.mkdir(parents=True)
    path.write_text(json.dumps({"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 4}))

    verdicts = judge_submission(tmp_path, db, "course", "s", ASSIGNMENT)
    assert [(v.grade_id, v.score) for v in verdicts] == [("ex1a_rate", 1.0), ("ex1a_voltage", 0.0), ("ex1a_count", 0.0)]
    with nbgrader_api.Gradebook(db, "course") as gb:
        grades = {g.name: g for g in gb.find_submission_notebook(NOTEBOOK, ASSIGNMENT, "s").grades}
        assert (grades["ex1a_rate"].auto_score, grades["ex1a_rate"].score, grades["ex1a_rate"].needs_manual_grade) \
            == (1.0, 1.0, False)
        voltage = grades["ex1a_voltage"]
        assert (voltage.auto_score, voltage.manual_score, voltage.score, voltage.needs_manual_grade) == \
            (0.0, 0.5, 0.5, True)
        assert grades["ex1a_count"].score == 0.0
    written = {c["metadata"]["nbgrader"]["grade_id"]: _text(c) for c in json.loads(path.read_text())["cells"]}
    assert written["ex1a_rate"].endswith("the grader: 1 of 1 point: right\n")
    assert "the grader: 0 of 1 point: a0_voltage_at_1n_v is " in written["ex1a_voltage"]
    assert written["ex1a_count"] == ("the grader: 0 of 1 point: not judged: the cell handed in no value (it raised "
                                     "NameError: name 'x' is not defined)\n")


@pytest.mark.ros
def test_on_gradescope_too_an_ast_transformer_gains_nothing_and_the_answer_key_keeps_its_points(tmp_path):
    """Gradescope's notebook path (grade_notebooks: generate, autograde_one, the gradebook's scores) judges the
    same way: the upload with wrong answers and the transformer gets 0 per cell, the answer key every point."""
    import nbformat

    from hri_teleop.course.release import COURSE_DIR
    from hri_teleop.grading.cases.templates import generate_answers
    from hri_teleop.grading.gradescope.notebooks import course_members, grade_notebooks
    from hri_teleop.grading.run.kernel_sandbox import KernelPolicy, kernel_sandbox_problem

    shipped = tmp_path / "shipped"
    for name, data in course_members(COURSE_DIR):
        path = shipped / name.split("/", 1)[1]
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    package = tmp_path / "package"
    generate_answers(SOLUTIONS, package)
    sandbox = None if kernel_sandbox_problem() else KernelPolicy((str(tmp_path),))
    outputs: Dict[str, List[Dict[str, Any]]] = {}
    for student, answers, extra in (("alice", "", ""), ("mallory", WRONG, SWALLOW)):
        nb = nbformat.read(str(COURSE_DIR / "source" / ASSIGNMENT / f"{NOTEBOOK}.ipynb"), as_version=4)
        first = next(i for i, c in enumerate(nb.cells) if c.metadata.get("nbgrader", {}).get("solution"))
        if answers:
            nb.cells[first].source = answers
            cell = nbformat.v4.new_code_cell(extra)
            cell.pop("id", None)
            nb.cells.insert(first + 1, cell)
        upload = tmp_path / student / f"{NOTEBOOK}.ipynb"
        upload.parent.mkdir()
        nbformat.write(nb, str(upload))
        result = grade_notebooks([upload], package, shipped, tmp_path / f"work-{student}", student=student,
                                 sandbox=sandbox)
        outputs[student] = result.tests[f"{ASSIGNMENT}/{NOTEBOOK}.ipynb"]
    assert [t["score"] for t in outputs["mallory"]] == [0.0] * 3, outputs["mallory"]
    assert "the grader: 0 of 1 point: sketch_rate_hz is 1 Hz" in outputs["mallory"][0]["output"]
    assert [(t["score"], t["max_score"]) for t in outputs["alice"]] == [(1.0, 1.0)] * 3, outputs["alice"]
    assert all("the grader: 1 of 1 point: right" in t["output"] for t in outputs["alice"])
