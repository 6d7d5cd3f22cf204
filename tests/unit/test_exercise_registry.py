"""The exercises' registry (docs/adding-an-exercise.md): every exercise module is registered and gives its
``EXERCISE``, its points add up to what the course counts, each check has a notebook's check cell, the
notebooks' calls are unique, and an exercise's name lives in its own module or folder plus at most three
other places of ``hri_teleop`` (the registry list, the course's map of check cells, and one more: the
notebook is the third place the guide allows, and it is no module).
"""

from __future__ import annotations

import ast
import importlib
import io
import tokenize
from collections import Counter
from functools import lru_cache
from numbers import Real
from pathlib import Path
from typing import Dict, List, Sequence, Tuple

import pytest

from hri_teleop.grading.exercises.registry import DELIVERABLE_FILES, exercises
from hri_teleop.grading.points import CHECK_CELLS, check_points

REPO = Path(__file__).resolve().parents[2]
PACKAGE = REPO / "hri_teleop"
EXERCISES = PACKAGE / "grading" / "exercises"
#: What of the exercises' folder is no exercise (the Exercise type lived here before it moved up).
NOT_EXERCISES = {"__init__", "exercise", "registry"}
#: The most modules of hri_teleop (its own module or folder aside) that may name an exercise.
MOST_PLACES = 3
def exercise_modules() -> List[str]:
    """The modules and folders under hri_teleop/grading/exercises that hold an exercise."""
    found = [p.stem for p in EXERCISES.glob("*.py")] + [p.name for p in EXERCISES.iterdir()
                                                       if p.is_dir() and (p / "__init__.py").is_file()]
    return sorted(set(found) - NOT_EXERCISES)


def test_every_exercise_module_is_registered_and_gives_its_exercise():
    assert exercise_modules() == sorted(DELIVERABLE_FILES), \
        "hri_teleop/grading/exercises and the registry list differ (docs/adding-an-exercise.md, step 2)"
    for key in DELIVERABLE_FILES:
        module = importlib.import_module(f"hri_teleop.grading.exercises.{key}")
        if hasattr(module, "__path__"):  # a folder: its check module ends with the exercise
            module = importlib.import_module(f"hri_teleop.grading.exercises.{key}.check")
        found = getattr(module, "EXERCISE", None)
        assert found is not None and found.key == key, f"{module.__name__}: EXERCISE missing or keyed {found!r}"
    assert [e.key for e in exercises()] == list(DELIVERABLE_FILES)


@pytest.mark.parametrize("key", list(DELIVERABLE_FILES))
def test_an_exercises_parts_carry_numbers_that_add_up_to_its_points(key):
    found = next(e for e in exercises() if e.key == key)
    points = [p for _name, p in found.parts.values()]
    assert points and all(isinstance(p, Real) and not isinstance(p, bool) and p >= 0 for p in points), found.parts
    assert sum(points) == found.points == check_points(found.check), (key, found.parts)


def test_every_check_has_a_check_cell_in_a_notebook_of_its_assignment():
    shown = {(c.assignment, c.check) for c in CHECK_CELLS}
    missing = [e.check for e in exercises() if (e.assignment, e.check) not in shown]
    assert missing == [], f"no CHECK_CELLS line (hri_teleop/grading/points.py) for {missing}"


def test_the_notebooks_calls_are_unique_across_exercises():
    calls = Counter(name for e in exercises() for name in e.notebook_calls)
    assert [name for name, count in calls.items() if count > 1] == []
    for found in exercises():
        assert set(found.whole_check_calls) <= set(found.notebook_calls), found.key


# -- where an exercise's name appears -----------------------------------------------------------------

#: The grader's modules that know the exercises (a module importing one of these reads the checks); the kit
#: below them (run/, judge/, cases/) knows none, and a course module that only starts ROS nodes through the kit
#: names a node ("teleoperation", "mapping_node"), not an exercise.
GRADER_ABOVE_THE_KIT = ("hri_teleop.grading.exercises", "hri_teleop.grading.checks", "hri_teleop.grading.points",
                        "hri_teleop.grading.assignments", "hri_teleop.grading.deliverables", "hri_teleop.grading.batch",
                        "hri_teleop.grading.gradescope")


def _reads_the_exercises(module: str, names: Sequence[str] = ()) -> bool:
    if module == "hri_teleop.grading":
        return True  # the grader's facade: grade, check, CHECKS
    return any(module == top or module.startswith(top + ".") for top in GRADER_ABOVE_THE_KIT)


def _imports_grading(tree: ast.AST) -> bool:
    for node in ast.walk(tree):
        if isinstance(node, ast.Import) and any(_reads_the_exercises(a.name) for a in node.names):
            return True
        if isinstance(node, ast.ImportFrom) and node.module and (
                _reads_the_exercises(node.module)
                or (node.module == "hri_teleop" and any(a.name == "grading" for a in node.names))):
            return True
    return False


#: One module as the count reads it: (its path relative to the repository, its NAME tokens and STRING tokens'
#: values as (line, text, value), the modules it imports as (line, what the line says, module, names)).
Scanned = Tuple[str, Tuple[Tuple[int, str, str], ...], Tuple[Tuple[int, str, str, Tuple[str, ...]], ...]]


def scan(relative: str, text: str) -> Scanned:
    tokens = []
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type == tokenize.NAME:
            tokens.append((token.start[0], token.string, token.string))
        elif token.type == tokenize.STRING:
            try:
                value = ast.literal_eval(token.string)
            except (ValueError, SyntaxError):  # an f-string: a format, no name
                continue
            if isinstance(value, str):
                tokens.append((token.start[0], token.string, "\0" + value))
    imports = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            imports += [(node.lineno, f"import {a.name}", a.name, ()) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = tuple(a.name for a in node.names)
            imports.append((node.lineno, f"from {node.module} import {', '.join(names)}", node.module, names))
    return relative, tuple(tokens), tuple(imports)


@lru_cache(maxsize=None)
def scanned_modules() -> Tuple[Scanned, ...]:
    """hri_teleop/grading/** and every other module of hri_teleop that imports the grader above its kit, scanned."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        text = path.read_text(encoding="utf-8")
        relative = path.relative_to(REPO).as_posix()
        if relative.startswith("hri_teleop/grading/") or _imports_grading(ast.parse(text)):
            found.append(scan(relative, text))
    return tuple(found)


def name_places(key: str, modules: Sequence[Scanned]) -> Dict[str, List[str]]:
    """module -> where it names exercise ``key`` (line: what), its own module or folder left out: NAME tokens
    equal to the key, ``grade_<key>`` or ``<KEY>``; strings whose value is the key or the check's name;
    imports of ``hri_teleop.grading.exercises.<key>``."""
    check = key.replace("_", "-")
    wanted = {key, f"grade_{key}", key.upper(), "\0" + key, "\0" + check}
    path = f"hri_teleop.grading.exercises.{key}"
    own = (f"hri_teleop/grading/exercises/{key}.py", f"hri_teleop/grading/exercises/{key}/")
    places: Dict[str, List[str]] = {}
    for relative, tokens, imports in modules:
        if relative == own[0] or relative.startswith(own[1]):
            continue
        hits = [f"{line}: {text}" for line, text, value in tokens if value in wanted]
        hits += [f"{line}: {said}" for line, said, module, names in imports
                 if module == path or module.startswith(path + ".")
                 or (module == "hri_teleop.grading.exercises" and key in names)]
        if hits:
            places[relative] = hits
    return places


def _shown(places: Dict[str, List[str]]) -> str:
    return "\n".join(f"  {module}: {', '.join(hits[:8])}{' ...' if len(hits) > 8 else ''}"
                     for module, hits in places.items())


@pytest.mark.parametrize("key", list(DELIVERABLE_FILES))
def test_an_exercises_name_appears_in_at_most_three_modules_besides_its_own(key):
    places = name_places(key, scanned_modules())
    message = (f"{key} is named in {len(places)} modules of hri_teleop besides its own (at most {MOST_PLACES}: the "
               f"registry list, CHECK_CELLS; docs/adding-an-exercise.md):\n{_shown(places)}")
    print(message)
    assert len(places) <= MOST_PLACES, message


def test_the_count_finds_names_strings_and_imports_and_leaves_the_own_folder_out():
    modules = (
        ("hri_teleop/grading/exercises/lab_notes.py", "EXERCISE = 'lab_notes'\n"),
        ("hri_teleop/grading/exercises/other/check.py", "from hri_teleop.grading.exercises.lab_notes import PARTS\n"),
        ("hri_teleop/grading/points.py", "CHECK = ('lab-notes', f'{x}lab_notes', 'lab_notes.yaml')\n"),
        ("hri_teleop/grading/checks.py", "LAB_NOTES = grade_lab_notes\nlab_notes_table = 1\n"),
        ("hri_teleop/course/check.py", "from hri_teleop.grading.exercises import lab_notes\n"),
        ("hri_teleop/grading/exercises/lab_notes_x/check.py", "x = 'lab_notes'\n"),
    )
    places = name_places("lab_notes", [scan(relative, text) for relative, text in modules])
    assert places == {
        "hri_teleop/grading/exercises/other/check.py": ["1: lab_notes",
                                                        "1: from hri_teleop.grading.exercises.lab_notes import PARTS"],
        "hri_teleop/grading/points.py": ["1: 'lab-notes'"],
        "hri_teleop/grading/checks.py": ["1: LAB_NOTES", "1: grade_lab_notes"],
        "hri_teleop/course/check.py": ["1: lab_notes", "1: from hri_teleop.grading.exercises import lab_notes"],
        "hri_teleop/grading/exercises/lab_notes_x/check.py": ["1: 'lab_notes'"],
    }, places
