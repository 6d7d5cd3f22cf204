"""Ex. 9 and Ex. 12 c): the handout's catkin steps, judged on the student's package as handed in.

``teleoperation.py`` (Ex. 9) and ``gripper_manager.py`` (Ex. 12 c) executable and listed in the
package's ``CMakeLists.txt``: four parts. Nothing runs: the check reads file modes and the
CMakeLists text (:mod:`hri_teleop.ros.catkin_files`), the same alone, in a batch, idle or under
load. A script or CMakeLists.txt that is a link or not a regular file fails with one line.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple, Union

from hri_teleop.grading.exercise import Exercise
from hri_teleop.grading.results import CheckResult, GradingError, Part
from hri_teleop.grading.run.untrusted_files import UntrustedFileError, read_regular, refusal
from hri_teleop.grading.run.workspace import find_package_root, given_path
from hri_teleop.ros.catkin_files import installed_programs, is_executable

__all__ = ["EXERCISE", "PARTS", "EXERCISE_PARTS", "grade_catkin_package"]

#: part key -> (what it judges, points)
PARTS: Dict[str, Tuple[str, float]] = {
    "teleop_executable": ("Ex. 9: scripts/teleoperation.py is executable (chmod +x)", 1),
    "teleop_cmake": ("Ex. 9: CMakeLists.txt installs scripts/teleoperation.py (catkin_install_python)", 1),
    "gm_executable": ("Ex. 12 c): scripts/gripper_manager.py is executable (chmod +x)", 1),
    "gm_cmake": ("Ex. 12 c): CMakeLists.txt installs scripts/gripper_manager.py (catkin_install_python)", 1),
}
#: The parts each exercise's notebook grades.
EXERCISE_PARTS: Dict[int, Tuple[str, ...]] = {9: ("teleop_executable", "teleop_cmake"),
                                              12: ("gm_executable", "gm_cmake")}
_SCRIPTS = {"teleop": "scripts/teleoperation.py", "gm": "scripts/gripper_manager.py"}


def _lists(programs: Sequence[str], script: str) -> bool:
    """True if a catkin_install_python entry names ``script`` (plain, or under ${PROJECT_SOURCE_DIR}/ and the like)."""
    return any(entry == script or entry.endswith("/" + script) for entry in programs)


def _executable_part(root: Path, key: str) -> Part:
    name, points = PARTS[f"{key}_executable"]
    script = root / _SCRIPTS[key]
    why = refusal(script, root)
    if why.endswith("No such file or directory"):
        return Part(name, points, False, f"{_SCRIPTS[key]} was not found in {root}: put it at that place in your "
                                         "hri_lab package")
    if why:
        return Part(name, points, False, why)
    if is_executable(script):
        return Part(name, points, True)
    return Part(name, points, False, f"{_SCRIPTS[key]} is not executable, and rosrun starts only executable "
                                     f"scripts: chmod +x hri_lab/{_SCRIPTS[key]}")


def _cmake_part(root: Path, key: str, programs: Optional[List[str]], problem: str) -> Part:
    name, points = PARTS[f"{key}_cmake"]
    if programs is None:
        return Part(name, points, False, problem)
    if _lists(programs, _SCRIPTS[key]):
        return Part(name, points, True)
    listed = ", ".join(programs) or "nothing"
    return Part(name, points, False, f"CMakeLists.txt's catkin_install_python(PROGRAMS ...) lists {listed}: add "
                                     f"your script to that list, then build the workspace again")


def grade_catkin_package(path: Union[str, Path], *, seed: Optional[int] = None, out_dir: Optional[Union[str, Path]] = None,
                         exercise: Optional[int] = None) -> CheckResult:
    """The executable bits and CMakeLists entries of Ex. 9 and Ex. 12 c); ``exercise`` 9 or 12 grades its half."""
    del seed, out_dir  # no hidden inputs and nothing to plot: accepted so every check takes the same arguments
    started = time.monotonic()
    if exercise is not None and exercise not in EXERCISE_PARTS:
        raise GradingError(f"exercise {exercise!r}: the catkin-package check grades Ex. 9 or Ex. 12; pass 9, 12 or None")
    path = given_path(path)
    if not os.path.lexists(path):
        raise GradingError(f"{path}: no such file or folder; give the student's hri_lab folder (or its CMakeLists.txt)")
    root = path.parent if not path.is_dir() and path.name == "CMakeLists.txt" else find_package_root(path)
    cmake = root / "CMakeLists.txt"
    programs: Optional[List[str]] = None
    problem = ""
    try:
        programs = installed_programs(read_regular(cmake, root=root).decode("utf-8"))
    except UntrustedFileError as exc:
        problem = (f"CMakeLists.txt was not found in {root}: every catkin package has one (restore the released one)"
                   if str(exc).endswith("No such file or directory") else str(exc))
    except UnicodeDecodeError as exc:
        problem = f"CMakeLists.txt cannot be read ({exc})"
    parts: Dict[str, Part] = {}
    for key in _SCRIPTS:
        parts[f"{key}_executable"] = _executable_part(root, key)
        parts[f"{key}_cmake"] = _cmake_part(root, key, programs, problem)
    wanted = EXERCISE_PARTS[exercise] if exercise is not None else tuple(PARTS)
    return CheckResult(EXERCISE.check, str(cmake), [parts[k] for k in wanted], None, time.monotonic() - started)


def exercise_half(package: Union[str, Path], exercise: int) -> CheckResult:
    """Ex. 9's or Ex. 12's half, as its notebook's check cell shows it (``check.catkin_package(PACKAGE, 9)``)."""
    return grade_catkin_package(package, exercise=exercise)


EXERCISE = Exercise(key="catkin_package", handout="Ex. 9 and 12 c)", assignment="lab", parts=PARTS,
                    grade=grade_catkin_package, notebook_calls={"catkin_package": exercise_half})
