"""Reading the handout's catkin steps from a package: CMakeLists entries, executable bits, build errors."""

from __future__ import annotations

import os

import pytest

from hri_teleop.ros.catkin_files import explain_build_failure, installed_programs, is_executable

CMAKE = """cmake_minimum_required(VERSION 3.0.2)
project(hri_lab)
catkin_install_python(PROGRAMS
  scripts/FSR_sensor.py
  # scripts/teleoperation.py   (commented out: not installed)
  "scripts/mapping_node.py"
  ${PROJECT_SOURCE_DIR}/scripts/gripper_manager.py
  DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION}
)
install(PROGRAMS scripts/other.py DESTINATION bin)
"""


def test_the_programs_of_catkin_install_python_are_read_as_written():
    assert installed_programs(CMAKE) == ["scripts/FSR_sensor.py", "scripts/mapping_node.py",
                                         "${PROJECT_SOURCE_DIR}/scripts/gripper_manager.py"]


def test_two_install_calls_add_up_and_a_call_without_programs_adds_nothing():
    text = ("catkin_install_python(PROGRAMS scripts/a.py DESTINATION x)\n"
            "CATKIN_INSTALL_PYTHON(PROGRAMS scripts/b.py OPTIONAL DESTINATION y)\n"
            "catkin_install_python(FILES scripts/c.py DESTINATION z)\n")
    assert installed_programs(text) == ["scripts/a.py", "scripts/b.py"]


def test_no_install_call_lists_nothing():
    assert installed_programs("project(hri_lab)\ncatkin_package()\n") == []


@pytest.mark.parametrize("mode, expected", [(0o644, False), (0o744, True), (0o755, True), (0o654, False)])
def test_executable_means_the_owner_may_execute_it(tmp_path, mode, expected):
    script = tmp_path / "node.py"
    script.write_text("print(1)\n")
    os.chmod(script, mode)
    assert is_executable(script) is expected


def test_a_missing_file_or_a_folder_is_not_executable(tmp_path):
    assert not is_executable(tmp_path / "missing.py")
    assert not is_executable(tmp_path)


def test_a_listed_script_that_does_not_exist_is_named_with_the_fix():
    log = ("CMake Error at /usr/share/catkin/cmake/catkin_install_python.cmake:86 (message):\n"
           "  catkin_install_python() called with non-existing file\n"
           "  '/home/s/catkin_ws/src/hri_lab/scripts/teleoperaton.py'.\n")
    assert explain_build_failure(log) == ("CMakeLists.txt lists scripts/teleoperaton.py, which does not exist: correct "
                                          "the name in catkin_install_python(PROGRAMS ...) or put the file into "
                                          "hri_lab/scripts/")


def test_a_cmake_syntax_error_gives_its_line():
    log = ('CMake Error at hri_lab/CMakeLists.txt:8:\n  Parse error.  Function missing ending ")".  '
           "End of file reached.\n\n-- Configuring incomplete, errors occurred!\n")
    message = explain_build_failure(log)
    assert message.startswith("CMakeLists.txt line 8 is not valid CMake (Function missing ending")


def test_a_bad_manifest_is_named_with_its_reason():
    log = ("Error(s) in package '/ws/src/hri_lab/package.xml':\nError(s):\n"
           '- The manifest of package "hri_lab" (with format version 2) must not contain the following tags: bogus\n')
    assert explain_build_failure(log) == ('package.xml is not a valid catkin manifest (The manifest of package '
                                          '"hri_lab" (with format version 2) must not contain the following tags: '
                                          "bogus); restore it from the released version")


def test_an_unknown_failure_gives_its_first_error_line_or_the_log():
    assert explain_build_failure("#### Running\nmake: *** [all] Error 2\n") == "catkin_make failed: make: *** [all] Error 2"
    assert explain_build_failure("nothing useful\n") == "catkin_make failed (see catkin_ws/build.log)"
