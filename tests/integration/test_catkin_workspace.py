"""The handout's catkin workflow for real: the released package builds with catkin_make, rosrun starts
the student's node from the workspace on the notebook's master, and a broken CMakeLists is one line."""

from __future__ import annotations

import os
import stat
import subprocess
import time
from pathlib import Path

import pytest

from hri_teleop.core.paths import SOLUTIONS
from hri_teleop.course.release import STUDENT_MAKES_EXECUTABLE
from hri_teleop.grading.cases.templates import generate_templates, make_answer
from hri_teleop.grading.exercises.catkin_package import grade_catkin_package
from hri_teleop.ros.catkin_ws import CatkinError, build_workspace
from hri_teleop.ros.master import finds_hri_lab

pytestmark = pytest.mark.ros


@pytest.fixture
def released(tmp_path):
    """The student's package as make release writes it (templates and provided files)."""
    package = tmp_path / "lab" / "hri_lab"
    generate_templates(SOLUTIONS, package, not_executable=STUDENT_MAKES_EXECUTABLE)
    return package


def _answer(package: Path) -> None:
    """What a student does for Ex. 9 and 12 c): chmod +x and the CMakeLists entries."""
    for sub in STUDENT_MAKES_EXECUTABLE:
        path = package / sub
        path.chmod(path.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
    (package / "CMakeLists.txt").write_text(make_answer((SOLUTIONS / "CMakeLists.txt").read_text()))


def test_the_released_package_builds_and_gets_no_catkin_points_until_the_student_does_the_steps(released, ros_env,
                                                                                              monkeypatch):
    for key, value in ros_env.items():
        monkeypatch.setenv(key, value)
    ws = build_workspace(released)
    assert ws.root == released.parent / "catkin_ws" and (ws.root / "src" / "hri_lab").resolve() == released.resolve()
    assert (ws.setup).is_file() and (ws.root / "build.log").is_file()
    assert grade_catkin_package(released).score == 0
    _answer(released)
    build_workspace(released)
    assert (ws.root / "devel" / "lib" / "hri_lab" / "teleoperation.py").is_file(), "catkin made no relay"
    assert grade_catkin_package(released).score == 4


def test_the_workspace_environment_keeps_the_notebooks_master_and_drops_the_labs_package(released, ros_env,
                                                                                        monkeypatch):
    for key, value in ros_env.items():
        monkeypatch.setenv(key, value)
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:54321/")
    env = build_workspace(released).env()
    assert "ROS_MASTER_URI" not in env, "devel/setup.bash's 11311 must not reach the nodes"
    paths = env["ROS_PACKAGE_PATH"].split(":")
    assert paths[0] == str(released.parent / "catkin_ws" / "src")
    assert not any(finds_hri_lab(p) for p in paths[1:]), "the lab's hri_lab shadows"


def test_rosrun_starts_the_students_node_from_the_workspace_on_the_notebooks_master(released, ros_master,
                                                                                   monkeypatch):
    from hri_teleop.course import lab

    for key, value in ros_master.env.items():
        monkeypatch.setenv(key, value)
    _answer(released)
    (released / "scripts" / "teleoperation.py").write_text(
        make_answer((SOLUTIONS / "scripts" / "teleoperation.py").read_text()))
    ws = build_workspace(released)
    node = lab.rosrun(ws, "teleoperation.py", "teleoperation", pad="virtual", wait_for_robot_s=0.1)
    try:
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and "/teleoperation" not in ros_master.node_names():
            assert node.running, node.output()
            time.sleep(0.1)
        info = subprocess.run(["rostopic", "info", "/gripper_width"], env=dict(os.environ), capture_output=True,
                              text=True, timeout=30).stdout
        assert "/teleoperation" in info
    finally:
        lab.stop()


def test_a_misspelled_script_in_cmakelists_is_one_line_naming_it(released, ros_env, monkeypatch):
    for key, value in ros_env.items():
        monkeypatch.setenv(key, value)
    cmake = released / "CMakeLists.txt"
    cmake.write_text(cmake.read_text().replace("scripts/FSR_sensor.py", "scripts/FSR_sensr.py"))
    with pytest.raises(CatkinError) as err:
        build_workspace(released)
    message = str(err.value)
    assert "\n" not in message
    assert message.startswith("CMakeLists.txt lists scripts/FSR_sensr.py, which does not exist: correct the name")
    assert message.endswith(f"(full log: {released.parent / 'catkin_ws' / 'build.log'})")


def test_a_package_without_manifest_is_refused_before_building(tmp_path):
    (tmp_path / "hri_lab").mkdir()
    with pytest.raises(CatkinError, match="package.xml: not found; a catkin package needs it"):
        build_workspace(tmp_path / "hri_lab")
