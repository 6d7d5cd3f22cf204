"""A student file that uses the lab's reference rules fails its check: writing the rule is the exercise.

The lab PCs and the grader have the toolkit installed, with ``hri_teleop.core.mapping`` (Ex. 5),
``hri_teleop.core.teleop`` (Ex. 8), ``hri_teleop.core.paramfile`` (Ex. 4, 11) and the grader. A file
that reaches them (an import, an attribute of ``hri_teleop``, a module name in a string for
``importlib``) is refused with that line and what to write instead. The templates' given code imports
other modules (``hri_teleop.core.gamepad``, ``hri_teleop.core.limits``), which stay allowed.
"""

from __future__ import annotations

import ast
from typing import Dict, List

__all__ = ["REFERENCE_MODULES", "REFERENCE_NAMES", "reference_uses", "refusal"]

#: module -> what of the exercises it holds
REFERENCE_MODULES: Dict[str, str] = {
    "hri_teleop.core.mapping": "Ex. 5's mapping rule",
    "hri_teleop.core.teleop": "Ex. 8's teleoperation rules",
    "hri_teleop.core.paramfile": "the lab's parameter files",
    "hri_teleop.grading": "the grader",
    "hri_teleop.hardware.sim.lab": "the lab's reference nodes, simulated",
}
#: names of the reference rules, wherever they are taken from
REFERENCE_NAMES = frozenset({"map_force", "TeleopController", "TeleopCommand"})


def _module_hit(name: str) -> str:
    for module in REFERENCE_MODULES:
        if name == module or name.startswith(module + "."):
            return module
    return ""


def _dotted(node: ast.Attribute) -> str:
    """``a.b.c`` for an attribute chain on a plain name, else ``""``."""
    parts = [node.attr]
    value = node.value
    while isinstance(value, ast.Attribute):
        parts.append(value.attr)
        value = value.value
    return ".".join([value.id, *reversed(parts)]) if isinstance(value, ast.Name) else ""


def reference_uses(source: str) -> List[str]:
    """``line N: <what>`` for every use of a reference module or rule in a Python file's text."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return []  # the check reports the syntax error itself
    hits: List[str] = []
    for node in ast.walk(tree):
        line = getattr(node, "lineno", 0)
        if isinstance(node, ast.Import):
            hits += [f"line {line}: import {a.name}" for a in node.names if _module_hit(a.name)]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [a.name for a in node.names]
            full = [f"{node.module}.{n}" for n in names]
            if _module_hit(node.module) or any(_module_hit(f) for f in full) or REFERENCE_NAMES & set(names):
                hits.append(f"line {line}: from {node.module} import {', '.join(names)}")
        elif isinstance(node, ast.Attribute) and _module_hit(_dotted(node)):
            hits.append(f"line {line}: {_module_hit(_dotted(node))}")
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and _module_hit(node.value.strip()):
            hits.append(f"line {line}: '{node.value.strip()}'")
    return sorted(set(hits), key=lambda h: int(h.split(":")[0].split()[1]))


def refusal(file_label: str, uses: List[str]) -> str:
    """The one-line message for a file that uses the reference (``uses`` from :func:`reference_uses`)."""
    return (f"{file_label} uses the lab's reference implementation ({'; '.join(uses[:3])}): the exercise is to "
            "write that rule yourself; remove the import and write it in your file")
