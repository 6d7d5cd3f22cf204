"""What the notebooks call from hri_teleop.course: the fast flag, scoring, the two halves of Ex. 8/9, files."""

from __future__ import annotations

import pytest

from hri_teleop import course
from hri_teleop.course import cells, check, lab, release
from hri_teleop.course.errors import CourseError
from hri_teleop.grading.assignments import ASSIGNMENTS
from hri_teleop.grading.exercises.teleoperation.parts import PARTS as TELEOP
from hri_teleop.grading.results import CheckResult, Part


@pytest.mark.parametrize("env,expected", [({}, False), ({"HRI_NOTEBOOK_FAST": "1"}, True),
                                          ({"HRI_NOTEBOOK_FAST": "0"}, False),
                                          ({"NBGRADER_EXECUTION": "autograde"}, True)])
def test_fast_under_tests_and_nbgrader_only(monkeypatch, env, expected):
    for name in cells.FAST_ENV:
        monkeypatch.delenv(name, raising=False)
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    assert cells.fast() is expected
    assert course.seconds(20.0, 2.0) == (2.0 if expected else 20.0)


def test_score_prints_the_feedback_and_returns_the_points_of_passed_parts(capsys):
    result = CheckResult("mapping-node", "hri_lab/scripts/mapping_node.py",
                         [Part("subscribes /pub_force", 3, True), Part("publishes /force_mapped", 3, False,
                                                                       "nothing arrived on /force_mapped")])
    assert check.score(result) == 3.0
    out = capsys.readouterr().out
    assert "nothing arrived on /force_mapped" in out and "3/6" in out


def test_teleoperation_check_splits_into_the_class_parts_and_the_node_parts(tmp_path):
    from hri_teleop.grading.cases.templates import generate_templates

    generate_templates(release.SOLUTIONS, tmp_path / "hri_lab")
    parts = check.calls()["teleoperation_parts"](tmp_path / "hri_lab")
    names = {p.name for p in parts.parts}
    assert names == {name for key, (name, _) in TELEOP.items() if not key.startswith("node_")}
    assert parts.score < parts.max_score == sum(p for k, (_, p) in TELEOP.items() if not k.startswith("node_"))
    node = check.calls()["teleoperation_node"](tmp_path / "hri_lab")
    assert {p.name for p in node.parts} == {name for key, (name, _) in TELEOP.items() if key.startswith("node_")}
    assert node.score == 0 and any("Ex. 8 parts still failing" in n for n in node.notes)


def test_show_file_names_a_missing_file_and_how_to_get_it_back(tmp_path):
    with pytest.raises(FileNotFoundError, match="restore it from the released version"):
        course.show_file(tmp_path / "hri_lab" / "scripts" / "mapping_node.py")


def test_import_student_file_rereads_the_file_each_time(tmp_path):
    script = tmp_path / "student.py"
    script.write_text("VALUE = 1\n")
    assert course.import_student_file(script).VALUE == 1
    script.write_text("VALUE = 2\n")
    assert course.import_student_file(script).VALUE == 2


def test_nodes_need_the_kernels_master_first(monkeypatch):
    monkeypatch.delenv("ROS_MASTER_URI", raising=False)
    with pytest.raises(CourseError, match="ensure_ros"):
        lab.run_provided("FSR_sensor.py")


def test_only_the_labs_own_nodes_are_provided(monkeypatch):
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:1/")
    with pytest.raises(CourseError, match="not one of the lab's nodes"):
        lab.run_provided("mapping_node_of_somebody_else.py")


def test_exclude_overwriting_names_every_student_file_in_both_assignments():
    from hri_teleop.grading.run.workspace import DELIVERABLES

    files = release.exclude_overwriting()
    assert set(files) == set(ASSIGNMENTS)
    for listed in files.values():
        # the six deliverables, and the CMakeLists.txt students add their scripts to (Ex. 9, 12 c)
        assert sorted(listed) == sorted([f"hri_lab/{sub}" for sub in DELIVERABLES.values()] + ["hri_lab/CMakeLists.txt"])


def test_link_answer_key_refuses_a_copy_of_the_answer_key_in_source(tmp_path):
    for assignment in ASSIGNMENTS:
        (tmp_path / "source" / assignment).mkdir(parents=True)
    (tmp_path / "source" / "preparation" / "hri_lab").mkdir()
    with pytest.raises(CourseError, match="never hold a copy"):
        release.link_answer_key(tmp_path)
    (tmp_path / "source" / "preparation" / "hri_lab").rmdir()
    links = release.link_answer_key(tmp_path)
    assert all(link.resolve() == release.SOLUTIONS.resolve() for link in links)
