"""The student API stays: hri_teleop.student against its committed list (tests/unit/student_api.yaml).

A listed name that leaves the module fails unless it still works with a DeprecationWarning
(hri_teleop.student.DEPRECATED); a name of the module that is not listed fails; a released
version's entries are pinned by their digest, so adding or changing a name takes a new version.
Students' files import nothing else of the toolkit (solutions/ and the generated templates).
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
import types
import warnings
from pathlib import Path
from typing import Any, Dict, List, Optional

import pytest
from student_api_check import breaks, committed, digest, list_problems, module_problems, surface_at, version

import hri_teleop.student as student
from hri_teleop.grading.cases.templates import generate_templates

REPO = Path(__file__).resolve().parents[2]
SOLUTIONS = REPO / "solutions" / "hri_lab"
STUDENT_MODULE = "hri_teleop.student"

# -- the student module against its list ------------------------------------------------------------

def test_the_list_pins_every_released_version():
    assert list_problems(committed()) == []


def test_the_student_module_gives_every_listed_name_as_listed_and_nothing_unlisted():
    assert module_problems(committed(), student) == []


def test_the_version_is_the_newest_listed_and_the_package_says_it():
    newest = max(committed()["versions"], key=version)
    assert student.API_VERSION == student.__version__ == newest
    assert re.fullmatch(r"\d+\.\d+", student.API_VERSION)


def test_the_docstring_lists_each_name_with_what_it_is_for_and_its_version():
    listed = committed()
    doc = student.__doc__ or ""
    assert f"Student API {student.API_VERSION}." in doc
    for name, entry in surface_at(listed, version(student.API_VERSION)).items():
        since = listed["names"][name]["since"]
        line = re.search(rf"^\s+{re.escape(name)}\s+{re.escape(str(since))}\s+(\S.*)$", doc, re.MULTILINE)
        assert line, f"{name}: no line '  {name}  {since}  <what it is for>' in the docstring of hri_teleop.student"
        assert ("deprecated" in line.group(1)) == entry["deprecated"], line.group(0)


def test_the_docs_page_names_each_name_and_the_version():
    page = (REPO / "docs" / "student-api.md").read_text(encoding="utf-8")
    assert f"Student API {student.API_VERSION}" in page
    missing = [n for n in surface_at(committed(), version(student.API_VERSION)) if f"`{n}`" not in page]
    assert missing == []


def test_a_deprecated_name_of_the_student_module_warns_once_per_line_and_gives_the_new_one(monkeypatch):
    monkeypatch.setitem(student.DEPRECATED, "Limiter", ("TwistLimiter", "1.1"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = student.Limiter
    assert value is student.TwistLimiter
    assert [str(w.message) for w in caught] == [
        "hri_teleop.student.Limiter is deprecated since student API 1.1: write "
        "'from hri_teleop.student import TwistLimiter' instead; it goes in 2.0"]
    assert caught[0].filename == __file__  # the line that used it, not the toolkit's


def test_importing_the_student_module_loads_neither_rospy_nor_pygame_until_a_ros_helper_is_used():
    code = ("import sys, hri_teleop.student as s\n"
            "print(sorted(m for m in ('rospy', 'pygame') if m in sys.modules))\n"
            "from hri_teleop.student import get_param, NodeClock, MoveGoal\n"
            "print(sorted(m for m in ('rospy', 'pygame') if m in sys.modules), get_param.__module__,"
            " NodeClock.__module__)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert out.stdout.split("\n")[:2] == ["[]", "['rospy'] hri_teleop.ros.params hri_teleop.ros.clock"]


# -- the checker itself: it catches each way the surface can change ---------------------------------

def _module(**names: Any) -> types.ModuleType:
    module = types.ModuleType("fake_student")
    module.__dict__.update(names)
    module.__dict__.setdefault("__all__", [n for n in names if n not in ("API_VERSION", "DEPRECATED", "__getattr__")])
    return module


def _listed(extra: Optional[Dict[str, Any]] = None) -> Dict[str, Any]:
    names: Dict[str, Any] = {"limit": {"kind": "function", "signature": "(value, top=...)", "since": "1.0"},
                             "RATE_HZ": {"kind": "constant", "signature": "float", "since": "1.0"}}
    names.update(extra or {})
    listed = {"versions": {}, "names": names}
    listed["versions"] = {"1.0": digest(surface_at(listed, (1, 0)))}
    return listed


def limit(value, top=1.0):
    return min(value, top)


def test_the_checker_accepts_a_module_as_listed():
    assert module_problems(_listed(), _module(limit=limit, RATE_HZ=50.0, API_VERSION="1.0")) == []
    assert list_problems(_listed()) == []


def test_the_checker_fails_a_name_removed_or_renamed_without_a_deprecation_path():
    renamed = _module(clamp=limit, RATE_HZ=50.0, API_VERSION="1.0")
    problems = module_problems(_listed(), renamed)
    assert any(p.startswith("limit is gone from fake_student without a deprecation path") for p in problems)
    assert any(p.startswith("clamp is in fake_student.__all__ but not listed") for p in problems)


def _renamed_module(warn: bool) -> types.ModuleType:
    def __getattr__(name: str) -> Any:
        if name == "limit":
            if warn:
                warnings.warn("fake_student.limit is deprecated: write 'from fake_student import clamp'",
                              DeprecationWarning, stacklevel=2)
            return limit
        raise AttributeError(name)
    return _module(clamp=limit, RATE_HZ=50.0, API_VERSION="1.1", DEPRECATED={"limit": ("clamp", "1.1")},
                   __getattr__=__getattr__, __all__=["clamp", "RATE_HZ"])


def _renamed_list() -> Dict[str, Any]:
    listed = _listed()
    listed["names"]["limit"].update(deprecated="1.1", use="clamp")
    listed["names"]["clamp"] = {"kind": "function", "signature": "(value, top=...)", "since": "1.1"}
    listed["versions"]["1.1"] = digest(surface_at(listed, (1, 1)))
    return listed


def test_the_checker_accepts_a_rename_whose_old_name_warns_and_fails_one_that_does_not():
    assert list_problems(_renamed_list()) == []
    assert module_problems(_renamed_list(), _renamed_module(warn=True)) == []
    silent = module_problems(_renamed_list(), _renamed_module(warn=False))
    assert len(silent) == 1 and "must give one one-line DeprecationWarning naming clamp" in silent[0]


def test_the_checker_fails_a_name_added_to_a_released_version_and_prints_the_new_versions_digest():
    listed = _listed()
    listed["names"]["clamp"] = {"kind": "function", "signature": "(value)", "since": "1.0"}
    assert any("the surface of released version 1.0 changed" in p for p in list_problems(listed))
    listed["names"]["clamp"]["since"] = "1.1"
    problems = list_problems(listed)
    assert any(p.startswith("clamp: version 1.1 is not under versions") for p in problems)
    assert any(re.match(r"version 1\.1's digest would be [0-9a-f]{16}$", p) for p in problems)


def test_the_checker_fails_a_changed_signature_and_tells_a_break_from_an_extension():
    def narrower(value):
        return value

    def wider(value, top=1.0, *, bottom=0.0):
        return max(bottom, min(value, top))

    broken = module_problems(_listed(), _module(limit=narrower, RATE_HZ=50.0, API_VERSION="1.0"))
    assert broken and "a break (parameter top is no longer the 2. positional one)" in broken[0]
    extended = module_problems(_listed(), _module(limit=wider, RATE_HZ=50.0, API_VERSION="1.0"))
    assert extended and "a compatible change" in extended[0]
    constant = module_problems(_listed(), _module(limit=limit, RATE_HZ="fast", API_VERSION="1.0"))
    assert constant and constant[0].startswith("RATE_HZ is now constant str")


class Limiter:
    def __init__(self, top=1.0):
        self.top = top

    def step(self, target, dt_s):
        return min(target, self.top)

    @property
    def velocity(self):
        return 0.0


def _with_members() -> Dict[str, Any]:
    listed = _listed({"Limiter": {"kind": "class", "signature": "(top=...)", "since": "1.0",
                                  "members": {"step": "(target, dt_s)", "velocity": "property"}},
                      "make": {"kind": "function", "signature": "()", "since": "1.0", "returns": {"step": "(target, dt_s)"}}})
    listed["versions"]["1.0"] = digest(surface_at(listed, (1, 0)))
    return listed


def make() -> Limiter:
    return Limiter()


class RenamedStep(Limiter):
    step = None


class WiderStep(Limiter):
    def step(self, target, dt_s, *, smooth=False):
        return target


class NarrowerStep(Limiter):
    def step(self, target):
        return target


def make_narrower() -> NarrowerStep:
    return NarrowerStep()


def test_the_checker_fails_a_member_students_use_that_is_gone_or_broken_and_accepts_an_extension():
    fine = _module(limit=limit, RATE_HZ=50.0, Limiter=Limiter, make=make, API_VERSION="1.0")
    assert module_problems(_with_members(), fine) == []
    gone = module_problems(_with_members(), _module(limit=limit, RATE_HZ=50.0, Limiter=RenamedStep, make=make,
                                                    API_VERSION="1.0"))
    assert gone == ["Limiter.step is now attribute, listed (target, dt_s): a break ((target, dt_s) became "
                    "attribute): keep the old form working"]
    assert module_problems(_with_members(), _module(limit=limit, RATE_HZ=50.0, Limiter=WiderStep, make=make,
                                                    API_VERSION="1.0")) == []

    returned = module_problems(_with_members(), _module(limit=limit, RATE_HZ=50.0, Limiter=Limiter,
                                                        make=make_narrower, API_VERSION="1.0"))
    assert returned == ["step of what make returns is now (target), listed (target, dt_s): a break (parameter dt_s "
                        "is no longer the 2. positional one): keep the old form working"]
    listed = _with_members()
    del listed["names"]["Limiter"]["members"]["velocity"]
    assert any("the surface of released version 1.0 changed" in p for p in list_problems(listed))


@pytest.mark.parametrize("old, new, why", [
    ("(value, top=...)", "(value, top=..., *, bottom=...)", ""),
    ("(value, top=...)", "(value, top=..., extra=...)", ""),
    ("(value, top=...)", "(value)", "no longer the 2. positional"),
    ("(value, top=...)", "(value, top)", "lost its default"),
    ("(value, top=...)", "(top=..., value=...)", "no longer the 1. positional"),
    ("(value, *, top=...)", "(value)", "keyword parameter top is gone"),
    ("(value)", "(value, *, top)", "new parameter top has no default"),
    ("(*args, **kwds)", "(*args)", "**kwds is gone"),
    ("float", "int", "a float became a int"),
])
def test_a_signature_break_is_told_from_a_compatible_change(old, new, why):
    found = breaks(old, new)
    assert (why in found and found) if why else found == ""


def test_the_checker_refuses_a_removal_before_the_next_major_version():
    listed = _renamed_list()
    listed["names"]["limit"]["removed"] = "1.2"
    listed["versions"]["1.2"] = digest(surface_at(listed, (1, 2)))
    assert any(p.startswith("limit: removed in 1.2, but a name goes only in the major version")
               for p in list_problems(listed))


# -- students' files import the student module and nothing else of the toolkit ----------------------

def toolkit_imports(source: str) -> List[str]:
    """Every module of the toolkit a Python file imports (``from X import`` and ``import X``, nested too)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom) and node.module == "hri_teleop" and not node.level:
            found += [f"hri_teleop.{alias.name}" for alias in node.names]  # from hri_teleop import student
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            found.append(node.module)
        elif isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
    return [m for m in found if m == "hri_teleop" or m.startswith("hri_teleop.")]


def _foreign_imports(folder: Path) -> Dict[str, List[str]]:
    found = {}
    for path in sorted(folder.rglob("*.py")):
        other = [m for m in toolkit_imports(path.read_text(encoding="utf-8")) if m != STUDENT_MODULE]
        if other:
            found[str(path.relative_to(folder))] = other
    return found


def test_the_answer_key_imports_only_the_student_module():
    assert _foreign_imports(REPO / "solutions") == {}
    assert any(STUDENT_MODULE in toolkit_imports(p.read_text()) for p in (SOLUTIONS / "scripts").glob("*.py"))


def test_the_generated_templates_import_only_the_student_module(tmp_path):
    generate_templates(SOLUTIONS, tmp_path / "hri_lab")
    assert _foreign_imports(tmp_path / "hri_lab") == {}


@pytest.mark.parametrize("source, expected", [
    ("from hri_teleop.core.limits import TwistLimiter\n", ["hri_teleop.core.limits"]),
    ("def f():\n    import hri_teleop.ros.params as p\n", ["hri_teleop.ros.params"]),
    ("from hri_teleop import student\nimport rospy\n", ["hri_teleop.student"]),
    ("import hri_teleop\n", ["hri_teleop"]),
    ("from hri_teleop.student import PadState\nfrom .local import x\n", ["hri_teleop.student"]),
])
def test_a_toolkit_import_is_found_wherever_it_is(source, expected):
    assert toolkit_imports(source) == expected
