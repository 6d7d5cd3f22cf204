"""Modules meet through public names: no file imports another module's underscore name, or reaches
into it through the module (``harness._start``). A helper two modules share is public, documented,
in the module that owns it; a name with one underscore stays inside its own module."""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Dict, Iterator, List

import pytest

REPO = Path(__file__).resolve().parents[2]
#: Every folder of the project's own Python (the tests too: they use the same doors).
ROOTS = ["hri_teleop", "hri_lab/scripts", "solutions", "grading", "benchmarks", "tools", "tests", "firmware"]


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _is_project_module(dotted: str) -> bool:
    path = REPO.joinpath(*dotted.split("."))
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


def private_reaches(source: str) -> Iterator[str]:
    """``module.name`` for each underscore name of a project module that ``source`` imports or reads
    through the module."""
    tree = ast.parse(source)
    modules: Dict[str, str] = {}  # local name -> the hri_teleop module it is bound to
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and not node.level:
            for alias in node.names:
                if _private(alias.name) and node.module.startswith("hri_teleop"):
                    yield f"{node.module}.{alias.name}"
                elif node.module.startswith("hri_teleop") and _is_project_module(f"{node.module}.{alias.name}"):
                    modules[alias.asname or alias.name] = f"{node.module}.{alias.name}"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("hri_teleop") and alias.asname:
                    modules[alias.asname] = alias.name
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in modules
                and _private(node.attr)):
            yield f"{modules[node.value.id]}.{node.attr}"


def _python_files() -> List[Path]:
    files: List[Path] = []
    for root in ROOTS:
        folder = REPO / root
        if folder.is_dir():
            files += [p for p in folder.rglob("*.py") if ".venv" not in p.parts and "build" not in p.parts]
    return sorted(files)


def test_no_file_imports_or_reads_another_modules_underscore_name() -> None:
    found = [f"{path.relative_to(REPO)}: {name}" for path in _python_files()
             for name in private_reaches(path.read_text(encoding="utf-8"))]
    assert not found, "private names used across modules (make them public in their owner):\n" + "\n".join(found)


@pytest.mark.parametrize("source, expected", [
    ("from hri_teleop.grading.judge.harness import _start\n", ["hri_teleop.grading.judge.harness._start"]),
    ("def f():\n    from hri_teleop.core.limits import _clip\n", ["hri_teleop.core.limits._clip"]),
    ("from hri_teleop.grading.judge import harness\nharness._reusable('x')\n",
     ["hri_teleop.grading.judge.harness._reusable"]),
    ("import hri_teleop.core.limits as lim\nlim._clip\n", ["hri_teleop.core.limits._clip"]),
    ("from hri_teleop.grading.judge.harness import start_check, __all__\n", []),
    ("from hri_teleop.grading.judge import harness\nharness.start_check\nself._start\n", []),
    ("from os import _exit\n", []),
])
def test_a_reach_into_a_private_name_is_found(source: str, expected: List[str]) -> None:
    assert list(private_reaches(source)) == expected
