"""hri-grade as a program: exit status 0/1/2, --json in Gradescope's format, one-line grader errors."""

from __future__ import annotations

import json

import pytest
from grading_helpers import SOLUTIONS, answer_text, hri_grade, write_package


def test_a_passing_check_exits_0_and_json_is_gradescopes_format(tmp_path):
    proc = hri_grade("robot-params", str(SOLUTIONS / "config" / "robot_params.yaml"), "--json", "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    payload = json.loads(proc.stdout)
    assert payload["score"] == 10
    assert {"name", "score", "max_score", "status", "output"} <= set(payload["tests"][0])
    assert all(t["status"] == "passed" for t in payload["tests"])
    assert json.loads((tmp_path / "results.json").read_text()) == payload


def test_a_failing_check_exits_1_and_prints_what_to_fix(tmp_path):
    bad = answer_text("config/robot_params.yaml").replace("robot_mass: 18.0 ", "robot_mass: 18   ")
    write_package(tmp_path / "hri_lab", {"config/robot_params.yaml": bad})
    proc = hri_grade("robot-params", str(tmp_path / "hri_lab"), "--out", str(tmp_path / "out"))
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "[FAIL] robot_mass" in proc.stdout and "decimal point" in proc.stdout


@pytest.mark.parametrize("args, words", [
    (["mapping-node", "/nonexistent/hri_lab"], "no such file or folder"),
    (["submission", "/nonexistent/hri_lab"], "no such file or folder"),
    (["templates", "--solutions", "/nonexistent"], "no such folder"),
    (["batch", "/nonexistent/submitted"], "collect submissions first"),
])
def test_when_the_grader_cannot_run_it_exits_2_with_one_line(args, words):
    proc = hri_grade(*args)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hri-grade: ") and words in lines[0], proc.stderr
    assert "Traceback" not in proc.stderr


def test_an_unknown_check_is_a_usage_error():
    proc = hri_grade("mapping", "x")
    assert proc.returncode == 2 and "invalid choice" in proc.stderr


def test_the_seed_is_reported_and_can_be_given(tmp_path):
    write_package(tmp_path / "hri_lab", {"config/robot_params.yaml": "x: 1\n"})
    proc = hri_grade("submission", str(tmp_path / "hri_lab"), "--seed", "1234", "--checks", "robot-params,mapping-node",
                     "--out", str(tmp_path / "out"))
    assert proc.returncode == 1
    assert "--seed 1234" in proc.stdout and "scripts/mapping_node.py was not found" in proc.stdout
