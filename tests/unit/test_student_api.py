"""The student API stays: hri_teleop.student against its committed list (tests/unit/student_api.yaml).

A listed name that leaves the module fails unless it still works with a DeprecationWarning
(hri_teleop.student.DEPRECATED); a name of the module that is not listed fails; a released
version's entries are pinned by their digest, so adding or changing a name takes a new version.
Students' files import nothing else of the toolkit (solutions/ and the generated templates).
"""

from __future__ import annotations

import ast
import hashlib
import inspect
import re
import subprocess
import sys
import types
import warnings
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

import pytest
import yaml

import hri_teleop.student as student
from hri_teleop.grading.cases.templates import generate_templates

REPO = Path(__file__).resolve().parents[2]
LISTED = Path(__file__).with_name("student_api.yaml")
SOLUTIONS = REPO / "solutions" / "hri_lab"
STUDENT_MODULE = "hri_teleop.student"

Version = Tuple[int, ...]


def version(text: str) -> Version:
    return tuple(int(part) for part in str(text).split("."))


# -- what a name is -------------------------------------------------------------------------------

def parameters(obj: Any) -> str:
    """A callable's parameters as callers see them: names, order, kinds, which have a default."""
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return "(?)"
    parts: List[str] = []
    starred = False
    for p in signature.parameters.values():
        if p.kind is p.VAR_POSITIONAL:
            parts.append(f"*{p.name}")
            starred = True
        elif p.kind is p.VAR_KEYWORD:
            parts.append(f"**{p.name}")
        else:
            if p.kind is p.KEYWORD_ONLY and not starred:
                parts.append("*")
                starred = True
            parts.append(p.name + ("=..." if p.default is not p.empty else ""))
        if p.kind is p.POSITIONAL_ONLY:
            parts[-1] += "/"
    return "(" + ", ".join(parts) + ")"


def describe(obj: Any) -> Tuple[str, str]:
    """(kind, signature): a class or function with its parameters, an exception with the built-in ones it
    is caught as, a constant with its type."""
    if inspect.isclass(obj) and issubclass(obj, BaseException):
        builtin = [c.__name__ for c in obj.__mro__ if c.__module__ == "builtins"]
        return "exception", ", ".join(n for n in builtin if n not in ("object", "BaseException", "Exception"))
    if inspect.isclass(obj):
        return "class", parameters(obj)
    if callable(obj):
        return "function", parameters(obj)
    return "constant", type(obj).__name__


def _split(signature: str) -> Tuple[List[str], List[str], List[str]]:
    """(positional parameters, keyword-only parameters, ``*args``/``**kwargs``) of a :func:`parameters` text."""
    positional: List[str] = []
    keyword: List[str] = []
    stars: List[str] = []
    starred = False
    for part in [p for p in signature.strip()[1:-1].split(", ") if p]:
        if part.startswith("*"):
            starred = True
            stars += [part] if part != "*" else []
        else:
            (keyword if starred else positional).append(part.rstrip("/"))
    return positional, keyword, stars


def _star(part: str) -> str:
    return "**" if part.startswith("**") else "*"


def breaks(old: str, new: str) -> str:
    """Why a call written for signature ``old`` fails with ``new`` ("" when every such call still works)."""
    if old.startswith("(") is not new.startswith("("):
        return f"{old} became {new}"
    if not old.startswith("("):
        return "" if old == new else f"a {old} became a {new}"
    old_pos, old_kw, old_stars = _split(old)
    new_pos, new_kw, new_stars = _split(new)
    for index, name in enumerate(old_pos):
        if index >= len(new_pos) or new_pos[index].split("=")[0] != name.split("=")[0]:
            return f"parameter {name.split('=')[0]} is no longer the {index + 1}. positional one"
        if name.endswith("=...") and not new_pos[index].endswith("=..."):
            return f"parameter {name.split('=')[0]} lost its default"
    for name in new_pos[len(old_pos):] + [k for k in new_kw if k not in old_kw]:
        if not name.endswith("=...") and not any(name.split("=")[0] == o.split("=")[0] for o in old_kw):
            return f"new parameter {name} has no default"
    for name in old_kw:
        match = [n for n in new_pos + new_kw if n.split("=")[0] == name.split("=")[0]]
        if not match:
            return f"keyword parameter {name.split('=')[0]} is gone"
        if name.endswith("=...") and not match[0].endswith("=..."):
            return f"parameter {name.split('=')[0]} lost its default"
    missing = [s for s in old_stars if _star(s) not in {_star(n) for n in new_stars}]
    return f"{missing[0]} is gone" if missing else ""


# -- the committed list -----------------------------------------------------------------------------

def signature_at(entry: Dict[str, Any], at: Version) -> str:
    changes = sorted((version(v), s) for v, s in (entry.get("changed") or {}).items() if version(v) <= at)
    return changes[-1][1] if changes else str(entry["signature"])


def surface_at(listed: Dict[str, Any], at: Version) -> Dict[str, Dict[str, Any]]:
    """name -> {kind, signature, deprecated, use} of the names version ``at`` gives."""
    found = {}
    for name, entry in listed["names"].items():
        if version(entry["since"]) > at or ("removed" in entry and version(entry["removed"]) <= at):
            continue
        deprecated = "deprecated" in entry and version(entry["deprecated"]) <= at
        found[name] = {"kind": entry["kind"], "signature": signature_at(entry, at), "deprecated": deprecated,
                       "use": entry.get("use", "") if deprecated else ""}
    return found


def digest(surface: Dict[str, Dict[str, Any]]) -> str:
    lines = sorted(f"{n} {e['kind']} {e['signature']} {'deprecated:' + e['use'] if e['deprecated'] else ''}"
                   for n, e in surface.items())
    return hashlib.sha256("\n".join(lines).encode()).hexdigest()[:16]


def list_problems(listed: Dict[str, Any]) -> List[str]:
    """What is wrong with the list itself: edited released versions, versions out of order, bad entries."""
    problems: List[str] = []
    versions = list(listed["versions"])
    if [version(v) for v in versions] != sorted(version(v) for v in versions):
        problems.append(f"versions {versions} are not in ascending order")
    known = set(versions)
    for name, entry in listed["names"].items():
        used = [entry["since"], entry.get("deprecated"), entry.get("removed"), *(entry.get("changed") or {})]
        unknown = [str(v) for v in used if v is not None and str(v) not in known]
        if unknown:
            problems.append(f"{name}: version {unknown[0]} is not under versions: add it with the digest printed "
                            "below and raise hri_teleop.student.API_VERSION")
        if "deprecated" in entry and entry.get("use") not in listed["names"]:
            problems.append(f"{name}: deprecated without 'use: <the listed name to use instead>'")
        if "removed" in entry:
            gone, since = version(entry["removed"]), version(entry.get("deprecated", entry["removed"]))
            if gone[0] <= since[0] or gone[1:] != (0,) * len(gone[1:]):
                problems.append(f"{name}: removed in {entry['removed']}, but a name goes only in the major version "
                                "after the one that deprecated it (e.g. deprecated 1.2, removed 2.0)")
        changes = [str(entry["signature"])] + [s for _, s in sorted((version(v), s) for v, s in
                                                                  (entry.get("changed") or {}).items())]
        for old, new in zip(changes, changes[1:]):
            why = breaks(old, new)
            if why:
                problems.append(f"{name}: {why} ({old} -> {new}): keep old calls working or deprecate the name")
    for v, pinned in listed["versions"].items():
        found = digest(surface_at(listed, version(v)))
        if found != pinned:
            problems.append(f"the surface of released version {v} changed (digest {found}, pinned {pinned}): "
                            "never edit a released version; list the change under a new version "
                            "(see the head of tests/unit/student_api.yaml)")
    used = {str(v) for e in listed["names"].values()
            for v in [e["since"], e.get("deprecated"), e.get("removed"), *(e.get("changed") or {})] if v is not None}
    for v in sorted(used - known, key=version):
        problems.append(f"version {v}'s digest would be {digest(surface_at(listed, version(v)))}")
    return problems


def module_problems(listed: Dict[str, Any], module: types.ModuleType) -> List[str]:
    """Where ``module`` differs from the list's newest version: gone, changed, unlisted, not warning."""
    problems: List[str] = []
    newest = max(listed["versions"], key=version)
    if getattr(module, "API_VERSION", None) != newest:
        problems.append(f"{module.__name__}.API_VERSION is {getattr(module, 'API_VERSION', None)!r}, the list's "
                        f"newest version {newest!r}: raise one of them to the other")
    surface = surface_at(listed, version(newest))
    exported = list(getattr(module, "__all__", []))
    deprecated_table: Dict[str, Tuple[str, str]] = getattr(module, "DEPRECATED", {})
    for name, entry in sorted(surface.items()):
        if entry["deprecated"]:
            problems += _alias_problems(module, name, entry["use"], exported)
            continue
        if name not in exported or not hasattr(module, name):
            fix = (f"keep it, or list it as deprecated (use: <new name>) and add it to {module.__name__}.DEPRECATED "
                   "so the old name keeps working with a DeprecationWarning")
            problems.append(f"{name} is gone from {module.__name__} without a deprecation path: {fix}")
            continue
        kind, signature = describe(getattr(module, name))
        if (kind, signature) != (entry["kind"], entry["signature"]):
            why = breaks(entry["signature"], signature) if kind == entry["kind"] else f"a {entry['kind']} became a {kind}"
            problems.append(f"{name} is now {kind} {signature}, listed {entry['kind']} {entry['signature']}: "
                            + (f"a break ({why}): keep the old form working" if why else
                               "a compatible change: list it under changed: with a new version"))
    for name in exported:
        if name not in surface or surface[name]["deprecated"]:
            problems.append(f"{name} is in {module.__name__}.__all__ but not listed: list it in "
                            "tests/unit/student_api.yaml with since: <a new version> and raise API_VERSION")
    for name in deprecated_table:
        if name not in surface or not surface[name]["deprecated"]:
            problems.append(f"{name} is in {module.__name__}.DEPRECATED but not listed as deprecated")
    gone = [n for n, e in listed["names"].items() if n not in surface and version(e["since"]) <= version(newest)]
    problems += [f"{name} was removed but {module.__name__} still gives it" for name in gone
                 if name in exported or name in deprecated_table]
    return problems


def _alias_problems(module: types.ModuleType, name: str, use: str, exported: List[str]) -> List[str]:
    if name in exported:
        return [f"{name} is deprecated but still in {module.__name__}.__all__: take it out of __all__"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            value = getattr(module, name)
        except AttributeError:
            return [f"{name} is deprecated but gone: it must keep working until the next major version"]
    said = [w for w in caught if issubclass(w.category, DeprecationWarning) and use in str(w.message)]
    if len(said) != 1 or "\n" in str(said[0].message):
        return [f"{module.__name__}.{name} must give one one-line DeprecationWarning naming {use}, gave "
                f"{[str(w.message) for w in caught]}"]
    if value is not getattr(module, use, None):
        return [f"{module.__name__}.{name} is not {use}"]
    return []


def committed() -> Dict[str, Any]:
    data: Dict[str, Any] = yaml.safe_load(LISTED.read_text(encoding="utf-8"))
    data["versions"] = {str(k): str(v) for k, v in data["versions"].items()}
    return data


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
