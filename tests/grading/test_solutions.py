"""The answer key passes every check, and so do the lab's own files (the rules and the key agree)."""

from __future__ import annotations

import threading
import time

import pytest
from grading_helpers import REPO, SOLUTIONS

from hri_teleop.grading import GradingError, feedback_text, grade_submission
from hri_teleop.grading.cases.templates import generate_templates
from hri_teleop.grading.checks import CHECKS, default_check_jobs
from hri_teleop.grading.exercises.mapping_node.check import grade_mapping_node
from hri_teleop.grading.exercises.registry import exercise
from hri_teleop.grading.exercises.robot_params import grade_robot_params
from hri_teleop.grading.exercises.teleoperation.check import grade_teleoperation
from hri_teleop.grading.judge.harness import CheckRun, closing_scratch, start_check

pytestmark = pytest.mark.ros


def test_solutions_pass_every_check_with_full_marks_graded_three_checks_at_a_time(tmp_path):
    """Side by side (hri-grade submission's default on a 2-core machine): each check keeps its own
    scratch folder, sandbox and master while the others start and end, and the results come back
    in the checks' order."""
    started = time.monotonic()
    jobs = default_check_jobs(2)
    assert jobs == 3
    results = grade_submission(SOLUTIONS, out_dir=tmp_path, graph_cache=tmp_path / "graph.json", jobs=jobs)
    assert [r.check for r in results] == list(CHECKS)
    assert all(r.passed for r in results), feedback_text(results)
    assert all(r.max_score > 0 for r in results)
    durations = ", ".join(f"{r.check} {r.duration_s:.1f} s" for r in results)
    print(f"answer key graded in {time.monotonic() - started:.1f} s: {durations}")


def test_the_labs_own_robot_params_and_mapping_node_pass_the_same_checks(tmp_path):
    params = grade_robot_params(REPO / "hri_lab" / "config" / "robot_params.yaml", out_dir=tmp_path)
    lab_node = REPO / "hri_lab" / "scripts" / "mapping_node.py"
    node = grade_mapping_node(lab_node, out_dir=tmp_path, seed=11, reference_allowed=True)
    assert params.passed and node.passed, feedback_text([params, node])
    refused = grade_mapping_node(lab_node, out_dir=tmp_path, seed=11)  # the reference itself, handed in by a student
    assert refused.score == 0 and "uses the lab's reference implementation" in refused.parts[0].message


def test_the_generated_templates_are_gradable_and_say_what_to_fill_in(tmp_path):
    generate_templates(SOLUTIONS, tmp_path / "hri_lab")
    params = grade_robot_params(tmp_path / "hri_lab", out_dir=tmp_path / "out")
    assert not params.parts[0].passed and "sets no parameter" in params.parts[0].message  # comments only
    assert params.score == 0
    teleop = grade_teleoperation(tmp_path / "hri_lab", out_dir=tmp_path / "out", node=False)
    assert teleop.parts[0].passed, feedback_text([teleop])  # it imports
    for part in teleop.parts[1:5]:
        assert not part.passed and "NotImplementedError" in part.message and "YOUR CODE HERE" in part.message


def test_by_default_one_check_more_than_cores_runs_at_once_and_at_least_two():
    assert [default_check_jobs(n) for n in (None, 0, 1, 2, 8)] == [2, 2, 2, 3, 9]


def test_grade_submission_refuses_zero_jobs(tmp_path):
    with pytest.raises(GradingError, match="at least 1"):
        grade_submission(SOLUTIONS, out_dir=tmp_path, jobs=0)


def test_a_check_that_ends_closes_only_the_scratch_folders_of_its_own_thread(tmp_path):
    """closing_scratch used to close every open run: a check graded beside another lost its folder."""
    opened: dict = {}
    other_may_end, other_ended = threading.Event(), threading.Event()

    @closing_scratch
    def other_check() -> None:
        run, _ = start_check(exercise("robot-params"), SOLUTIONS, tmp_path / "other", 1)
        opened["other"] = run
        other_may_end.wait(30)

    thread = threading.Thread(target=lambda: (other_check(), other_ended.set()))
    mine, _ = start_check(exercise("mapping-node"), SOLUTIONS, tmp_path / "mine", 1)
    thread.start()
    other_may_end.set()
    thread.join(30)
    assert other_ended.is_set() and isinstance(mine, CheckRun)
    assert opened["other"].closed and not opened["other"].session_dir.exists()
    assert not mine.closed and mine.session_dir.is_dir()  # still there for this thread's check
    mine.close()
    assert not mine.session_dir.exists()
