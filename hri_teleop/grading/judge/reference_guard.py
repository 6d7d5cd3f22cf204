"""A student file that uses the lab's reference rules fails its check: writing the rule is the exercise.

The lab PCs and the grader have the toolkit installed, with ``hri_teleop.core.mapping`` (Ex. 5),
``hri_teleop.core.teleop`` (Ex. 8), ``hri_teleop.core.paramfile`` (Ex. 4, 11) and the grader. A file
that reaches them (an import, an attribute of ``hri_teleop`` or of a module imported under another
name, a module name in a string for ``importlib``) or imports a rule's name (from ``hri_teleop.student``
too) is refused with that line and what to write instead. The templates' given code imports
``hri_teleop.student`` (docs/student-api.md), which stays allowed.
"""

from __future__ import annotations

import ast
import gc
import threading
from typing import Dict, List

__all__ = ["REFERENCE_MODULES", "REFERENCE_NAMES", "reference_uses", "refusal"]

#: module -> what of the exercises it holds
REFERENCE_MODULES: Dict[str, str] = {
    "hri_teleop.core.mapping": "Ex. 5's mapping rule",
    "hri_teleop.core.teleop": "Ex. 8's teleoperation rules",
    "hri_teleop.core.paramfile": "the lab's parameter files",
    "hri_teleop.grading": "the grader",
    "hri_teleop.sim.lab": "the lab's reference nodes, simulated",
    # last term's paths of the same (hri_teleop.mapping is a shim of the student API again)
    "hri_teleop.mapping": "Ex. 5's mapping rule",
    "hri_teleop.teleop": "Ex. 8's teleoperation rules",
    "hri_teleop.paramfile": "the lab's parameter files",
}
#: names of the reference rules, wherever they are taken from
REFERENCE_NAMES = frozenset({"map_force", "TeleopController", "TeleopCommand"})


def _module_hit(name: str) -> str:
    for module in REFERENCE_MODULES:
        if name == module or name.startswith(module + "."):
            return module
    return ""


def _dotted(node: ast.Attribute, aliases: Dict[str, str]) -> str:
    """``a.b.c`` for an attribute chain on a plain name (an imported module's name resolved), else ``""``."""
    parts = [node.attr]
    value = node.value
    while isinstance(value, ast.Attribute):
        parts.append(value.attr)
        value = value.value
    if not isinstance(value, ast.Name):
        return ""
    return ".".join([aliases.get(value.id, value.id), *reversed(parts)])


def _import_aliases(tree: ast.AST) -> Dict[str, str]:
    """Each name an import binds to a toolkit module -> that module (``import hri_teleop.core as c``: c)."""
    aliases: Dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.asname and alias.name.startswith("hri_teleop"):
                    aliases[alias.asname] = alias.name
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("hri_teleop"):
            for alias in node.names:
                aliases[alias.asname or alias.name] = f"{node.module}.{alias.name}"
    return aliases


def _attribute_hit(dotted: str) -> str:
    """The reference module or rule an attribute chain reaches, or ``""``."""
    if _module_hit(dotted):
        return _module_hit(dotted)
    parts = dotted.split(".")
    return dotted if parts[0] == "hri_teleop" and REFERENCE_NAMES & set(parts[1:]) else ""


#: one parse at a time: the collector's pause below must not be undone by another check's parse
_PARSE_LOCK = threading.Lock()


def _parse_alone(source: str) -> ast.Module:
    """``ast.parse`` that no other thread's parse can interleave with, as checks run side by side.

    Python 3.11's ast keeps one recursion counter for all threads; a finalizer run by the collector
    mid-parse hands the GIL to another thread, whose parse resets the counter, and the first one
    fails with ``SystemError: AST constructor recursion depth mismatch``. With the collector paused
    nothing but the parse runs until it returns.
    """
    with _PARSE_LOCK:
        collecting = gc.isenabled()
        gc.disable()
        try:
            return ast.parse(source)
        finally:
            if collecting:
                gc.enable()


def reference_uses(source: str) -> List[str]:
    """``line N: <what>`` for every use of a reference module or rule in a Python file's text."""
    try:
        tree = _parse_alone(source)
    except SyntaxError:
        return []  # the check reports the syntax error itself
    hits: List[str] = []
    aliases = _import_aliases(tree)
    for node in ast.walk(tree):
        line = getattr(node, "lineno", 0)
        if isinstance(node, ast.Import):
            hits += [f"line {line}: import {a.name}" for a in node.names if _module_hit(a.name)]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [a.name for a in node.names]
            full = [f"{node.module}.{n}" for n in names]
            if _module_hit(node.module) or any(_module_hit(f) for f in full) or REFERENCE_NAMES & set(names):
                hits.append(f"line {line}: from {node.module} import {', '.join(names)}")
        elif isinstance(node, ast.Attribute) and _attribute_hit(_dotted(node, aliases)):
            hits.append(f"line {line}: {_attribute_hit(_dotted(node, aliases))}")
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and _module_hit(node.value.strip()):
            hits.append(f"line {line}: '{node.value.strip()}'")
    return sorted(set(hits), key=lambda h: int(h.split(":")[0].split()[1]))


def refusal(file_label: str, uses: List[str]) -> str:
    """The one-line message for a file that uses the reference (``uses`` from :func:`reference_uses`)."""
    return (f"{file_label} uses the lab's reference implementation ({'; '.join(uses[:3])}): the exercise is to "
            "write that rule yourself; remove the import and write it in your file")
