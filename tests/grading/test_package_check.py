"""Ex. 9 and Ex. 12 c): executable bits and CMakeLists entries, each a part of its own."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from hri_teleop.grading.exercises.catkin_package import PARTS as CATKIN_PACKAGE
from hri_teleop.grading.exercises.catkin_package import grade_catkin_package
from hri_teleop.grading.results import GradingError

LISTS = "catkin_install_python(PROGRAMS\n  scripts/FSR_sensor.py\n{extra}  DESTINATION ${{CATKIN_PACKAGE_BIN_DESTINATION}}\n)\n"


def _package(root: Path, *, teleop_x=True, gm_x=True, listed=("teleoperation.py", "gripper_manager.py"),
             cmake=True) -> Path:
    (root / "scripts").mkdir(parents=True)
    for name, executable in (("teleoperation.py", teleop_x), ("gripper_manager.py", gm_x)):
        path = root / "scripts" / name
        path.write_text("#!/usr/bin/env python3\n")
        os.chmod(path, 0o755 if executable else 0o644)
    if cmake:
        extra = "".join(f"  scripts/{name}\n" for name in listed)
        (root / "CMakeLists.txt").write_text(LISTS.format(extra=extra))
    return root


def _passed(result):
    return {p.name: p.passed for p in result.parts}


def test_the_answer_key_gets_every_point(tmp_path):
    result = grade_catkin_package(_package(tmp_path / "hri_lab"))
    assert result.score == result.max_score == sum(points for _n, points in CATKIN_PACKAGE.values()) == 4


def test_each_missing_step_costs_its_own_point(tmp_path):
    result = grade_catkin_package(_package(tmp_path / "hri_lab", teleop_x=False, listed=("gripper_manager.py",)))
    assert result.score == 2
    failed = [p for p in result.parts if not p.passed]
    assert [p.name for p in failed] == [CATKIN_PACKAGE["teleop_executable"][0], CATKIN_PACKAGE["teleop_cmake"][0]]
    assert "chmod +x hri_lab/scripts/teleoperation.py" in failed[0].message
    assert "lists scripts/FSR_sensor.py, scripts/gripper_manager.py: add your script" in failed[1].message


def test_an_exercise_grades_only_its_half(tmp_path):
    package = _package(tmp_path / "hri_lab", gm_x=False, listed=("teleoperation.py",))
    assert grade_catkin_package(package, exercise=9).score == 2
    ex12 = grade_catkin_package(package, exercise=12)
    assert ex12.score == 0 and ex12.max_score == 2
    with pytest.raises(GradingError, match="pass 9, 12 or None"):
        grade_catkin_package(package, exercise=10)


def test_the_same_package_gets_the_same_points_from_its_folder_a_script_or_its_cmakelists(tmp_path):
    package = _package(tmp_path / "hri_lab", gm_x=False)
    scores = {grade_catkin_package(p).score for p in (package, package / "CMakeLists.txt",
                                                      package / "scripts" / "teleoperation.py")}
    assert scores == {3}


def test_without_cmakelists_the_entries_fail_and_the_bits_still_count(tmp_path):
    result = grade_catkin_package(_package(tmp_path / "hri_lab", cmake=False))
    assert result.score == 2
    assert all("CMakeLists.txt was not found" in p.message for p in result.parts if not p.passed)


def test_a_missing_script_fails_its_bit_with_where_to_put_it(tmp_path):
    package = _package(tmp_path / "hri_lab")
    (package / "scripts" / "gripper_manager.py").unlink()
    parts = {p.name: p for p in grade_catkin_package(package).parts}
    assert "scripts/gripper_manager.py was not found" in parts[CATKIN_PACKAGE["gm_executable"][0]].message


def test_a_path_that_does_not_exist_is_a_grader_error(tmp_path):
    with pytest.raises(GradingError, match="no such file or folder"):
        grade_catkin_package(tmp_path / "nope")
