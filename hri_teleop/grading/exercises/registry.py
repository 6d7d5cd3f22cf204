"""The exercises of :data:`~hri_teleop.grading.deliverables.DELIVERABLE_FILES`, loaded and looked up.

Each module named there (a folder's ``check`` module) is imported by its name and gives its ``EXERCISE``; everything that runs,
counts or reports checks (``checks``, ``points``, ``assignments``, ``batch``, ``gradescope``, the course)
asks here instead of naming an exercise.
"""

from __future__ import annotations

import importlib
from typing import Dict, Tuple

from hri_teleop.grading.deliverables import DELIVERABLE_FILES, key_of
from hri_teleop.grading.exercise import Exercise, PartTable
from hri_teleop.grading.results import GradingError

__all__ = ["exercises", "exercise", "by_file", "checks", "part_tables", "by_assignment"]

_LOADED: Dict[str, Exercise] = {}


def exercises() -> Tuple[Exercise, ...]:
    """Every exercise, in the registry's order."""
    for key in DELIVERABLE_FILES:
        if key not in _LOADED:  # each module is imported once, the first time it is asked for
            module = importlib.import_module(f"{__package__}.{key}")
            if hasattr(module, "__path__"):  # a folder: its check module holds the exercise
                module = importlib.import_module(f"{__package__}.{key}.check")
            found = getattr(module, "EXERCISE", None)
            if not isinstance(found, Exercise) or found.key != key:
                raise GradingError(f"hri_teleop/grading/exercises/{key}: its module must end with "
                                   f"EXERCISE = Exercise(key={key!r}, ...) (docs/adding-an-exercise.md)")
            _LOADED[key] = found
    return tuple(_LOADED[key] for key in DELIVERABLE_FILES)


def exercise(check: str) -> Exercise:
    """The exercise of a check's name (``mapping-node``; its module's name works too)."""
    for found in exercises():
        if check in (found.check, found.key):
            return found
    raise GradingError(f"unknown check {check!r}; use one of {', '.join(checks())}")


def by_file(sub: str) -> Exercise:
    """The exercise that judges the file at ``sub`` in the package (``scripts/teleoperation.py``)."""
    return exercise(key_of(sub, DELIVERABLE_FILES))


def checks() -> Tuple[str, ...]:
    """Every check's name, in the registry's order."""
    return tuple(found.check for found in exercises())


def part_tables() -> Dict[str, PartTable]:
    """check -> its parts (key -> (name, points))."""
    return {found.check: found.parts for found in exercises()}


def by_assignment() -> Dict[str, Tuple[str, ...]]:
    """assignment -> the checks whose files it grades, in the registry's order."""
    table: Dict[str, Tuple[str, ...]] = {}
    for found in exercises():
        table[found.assignment] = table.get(found.assignment, ()) + (found.check,)
    return table
