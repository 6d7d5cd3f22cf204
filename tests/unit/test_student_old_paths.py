"""Last term's import paths (hri_teleop.gamepad, hri_teleop.limits, ...) still give what last term's files
imported, as the student API's objects, with one one-line DeprecationWarning on the importing line,
until the student API's next major version. Last term's files: tests/grading/last_term/."""

from __future__ import annotations

import ast
import importlib
import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Dict, List

import pytest

import hri_teleop.student as student
from hri_teleop.student.deprecation import OLD_PATHS_SINCE, REMOVED_IN

REPO = Path(__file__).resolve().parents[2]
LAST_TERM = REPO / "tests" / "grading" / "last_term"
#: The shims and their files; tests/unit/test_layers.py keeps them the only modules outside the layers.
OLD_PATHS = {"hri_teleop.gamepad": "hri_teleop/gamepad/__init__.py", "hri_teleop.gamepad.events":
             "hri_teleop/gamepad/events.py", "hri_teleop.limits": "hri_teleop/limits.py",
             "hri_teleop.mapping": "hri_teleop/mapping.py", "hri_teleop.sensor_profile": "hri_teleop/sensor_profile.py",
             "hri_teleop.gripper": "hri_teleop/gripper.py"}


def last_terms_imports() -> Dict[str, List[str]]:
    """Module -> the names last term's files import from it (every ``from hri_teleop... import``)."""
    found: Dict[str, List[str]] = {}
    for path in sorted(LAST_TERM.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("hri_teleop"):
                names = found.setdefault(str(node.module), [])
                names += [a.name for a in node.names if a.name not in names]
    return found


def _clean_env() -> Dict[str, str]:
    return {k: v for k, v in os.environ.items() if k != "PYTHONWARNINGS"}


def test_the_old_paths_are_exactly_the_modules_last_terms_files_import_that_moved():
    pytest.importorskip("rospy", reason="hri_teleop.ros needs rospy (the Python 3.8 run of the core tests has none)")
    moved = []
    for module in last_terms_imports():
        try:
            importlib.import_module(module)
        except ImportError:
            moved.append(module)
    assert moved == []  # every one imports
    assert {m for m in last_terms_imports() if not m.startswith("hri_teleop.ros.")} == set(OLD_PATHS)


@pytest.mark.parametrize("old", sorted(OLD_PATHS))
def test_an_old_path_gives_the_student_apis_objects_with_one_warning_on_the_importing_line(old, tmp_path):
    names = last_terms_imports()[old]
    script = tmp_path / "student_file.py"
    script.write_text(
        "import json, warnings\n"
        "import hri_teleop.student as api\n"
        "with warnings.catch_warnings(record=True) as caught:\n"
        "    warnings.simplefilter('always')\n"
        f"    from {old} import {', '.join(names)}\n"  # line 5
        f"    from {old} import {names[0]}\n"
        f"    import {old}\n"
        f"    again = {old}.{names[-1]}\n"
        f"same = [{', '.join(f'{n} is api.{n}' for n in names)}]\n"
        "print(json.dumps({'same': same, 'warnings': [[w.category.__name__, str(w.message), w.filename, w.lineno]"
        " for w in caught]}))\n")
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, env=_clean_env())
    assert out.returncode == 0, out.stderr
    seen = json.loads(out.stdout)
    assert seen["same"] == [True] * len(names)
    assert seen["warnings"] == [["DeprecationWarning", f"{old} is deprecated: write 'from hri_teleop.student import "
                                 f"{', '.join(names)}' instead; it goes in 2.0", str(script), 5]]


def test_a_students_node_run_as_a_program_shows_each_old_paths_warning_once(tmp_path):
    """Python shows a DeprecationWarning of __main__'s own lines: the node the student runs says it once."""
    script = tmp_path / "teleoperation.py"
    script.write_text("from hri_teleop.gamepad import PadState, normalize_analog_input, open_gamepad\n"
                      "from hri_teleop.gamepad.events import JOYAXISMOTION, JOYBUTTONDOWN, JOYBUTTONUP, pad_events\n"
                      "from hri_teleop.limits import TwistLimiter\n"
                      "from hri_teleop.limits import TwistLimiter as Again\n"
                      "print(TwistLimiter is Again)\n")
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, env=_clean_env())
    assert out.stdout == "True\n"
    said = [line for line in out.stderr.splitlines() if "DeprecationWarning" in line]
    assert [line.split(": DeprecationWarning: ")[1].split(" is deprecated")[0] for line in said] == [
        "hri_teleop.gamepad", "hri_teleop.gamepad.events", "hri_teleop.limits"]
    assert [line.split(": DeprecationWarning")[0] for line in said] == [f"{script}:1", f"{script}:2", f"{script}:3"]


def test_an_old_path_gives_only_what_last_term_imported_from_it():
    limits = importlib.import_module("hri_teleop.limits")
    with pytest.raises(AttributeError, match="has no attribute 'Watchdog'"):
        _ = limits.Watchdog
    with pytest.raises(ImportError):
        exec("from hri_teleop.mapping import map_force", {})  # Ex. 5's rule is never given


def test_the_old_paths_go_in_the_next_major_version_of_the_student_api():
    major = int(student.API_VERSION.split(".")[0])
    assert (OLD_PATHS_SINCE, REMOVED_IN) == ("1.0", "2.0")
    present = {module for module, path in OLD_PATHS.items() if (REPO / path).exists()}
    if major >= int(REMOVED_IN.split(".")[0]):
        assert present == set(), "student API 2.0: delete last term's shims (docs/student-api.md)"
    else:
        assert present == set(OLD_PATHS)
