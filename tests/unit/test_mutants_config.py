"""`make mutants`: its scope names the core and the late policy, each module with its own unit tests, and
`make test` does not run it. Also the two helpers' own rules: which tests judge a mutant, and how a
survivor is printed."""

from __future__ import annotations

import fnmatch
import importlib.util
import re
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# The newest rules, whose thresholds the unit tests pin (docs/testing.md): none may leave the scope.
PINNED = {
    "hri_teleop/core/joints.py": "tests/unit/test_joints.py",
    "hri_teleop/core/gamepad/stale.py": "tests/unit/test_gamepad_stale.py",
    "hri_teleop/core/gamepad/identify.py": "tests/unit/test_gamepad_identify.py",
    "hri_teleop/core/gamepad/rumble.py": "tests/unit/test_gamepad_rumble.py",
    "hri_teleop/core/doctor.py": "tests/unit/test_doctor_rules.py",
    "hri_teleop/core/teleop.py": "tests/unit/test_teleop.py",
    "hri_teleop/core/limits.py": "tests/unit/test_limits.py",
    "hri_teleop/grading/batch/late.py": "tests/grading/test_late_policy.py",
}


def _load(name: str):
    spec = importlib.util.spec_from_file_location(f"_tools_{name}", REPO / "tools" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def mutants():
    if sys.version_info < (3, 9):
        pytest.skip("make mutants runs mutmut 3, which needs Python 3.10 or later")
    return _load("mutants")


@pytest.fixture(scope="module")
def scope_plugin():
    if sys.version_info < (3, 9):
        pytest.skip("make mutants runs mutmut 3, which needs Python 3.10 or later")
    return _load("mutants_scope")


def test_the_newest_rules_are_mutated_and_judged_by_their_own_tests(mutants):
    mutmut, table = mutants.load_config(REPO / "pyproject.toml")
    for module, test in PINNED.items():
        assert any(fnmatch.fnmatch(module, p) for p in mutmut["only_mutate"]), f"{module} left the mutation scope"
        assert test in table[module], f"{module}'s mutants are not judged by {test}"


def test_the_scope_is_every_module_of_the_core_and_agrees_with_itself(mutants):
    mutmut, table = mutants.load_config(REPO / "pyproject.toml")
    assert mutants.scope_problems(mutmut, table, REPO) == []
    core = {p.relative_to(REPO).as_posix() for p in (REPO / "hri_teleop" / "core").rglob("*.py")}
    assert core <= set(table)
    assert mutmut["source_paths"][0] == "hri_teleop" and "tools.mutants_scope" in mutmut["pytest_add_cli_args"]


def test_a_scope_that_lost_a_module_or_a_test_file_is_reported(mutants):
    mutmut, table = mutants.load_config(REPO / "pyproject.toml")
    shrunk = {k: v for k, v in table.items() if k != "hri_teleop/core/joints.py"}
    assert any("hri_teleop/core/joints.py has no entry" in p for p in mutants.scope_problems(mutmut, shrunk, REPO))
    narrowed = dict(mutmut, only_mutate=["hri_teleop/core/gamepad/*"])
    assert any("hri_teleop/core/limits.py is not in [tool.mutmut] only_mutate" in p
               for p in mutants.scope_problems(narrowed, table, REPO))
    unlisted = dict(mutmut, pytest_add_cli_args_test_selection=["tests/unit/test_limits.py"])
    assert any("test_joints.py judges a module but is not in" in p for p in mutants.scope_problems(unlisted, table, REPO))


def test_make_mutants_runs_the_tool_and_make_test_does_not():
    makefile = (REPO / "Makefile").read_text()
    recipes = dict(re.findall(r"^([a-z-]+):[^\n]*\n((?:\t[^\n]*\n)+)", makefile, flags=re.M))
    assert "tools/mutants.py" in recipes["mutants"]
    assert "mutants" not in recipes["test"] and "mutmut" not in recipes["test"]
    assert "make mutants" in (REPO / "README.md").read_text() and "make mutants" in (REPO / "docs" / "testing.md").read_text()


@pytest.mark.parametrize("name, module", [
    ("hri_teleop.core.joints.x\u01c1JointLimitWatch\u01c1update__mutmut_3", "hri_teleop/core/joints.py"),
    ("hri_teleop.core.gamepad.rumble.x_unit_intensity__mutmut_12", "hri_teleop/core/gamepad/rumble.py"),
    ("hri_teleop.grading.batch.late.x_parse_when__mutmut_1", "hri_teleop/grading/batch/late.py"),
])
def test_a_mutant_is_judged_by_the_tests_of_the_module_its_name_starts_with(scope_plugin, name, module):
    table = scope_plugin.module_tests(REPO / "pyproject.toml")
    assert scope_plugin.scope_for(name, table) == (module, table[module])


@pytest.mark.parametrize("name", ["", "stats", "fail", "list_all_tests", "mutant_generation"])
def test_outside_a_mutants_run_no_test_is_deselected(scope_plugin, name):
    assert scope_plugin.scope_for(name, {"hri_teleop/core/joints.py": []}) is None


def test_a_survivor_is_printed_with_its_line_in_the_module_and_the_change(mutants):
    source = "import math\n\n\nclass Watch:\n    def update(self, x):\n        y = abs(x)\n        return y > 0.1\n"
    diff = ("--- m.py\n+++ m.py\n@@ -1,3 +1,3 @@\n def update(self, x):\n     y = abs(x)\n"
            "-    return y > 0.1\n+    return y >= 0.1\n")
    line, change = mutants.describe(diff, source, "m.x\u01c1Watch\u01c1update__mutmut_2")
    assert (line, change) == (7, "return y > 0.1  ->  return y >= 0.1")


@pytest.mark.parametrize("change, text", [
    ('"no gamepad found"  ->  "XXno gamepad foundXX"', True),
    ('f("check the cable", 1)  ->  f("CHECK THE CABLE", 1)', True),
    ('side == "max"  ->  side == "XXmaxXX"', False),  # a name compared somewhere: may be a rule
    ('f("check the cable", 1)  ->  f("check the cable", 2)', False),
    ("x > 0.1  ->  x >= 0.1", False),
])
def test_a_survivor_that_only_changed_a_messages_words_is_told_apart(mutants, change, text):
    assert mutants.is_text_change(change) is text
