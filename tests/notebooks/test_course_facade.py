"""The notebooks import the course's facade and nothing else of the toolkit, and the facade stays small."""

from __future__ import annotations

import ast
import importlib
import json
import re
from pathlib import Path
from typing import List, Tuple

import pytest

import hri_teleop.course as course
from hri_teleop.core.paths import NOTEBOOKS

ALL_NOTEBOOKS = sorted((NOTEBOOKS / "source").glob("*/*.ipynb")) + sorted((NOTEBOOKS / "experiment").glob("*.ipynb"))
NAMESPACES = ("lab", "check", "sim", "widgets", "experiment")


def toolkit_imports(source: str) -> List[Tuple[str, List[str]]]:
    """(module, names) of every import of ``hri_teleop`` in a cell's Python (shell lines left out)."""
    python = "\n".join(line[:len(line) - len(line.lstrip())] + "pass" if line.lstrip().startswith(("!", "%")) else line
                       for line in source.splitlines())
    found = []
    for node in ast.walk(ast.parse(python)):
        if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "hri_teleop":
            found.append((node.module or "", [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            found += [(a.name, []) for a in node.names if a.name.split(".")[0] == "hri_teleop"]
    return found


def facade_problems(source: str) -> List[str]:
    """What a cell imports of the toolkit beyond ``from hri_teleop.course import <facade names>``."""
    problems = []
    for module, names in toolkit_imports(source):
        if module != "hri_teleop.course":
            problems.append(f"imports {module}")
        else:
            problems += [f"imports {name}, which the facade does not offer" for name in names
                         if name not in course.__all__]
    return problems


@pytest.mark.parametrize("path", ALL_NOTEBOOKS, ids=lambda p: p.name)
def test_a_notebook_imports_only_the_course_facade(path: Path):
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    problems = [f"cell {k}: {p}" for k, cell in enumerate(cells) if cell["cell_type"] == "code"
                for p in facade_problems("".join(cell["source"]))]
    assert problems == []


def test_the_notebooks_use_every_name_of_the_facade():
    text = "\n".join(p.read_text(encoding="utf-8") for p in ALL_NOTEBOOKS)
    unused = [name for name in course.__all__ if not re.search(rf"\b{name}\b", text)]
    assert unused == []


def test_the_facade_is_about_ten_names_and_each_resolves():
    assert len(course.__all__) <= 12
    for name in course.__all__:
        assert getattr(course, name) is not None


@pytest.mark.parametrize("namespace", NAMESPACES)
def test_every_name_a_namespace_offers_exists(namespace: str):
    module = importlib.import_module(f"hri_teleop.course.{namespace}")
    assert module.__all__ and all(hasattr(module, name) for name in module.__all__)


#: The pages a student, an instructor or a lab engineer reads: a name they show is offered too.
USER_DOCS = [NOTEBOOKS.parent / "README.md", NOTEBOOKS / "README.md", NOTEBOOKS / "bundle" / "README.md",
             *sorted((NOTEBOOKS.parent / "docs").glob("*.md"))]


def unused_names(namespace: str, offered: List[str], notebooks: str, docs: str) -> List[str]:
    """The names ``namespace`` offers that no notebook and no user page writes as ``namespace.name``."""
    return [name for name in offered if not re.search(rf"\b{namespace}\.{name}\b", notebooks + "\n" + docs)]


@pytest.mark.parametrize("namespace", NAMESPACES)
def test_each_namespace_offers_only_what_the_notebooks_or_the_user_docs_use(namespace: str):
    module = importlib.import_module(f"hri_teleop.course.{namespace}")
    notebooks = "\n".join("".join(cell["source"]) for path in ALL_NOTEBOOKS
                          for cell in json.loads(path.read_text(encoding="utf-8"))["cells"])
    docs = "\n".join(path.read_text(encoding="utf-8") for path in USER_DOCS if path.is_file())
    assert unused_names(namespace, list(module.__all__), notebooks, docs) == []


def test_a_name_nobody_uses_is_found():
    assert unused_names("widgets", ["LivePlot", "FigureView"], "plot = widgets.LivePlot()", "") == ["FigureView"]
    assert unused_names("widgets", ["Doctor"], "", "`widgets.Doctor()` in a cell") == []
    assert unused_names("lab", ["mode"], "widgets.mode", "") == ["mode"]


def test_an_unknown_name_of_the_facade_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'grade_mapping_node'"):
        course.grade_mapping_node  # noqa: B018 - the lookup is the test


@pytest.mark.parametrize("source, expected", [
    ("from hri_teleop.course import lab, check\n", []),
    ("from hri_teleop.grading import grade_graph\n", ["imports hri_teleop.grading"]),
    ("from hri_teleop.course import score\n", ["imports score, which the facade does not offer"]),
    ("import hri_teleop.sim.lab\n", ["imports hri_teleop.sim.lab"]),
    ("def f():\n    from hri_teleop.course.widgets import LivePlot\n", ["imports hri_teleop.course.widgets"]),
    ("!rostopic list\nimport yaml\n", []),
])
def test_an_import_beside_the_facade_is_found(source: str, expected: List[str]):
    assert facade_problems(source) == expected
