"""make check's terminal lines: a cell or a check part that lost points comes with what its cell shows,
and the copies the notebooks and the files run in keep the student's folder out of reach."""

from __future__ import annotations

import os
from pathlib import Path

import nbformat

from hri_teleop.apps.files_check import check_lines, scratch_copy, summary_lines
from hri_teleop.apps.selfcheck import SLOW_FIRST, cell_feedback, default_jobs, kept_checks, notebook_lines, run_order
from hri_teleop.grading.cases.inputs import seed_for
from hri_teleop.grading.judge.reuse import REUSED_NOTE
from hri_teleop.grading.results import CheckResult, Part


def _graded(outputs, points=1):
    cell = nbformat.v4.new_code_cell("hand_in(...)")
    cell.metadata["nbgrader"] = {"grade": True, "solution": False, "grade_id": "ex2_rate", "points": points}
    cell.outputs = [nbformat.from_dict(o) for o in outputs]
    return cell


WRONG = [
    {"output_type": "display_data", "metadata": {}, "data": {"text/plain": "handed in for the grader: rate = 5"}},
    {"output_type": "error", "ename": "WrongAnswer", "evalue": "5 Hz is not what the board sends: measure it",
     "traceback": ["\x1b[0;31mWrongAnswer\x1b[0m: 5 Hz ..."]},
]


def test_a_failing_cell_shows_what_it_printed_and_its_error_in_one_line():
    assert cell_feedback(_graded(WRONG)) == ["handed in for the grader: rate = 5",
                                             "WrongAnswer: 5 Hz is not what the board sends: measure it"]


def test_colour_codes_and_blank_lines_are_left_out_and_a_long_output_keeps_its_end():
    cell = _graded([{"output_type": "stream", "name": "stdout",
                     "text": "".join(f"\x1b[1mline {k}\x1b[0m\n\n" for k in range(40))}])
    shown = cell_feedback(cell, limit=5)
    assert shown == ["...", "line 35", "line 36", "line 37", "line 38", "line 39"]


def test_a_notebook_line_lists_each_cell_that_lost_points_with_its_feedback():
    result = {"grades": {"ex2_type": [1.0, 1.0, ["ok"]], "ex2_rate": [0.0, 1.0, cell_feedback(_graded(WRONG))]},
              "error": "", "seconds": 3.2}
    lines = notebook_lines(Path("/b/preparation/ex02_fsr_sensor_node.ipynb"), result)
    assert lines[0] == "  preparation/ex02_fsr_sensor_node.ipynb ... 1/2 points (3 s)"
    assert lines[1:] == ["      ex2_rate: 0/1, the cell shows:", "        handed in for the grader: rate = 5",
                         "        WrongAnswer: 5 Hz is not what the board sends: measure it"]


def _result(notes=()):
    return CheckResult("mapping-node", "/tmp/x/hri_lab/scripts/mapping_node.py", [
        Part("subscribes /pub_force", 3, True),
        Part("publishes /force_mapped", 3, False, "nothing arrived on /force_mapped\nits last output:\n  NameError",
             plots=("/tmp/out/force_mapped.png",)),
        Part("clips above the range", 2, False, "not judged: the node did not publish", note="hidden inputs"),
    ], seed=7, notes=notes)


def test_a_check_that_lost_points_prints_each_failing_part_with_its_feedback_and_not_the_passed_ones():
    lines = check_lines(_result(notes=(REUSED_NOTE, "Ex. 8 parts still failing")), "preparation/hri_lab/scripts/x.py")
    assert lines[0] == "      mapping-node: 3/8 (preparation/hri_lab/scripts/x.py)"
    text = "\n".join(lines)
    assert "subscribes /pub_force" not in text
    for shown in ("[FAIL] publishes /force_mapped (0/3)", "nothing arrived on /force_mapped", "  NameError",
                  "[FAIL] clips above the range (0/2)", "hidden inputs", "not judged: the node did not publish",
                  "rerun with --seed 7", "note: Ex. 8 parts still failing", "plot: /tmp/out/force_mapped.png"):
        assert shown in text, shown
    assert REUSED_NOTE not in text  # make grade's note: not true of make check


def test_the_files_summary_names_the_notebook_and_the_terminal_command_of_a_check_that_lost_points():
    lines = summary_lines("preparation", [_result()], 1.0)
    assert lines[0] == "  preparation/hri_lab: mapping-node 3/8: 3/8 points (1 s)"
    assert lines[-1].endswith("(the same in ex05_mapping_node.ipynb, check cell; in a terminal: "
                              "hri-grade mapping-node preparation/hri_lab)")
    passed = CheckResult("mapping-node", "", [Part("subscribes /pub_force", 3, True)])
    assert summary_lines("preparation", [passed], 1.0) == ["  preparation/hri_lab: mapping-node 3/3: 3/3 points (1 s)"]


def test_the_slow_notebooks_start_first_and_the_others_keep_their_order():
    names = ["ex01_a", "ex04_b", "ex05_c", "ex08_d", "ex12_13_e"]
    order = [p.stem for p in run_order([Path(f"lab/{n}.ipynb") for n in names])]
    assert order == ["ex12_13_e", "ex05_c", "ex01_a", "ex04_b", "ex08_d"]
    assert SLOW_FIRST[0] == "ex12"


def test_a_scratch_copy_leaves_out_the_workspace_caches_and_other_assignments_links_the_toolkit_and_keeps_the_seed(tmp_path):
    bundle = tmp_path / "task4"
    package = bundle / "lab" / "hri_lab"
    (package / "scripts" / "__pycache__").mkdir(parents=True)
    (package / "scripts" / "teleoperation.py").write_text("print('mine')\n")
    (package / "scripts" / "__pycache__" / "teleoperation.cpython-311.pyc").write_bytes(b"x")
    (bundle / "lab" / "catkin_ws" / "build").mkdir(parents=True)
    (bundle / "lab" / "ex10_drive.yaml").write_text("[]\n")
    (bundle / "toolkit").mkdir()
    (bundle / "preparation").mkdir()
    copy = scratch_copy(bundle, "lab", tmp_path / "scratch")
    assert copy == tmp_path / "scratch" / "task4" / "lab"
    assert (copy / "hri_lab" / "scripts" / "teleoperation.py").read_text() == "print('mine')\n"
    assert (copy / "ex10_drive.yaml").is_file()
    assert not (copy / "catkin_ws").exists() and not (copy / "hri_lab" / "scripts" / "__pycache__").exists()
    assert os.readlink(copy.parent / "toolkit") == str(bundle / "toolkit")
    assert not (copy.parent / "preparation").exists()  # another assignment's folder: out of reach
    assert seed_for(copy / "hri_lab") == seed_for(package)
    (copy / "ex10_drive.yaml").write_text("changed\n")
    assert (bundle / "lab" / "ex10_drive.yaml").read_text() == "[]\n"


def test_the_check_cells_that_keep_a_whole_result_are_known_and_ex08s_parts_only_cell_is_not_one():
    source = Path(__file__).resolve().parents[2] / "notebooks" / "source"
    lab = sorted((source / "lab").glob("ex*.ipynb"))
    assert kept_checks([p for p in lab if p.stem.startswith("ex08")]) == {}
    assert kept_checks([p for p in lab if p.stem.startswith(("ex09", "ex12", "ex15"))]) == {
        "lab": {"teleoperation", "teleoperation-launch", "graph"}}
    preparation = sorted((source / "preparation").glob("ex*.ipynb"))
    assert kept_checks(preparation) == {"preparation": {"robot-params", "mapping-node", "sensor-launch"}}


def test_one_notebook_more_than_the_cores_runs_at_a_time():
    assert [default_jobs(n) for n in (None, 1, 2, 8)] == [2, 2, 3, 9]
