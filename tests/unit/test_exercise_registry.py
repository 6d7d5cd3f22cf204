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


# -- the registry's rules, each run afresh (the course's modules load it once at import) ------------------------

def _fake_module(monkeypatch, name: str, exercise_value=None, folder: bool = False) -> None:
    """hri_teleop.grading.exercises.<name> in sys.modules: a module (or a folder with its check module) ending
    with ``exercise_value`` (None: no EXERCISE at all)."""
    import sys
    import types

    full = f"hri_teleop.grading.exercises.{name}"
    module = types.ModuleType(full)
    target = module
    if folder:
        module.__path__ = []  # a package
        target = types.ModuleType(full + ".check")
        monkeypatch.setitem(sys.modules, full + ".check", target)
    if exercise_value is not None:
        target.EXERCISE = exercise_value
    monkeypatch.setitem(sys.modules, full, module)


def _made_up(key: str, assignment: str = "lab"):
    from hri_teleop.grading.exercise import Exercise
    from hri_teleop.grading.results import CheckResult

    def grade(path, **kwargs):
        return CheckResult(key.replace("_", "-"), str(path), [], None)

    return Exercise(key=key, handout="Ex. 99", assignment=assignment, parts={"one": ("one thing", 1)}, grade=grade)


@pytest.fixture
def fresh_registry(monkeypatch):
    """The registry with nothing loaded and a list of ``files`` the test sets (registry.DELIVERABLE_FILES)."""
    from hri_teleop.grading.exercises import registry

    monkeypatch.setattr(registry, "_LOADED", {})
    return registry


def test_the_registry_loads_each_exercise_from_its_module_or_its_folders_check_module_once(fresh_registry, monkeypatch):
    one, two = _made_up("made_one"), _made_up("made_two")
    _fake_module(monkeypatch, "made_one", one)
    _fake_module(monkeypatch, "made_two", two, folder=True)
    monkeypatch.setattr(fresh_registry, "DELIVERABLE_FILES", {"made_one": "a.yaml", "made_two": "b.yaml"})
    assert fresh_registry.exercises() == (one, two)
    imported = []
    monkeypatch.setattr(fresh_registry.importlib, "import_module", lambda name: imported.append(name))
    assert fresh_registry.exercises() == (one, two) and imported == []  # loaded once, then kept


def test_the_registry_keeps_its_lists_order_not_the_loading_order(fresh_registry, monkeypatch):
    one, two = _made_up("made_one"), _made_up("made_two")
    _fake_module(monkeypatch, "made_one", one)
    _fake_module(monkeypatch, "made_two", two)
    monkeypatch.setattr(fresh_registry, "DELIVERABLE_FILES", {"made_two": "b.yaml", "made_one": "a.yaml"})
    fresh_registry._LOADED["made_one"] = one  # loaded earlier, under the other order
    assert fresh_registry.exercises() == (two, one)


@pytest.mark.parametrize("value", [None, "EXERCISE as a string", "other_key"], ids=["none", "no exercise", "other key"])
def test_a_module_that_does_not_end_with_its_own_exercise_is_refused_in_one_line(fresh_registry, monkeypatch, value):
    given = _made_up("other_key") if value == "other_key" else value
    _fake_module(monkeypatch, "made_bad", given)
    monkeypatch.setattr(fresh_registry, "DELIVERABLE_FILES", {"made_bad": "c.yaml"})
    from hri_teleop.grading.results import GradingError

    with pytest.raises(GradingError) as info:
        fresh_registry.exercises()
    assert str(info.value) == ("hri_teleop/grading/exercises/made_bad: its module must end with EXERCISE = "
                               "Exercise(key='made_bad', ...) (docs/adding-an-exercise.md)")
    assert "made_bad" not in fresh_registry._LOADED


def test_an_exercise_is_found_by_its_check_its_module_or_its_file_and_an_unknown_one_is_named(fresh_registry,
                                                                                               monkeypatch):
    one, two = _made_up("made_one", "preparation"), _made_up("made_two")
    _fake_module(monkeypatch, "made_one", one)
    _fake_module(monkeypatch, "made_two", two)
    monkeypatch.setattr(fresh_registry, "DELIVERABLE_FILES", {"made_one": "config/a.yaml", "made_two": ""})
    assert fresh_registry.exercise("made-one") is one and fresh_registry.exercise("made_two") is two
    assert fresh_registry.by_file("config/a.yaml") is one
    assert fresh_registry.checks() == ("made-one", "made-two")
    assert fresh_registry.part_tables() == {"made-one": one.parts, "made-two": two.parts}
    from hri_teleop.grading.results import GradingError

    with pytest.raises(GradingError, match=r"^unknown check 'made-three'; use one of made-one, made-two$"):
        fresh_registry.exercise("made-three")
    with pytest.raises(GradingError, match=r"^config/b.yaml is no deliverable of the course"):
        fresh_registry.by_file("config/b.yaml")
    with pytest.raises(GradingError):
        fresh_registry.by_file("")  # the package's own check judges no file: no file names it


def test_the_course_files_keys_are_found_by_their_path_in_the_package_and_no_key_by_the_packages_own_check():
    from hri_teleop.grading.deliverables import key_of
    from hri_teleop.grading.results import GradingError

    assert key_of("scripts/mapping_node.py") == "mapping_node"
    assert key_of("launch/teleoperation.launch") == "teleoperation_launch"
    assert key_of("config/a.yaml", {"made_one": "", "made_two": "config/a.yaml"}) == "made_two"
    for sub in ("", "mapping_node.py", "scripts/mapping_node.py/"):
        with pytest.raises(GradingError, match=f"^{sub} is no deliverable of the course "
                                               r"\(hri_teleop/grading/exercises lists them\)$"):
            key_of(sub)


def test_each_assignment_lists_its_checks_in_the_registrys_order(fresh_registry, monkeypatch):
    made = [_made_up("made_a", "lab"), _made_up("made_b", "preparation"), _made_up("made_c", "lab")]
    for found in made:
        _fake_module(monkeypatch, found.key, found)
    monkeypatch.setattr(fresh_registry, "DELIVERABLE_FILES", {found.key: "" for found in made})
    assert fresh_registry.by_assignment() == {"lab": ("made-a", "made-c"), "preparation": ("made-b",)}


def test_the_course_assignments_take_their_checks_from_the_exercises():
    from hri_teleop.grading.assignments import ASSIGNMENT_CHECKS
    from hri_teleop.grading.exercises import registry

    assert ASSIGNMENT_CHECKS == {"preparation": ("robot-params", "mapping-node", "sensor-launch"),
                                 "lab": ("teleoperation", "teleoperation-launch", "graph", "catkin-package")}
    assert registry.by_assignment() == ASSIGNMENT_CHECKS


def test_an_exercises_call_runs_its_check_with_what_it_is_given():
    seen = []
    from hri_teleop.grading.exercise import Exercise
    from hri_teleop.grading.results import CheckResult

    def grade(path, **kwargs):
        seen.append((path, kwargs))
        return CheckResult("made-one", str(path), [], None)

    found = Exercise(key="made_one", handout="Ex. 99", assignment="lab", parts={}, grade=grade)
    assert found.call("pkg", seed=3).check == "made-one" and seen == [("pkg", {"seed": 3})]
