"""Every module of the toolkit, the lab's nodes and the benchmarks opens with a short docstring.

At most 8 lines, blank ones included: the first line says what the module holds, the rest why it
exists. Models, protocols and decisions live in the docstrings of their classes and in docs/. The
student API's docstring is its reference for students and may be longer (REFERENCE_DOCSTRINGS).
"""

from __future__ import annotations

import ast
import re
from pathlib import Path
from typing import List, Optional

import pytest

ROOT = Path(__file__).resolve().parents[2]
MAX_LINES = 8
#: Docstrings that are a reference and may be longer: the student API's lists each name students
#: may import, what it is for and since which version (help(hri_teleop.student) in a student's shell).
REFERENCE_DOCSTRINGS = {"hri_teleop/student/__init__.py": 42}  # one line per name of the student API
FOLDERS = (ROOT / "hri_teleop", ROOT / "hri_lab" / "scripts", ROOT / "benchmarks")
#: A sentence: starts with a capital letter, a digit or a quoted name, and ends on the first line.
SENTENCE = re.compile(r"^[A-Z0-9`\"'].*[.!?]$")


def _modules() -> List[Path]:
    files = sorted(ROOT.glob("hri_teleop/**/*.py")) + sorted((ROOT / "hri_lab" / "scripts").glob("*.py"))
    return files + sorted((ROOT / "benchmarks").glob("*.py"))


def docstring_problem(source: str, max_lines: int = MAX_LINES) -> Optional[str]:
    """What is wrong with the module docstring of ``source``, or None when it is short and opens with a sentence."""
    doc = ast.get_docstring(ast.parse(source), clean=False)
    if not doc:
        return "no module docstring"
    lines = doc.splitlines()
    if len(lines) > max_lines:
        return f"module docstring of {len(lines)} lines (at most {max_lines})"
    if not SENTENCE.match(lines[0]):
        return f"first line is not one sentence: {lines[0]!r}"
    return None


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(ROOT)))
def test_module_docstring_is_short_and_opens_with_a_sentence(path: Path):
    relative = path.relative_to(ROOT).as_posix()
    problem = docstring_problem(path.read_text(encoding="utf-8"), REFERENCE_DOCSTRINGS.get(relative, MAX_LINES))
    assert problem is None, f"{relative}: {problem}"


def test_every_folder_has_modules():
    found = _modules()
    for folder in FOLDERS:
        assert any(folder in path.parents for path in found), folder


def test_the_check_catches_long_docstrings_and_missing_sentences():
    nine = '"""One line that says what.\n\n3\n4\n5\n6\n7\n8\n9\n"""\nX = 1\n'
    eight = '"""One line that says what.\n\n3\n4\n5\n6\n7\n8\n"""\nX = 1\n'
    assert docstring_problem(nine) == "module docstring of 9 lines (at most 8)"
    assert docstring_problem(eight) is None
    assert docstring_problem("X = 1\n") == "no module docstring"
    assert docstring_problem('"""the first line runs on\ninto the second."""\n').startswith("first line")
