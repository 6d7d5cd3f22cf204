"""The layers are folders, and each imports only the layers below it (every import counts, those
inside functions too): core < plots < sim < hardware < ros < grading < course < apps, and student (what students'
files import) on ros, imported by nothing in the package but last term's import paths, thin shims
over it (docs/architecture.md). The core imports no process, socket, thread, ROS, pygame, serial
port or widget: only the standard library, numpy and yaml."""

from __future__ import annotations

import ast
import sys
from typing import Dict, Iterator, List, Set, Tuple

import pytest
from test_import_graph import PACKAGE, import_graph

#: layer -> the layers its modules may import (itself included).
ALLOWED: Dict[str, Set[str]] = {
    "core": {"core"},
    "plots": {"core", "plots"},
    "sim": {"core", "plots", "sim"},
    "hardware": {"core", "hardware", "plots", "sim"},
    "ros": {"core", "hardware", "plots", "ros", "sim"},
    "grading": {"core", "hardware", "plots", "ros", "sim", "grading"},
    "course": {"core", "hardware", "plots", "ros", "sim", "grading", "course"},
    "student": {"core", "hardware", "plots", "ros", "sim", "student"},
    # every command a person types: above every library, imported by none (test below)
    "apps": {"core", "hardware", "plots", "ros", "sim", "grading", "course", "student", "apps"},
}
#: Last term's import paths (docs/student-api.md): shims of the student API until its version 2.0,
#: outside the layer folders because that is where last term's templates looked; each imports only the student API.
OLD_PATHS: Dict[str, Set[str]] = {name: {"student"} for name in ("gamepad", "limits", "mapping", "sensor_profile",
                                                                 "gripper")}
#: Standard-library modules the core must not use: they start processes, threads or talk to the network.
CORE_FORBIDDEN_STDLIB = {"subprocess", "socket", "threading", "multiprocessing", "asyncio", "signal", "ctypes",
                         "concurrent", "xmlrpc", "http", "urllib", "tkinter", "atexit"}
CORE_THIRD_PARTY = {"numpy", "yaml"}


def layer_of(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def layer_violations(graph: Dict[str, Set[str]]) -> List[Tuple[str, str]]:
    """(importer, imported) pairs where a module imports a layer above its own (or the package root)."""
    bad = []
    for name, targets in sorted(graph.items()):
        allowed = {**ALLOWED, **OLD_PATHS}.get(layer_of(name))
        if allowed is None:
            continue
        bad += [(name, t) for t in sorted(targets) if layer_of(t) not in allowed]
    return bad


def imported_roots(source: str) -> Iterator[str]:
    """The top-level names of every absolute import in ``source`` (function-level ones too)."""
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            yield from (alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            yield node.module.split(".")[0]


def core_foreign_imports(source: str) -> Set[str]:
    """What a core module imports that the core may not: forbidden stdlib, any other third party."""
    stdlib = set(sys.stdlib_module_names)
    return {root for root in imported_roots(source)
            if root != "hri_teleop" and (root in CORE_FORBIDDEN_STDLIB
                                         or (root not in stdlib and root not in CORE_THIRD_PARTY))}


def test_every_module_lives_in_a_layer_folder():
    loose = {p.stem for p in PACKAGE.glob("*.py") if p.name != "__init__.py"}
    packages = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()}
    assert loose <= set(OLD_PATHS), "a module outside the layer folders: move it into its layer"
    assert packages - set(OLD_PATHS) == set(ALLOWED)
    assert loose | (packages & set(OLD_PATHS)) == set(OLD_PATHS)


def test_each_layer_imports_only_the_layers_below_it():
    graph = import_graph()
    assert any(layer_of(n) == "core" for n in graph)
    assert layer_violations(graph) == []


def test_the_core_imports_only_the_standard_library_numpy_and_yaml():
    found = {}
    for path in sorted((PACKAGE / "core").rglob("*.py")):
        foreign = core_foreign_imports(path.read_text())
        if foreign:
            found[str(path.relative_to(PACKAGE))] = sorted(foreign)
    assert found == {}


@pytest.mark.parametrize("graph, expected", [
    ({"hri_teleop.core.fsr": {"hri_teleop.ros.master"}}, [("hri_teleop.core.fsr", "hri_teleop.ros.master")]),
    ({"hri_teleop.sim.arm": {"hri_teleop.course.nodes"}},
     [("hri_teleop.sim.arm", "hri_teleop.course.nodes")]),
    ({"hri_teleop.plots.study": {"hri_teleop.sim.lab"}},
     [("hri_teleop.plots.study", "hri_teleop.sim.lab")]),
    ({"hri_teleop.apps.trial": {"hri_teleop.core.fsr", "hri_teleop.sim.hand"}}, []),
    ({"hri_teleop.core.teleop": {"hri_teleop.core.limits"}}, []),
    ({"hri_teleop.grading.batch.nbgrader_batch": {"hri_teleop.course.release"}},
     [("hri_teleop.grading.batch.nbgrader_batch", "hri_teleop.course.release")]),
    ({"hri_teleop.course.cells": {"hri_teleop.grading.checks"}}, []),
    ({"hri_teleop.student": {"hri_teleop.ros.params", "hri_teleop.hardware.gamepad"}}, []),
    ({"hri_teleop.student": {"hri_teleop.grading.cases.inputs"}}, [("hri_teleop.student", "hri_teleop.grading.cases.inputs")]),
    ({"hri_teleop.grading.checks": {"hri_teleop.student"}}, [("hri_teleop.grading.checks", "hri_teleop.student")]),
    ({"hri_teleop.limits": {"hri_teleop.student"}, "hri_teleop.gamepad.events": {"hri_teleop.student.deprecation"}}, []),
    ({"hri_teleop.limits": {"hri_teleop.core.limits"}}, [("hri_teleop.limits", "hri_teleop.core.limits")]),
])
def test_an_import_of_a_higher_layer_is_found(graph, expected):
    assert layer_violations(graph) == expected


@pytest.mark.parametrize("source, expected", [
    ("import rospy\n", {"rospy"}),
    ("def f():\n    import subprocess\n", {"subprocess"}),
    ("from pygame import joystick\n", {"pygame"}),
    ("import numpy as np\nimport yaml\nfrom pathlib import Path\nfrom hri_teleop.core import fsr\n", set()),
    ("from threading import Thread\n", {"threading"}),
])
def test_a_foreign_import_in_the_core_is_found(source, expected):
    assert core_foreign_imports(source) == expected


def test_no_library_module_imports_an_app():
    """apps/ holds the commands; a library that needs one's work calls the library the app calls."""
    graph = import_graph()
    assert sorted((name, t) for name, targets in graph.items() if layer_of(name) != "apps"
                  for t in targets if layer_of(t) == "apps") == []
