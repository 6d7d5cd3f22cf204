"""The toolkit's modules import each other without circles: every import counts, those inside
functions and under TYPE_CHECKING too (they hide a circle, they do not remove it). A package's
``__init__`` that re-exports its modules is not a circle with them."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Dict, List, Set

REPO = Path(__file__).resolve().parents[2]
PACKAGE = REPO / "hri_teleop"


def _architecture_tool():
    """tools/architecture.py, which draws docs/architecture.md from the same graph."""
    spec = importlib.util.spec_from_file_location("_tools_architecture", REPO / "tools" / "architecture.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


ARCHITECTURE = _architecture_tool()


def import_graph() -> Dict[str, Set[str]]:
    """Module -> the toolkit's modules it imports anywhere in its text (tools/architecture.py)."""
    return ARCHITECTURE.import_graph(PACKAGE)


def circles(graph: Dict[str, Set[str]]) -> List[List[str]]:
    """The strongly connected groups of more than one module (Tarjan)."""
    index: Dict[str, int] = {}
    low: Dict[str, int] = {}
    stack: List[str] = []
    found: List[List[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for other in sorted(graph[node]):
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            group = []
            while True:
                member = stack.pop()
                group.append(member)
                if member == node:
                    break
            if len(group) > 1:
                found.append(sorted(group))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def test_the_toolkit_has_no_import_circles():
    graph = import_graph()
    assert len(graph) > 90 and "hri_teleop.grading.batch.nbgrader_batch" in graph["hri_teleop.apps.grade"]
    assert circles(graph) == []


def test_a_circle_through_a_function_level_import_is_found():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert circles(graph) == [["a", "b", "c"]]
