"""The student distribution: ``out/task4-student-bundle.tar.gz`` as ``make release`` packs it.

Why a module of its own: what a student installs must hold no answer, and that is decided
here in one place. The bundle is the released notebooks and templates, a ``README.md`` and a
``Makefile`` (``make setup``, ``make lab``, ``make check``), and ``toolkit/``: a copy of this
project without instructor material -- no answer key, no tests, no benchmarks, and the lab's
``hri_lab`` without the files students write (:data:`LAB_DELIVERABLES`). Only the handout's
provided nodes and sketch, the simulation, the trials' analysis and what the notebooks read remain.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import tarfile
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

from hri_teleop.core.paths import NOTEBOOKS, REPO, SOLUTIONS
from hri_teleop.grading.cases.templates import (
    has_markers,
    kind_of,
    make_answer,
    make_template,
    solution_lines,
)

__all__ = ["TOOLKIT_FILES", "LAB_DELIVERABLES", "INSTRUCTOR_ONLY", "BUNDLE_FILES", "build_toolkit",
           "BUNDLE_TOP", "assemble_bundle", "pack_bundle", "deliverable_copies", "toolkit_leaks", "answer_files", "solution_texts",
           "bundle_leaks", "distinctive", "read_notebook"]

PathLike = Union[str, Path]
#: the bundle's own README.md and Makefile (committed; copied into the bundle's top folder)
BUNDLE_FILES = REPO / "notebooks" / "bundle"

#: the bundle's top files: its commands, its README, and the container (make image, docker compose, a devcontainer)
BUNDLE_TOP = ("README.md", "Makefile", "Dockerfile", "compose.yaml", ".dockerignore", ".devcontainer")
#: what of this project the student's toolkit holds (relative to the project root)
TOOLKIT_FILES = ("pyproject.toml", "setup.py", "constraints.txt", "environment.yml", "LICENSE", "hri_teleop", "hri_lab", "grading/traces", "tools/setup.sh", "tools/env.sh",
                 "tools/kernel.sh", "docs", "firmware/arduino_code_force_node", "notebooks/experiment")
#: the lab's completed deliverables (and the CMakeLists whose lines are Ex. 9's answer): instructors only
LAB_DELIVERABLES = ("hri_lab/scripts/mapping_node.py", "hri_lab/scripts/teleoperation.py",
                    "hri_lab/launch/sensor.launch", "hri_lab/launch/teleoperation.launch",
                    "hri_lab/config/robot_params.yaml", "hri_lab/CMakeLists.txt")
#: what only instructors and developers read or run (the nodes' docs go to students, the rubric does not)
INSTRUCTOR_ONLY = ("benchmarks", "docs/instructors.md", "docs/grading-internals.md", "docs/benchmarks.md",
                   "docs/adding-an-exercise.md",  # its worked example is an answer key's file, markers and all
                   "hri_teleop/grading/gradescope",  # it ships the course notebooks' hidden tests
                   "hri_teleop/apps/gradescope.py")  # its command, which needs it
#: Region lines shorter than this (``else:``, ``}``) are too common to prove a leak.
_MIN_LEAK_CHARS = 8
#: A region line found *inside* a longer line (a hint's string, a docstring) leaks when it is at
#: least this long and looks like code (see :func:`distinctive`): a path or a command alone
#: (``scripts/teleoperation.py``, ``!rostopic type /pub_force``) is named by the handout too.
_MIN_EMBEDDED_CHARS = 24
_CODE_MARK = re.compile(r"[=(){}\[\]<>]")
# (``*.so``: the simulated arm's compiled cycle is built by the student's own pip, never shipped)
_IGNORE = shutil.ignore_patterns("__pycache__", "*.pyc", "*.so", "*.egg-info", ".ipynb_checkpoints", "catkin_ws")


def build_toolkit(target: PathLike, repo: PathLike = REPO) -> Path:
    """Copy :data:`TOOLKIT_FILES` of ``repo`` into ``target`` (replaced), leaving out what students must not get."""
    root, target = Path(repo), Path(target)
    if target.exists():
        shutil.rmtree(target)
    left_out = {root / p for p in LAB_DELIVERABLES + INSTRUCTOR_ONLY}
    for relative in TOOLKIT_FILES:
        source, dest = root / relative, target / relative
        dest.parent.mkdir(parents=True, exist_ok=True)
        if source.is_dir():
            shutil.copytree(source, dest, ignore=lambda folder, names: set(_IGNORE(folder, names)) | {
                n for n in names if Path(folder) / n in left_out})
        else:
            shutil.copy2(source, dest)
    (target / "README.md").write_text(
        "# hri-teleop toolkit (student edition)\n\nInstalled by `make setup` one folder up; see the README there.\n",
        encoding="utf-8")
    return target


def assemble_bundle(release: PathLike, target: PathLike, assignments: Sequence[str], repo: PathLike = REPO) -> Path:
    """The bundle's top folder: the released assignments, :data:`BUNDLE_TOP` and toolkit/."""
    target = Path(target)
    if target.exists():
        shutil.rmtree(target)
    target.mkdir(parents=True)
    for assignment in assignments:
        shutil.copytree(Path(release) / assignment, target / assignment, symlinks=False, ignore=_IGNORE)
    for name in BUNDLE_TOP:
        if (BUNDLE_FILES / name).is_dir():
            shutil.copytree(BUNDLE_FILES / name, target / name)
        else:
            shutil.copy2(BUNDLE_FILES / name, target / name)
    build_toolkit(target / "toolkit", repo)
    return target


def pack_bundle(folder: PathLike, archive: PathLike) -> Path:
    """``folder`` as ``archive`` (.tar.gz) under the top folder ``task4/``."""
    archive = Path(archive)
    archive.parent.mkdir(parents=True, exist_ok=True)
    with tarfile.open(archive, "w:gz") as tar:
        tar.add(str(folder), arcname="task4")
    return archive


def _normalized(text: str) -> str:
    return "\n".join(line.rstrip() for line in text.strip().splitlines())


def deliverable_copies(folder: PathLike, answers: Dict[str, str]) -> List[str]:
    """Files under ``folder`` whose text is a completed deliverable (``answers``: where -> answer text); a ``.venv``
    folder is not read."""
    wanted = {_normalized(text): where for where, text in answers.items() if text.strip()}
    found = []
    for path in (p for p in _shipped_files(Path(folder)) if p.suffix != ".ipynb"):
        try:
            text = _normalized(path.read_text(encoding="utf-8"))
        except (UnicodeDecodeError, OSError):
            continue
        if text in wanted:
            found.append(f"{path}: is the completed {wanted[text]}")
    return found


def toolkit_leaks(folder: PathLike, texts: Dict[str, List[str]], answers: Dict[str, str],
                  code_with_markers: Iterable[str] = ("hri_teleop/grading/cases/templates.py",)
                  ) -> List[str]:
    """Solution lines and completed deliverables anywhere in a bundle (or an installed toolkit).

    The modules that strip solution regions name the markers themselves; a marker there is
    code, not an answer, so only their solution *lines* count.
    """
    allowed = tuple(str(Path(p)) for p in code_with_markers)
    problems = [p for p in bundle_leaks(folder, texts)
                if not (p.endswith(": holds a solution marker") and p[:-len(": holds a solution marker")].endswith(allowed))]
    problems.extend(deliverable_copies(folder, answers))
    # An installed toolkit's .venv holds third-party packages (nbgrader's docs show markers);
    # the toolkit itself is installed in place (editable), so its code is what is scanned.
    problems = [p for p in problems if "/.venv/" not in p]
    missing = [p for p in LAB_DELIVERABLES if (Path(folder) / "toolkit" / p).exists() or (Path(folder) / p).exists()]
    problems.extend(f"{p}: the lab's completed deliverable is in the bundle" for p in missing)
    return problems


def answer_files(solutions: Optional[PathLike] = None) -> Dict[str, str]:
    """The answer key's deliverables as a good student hands them in (markers dropped): path -> text."""
    root = Path(solutions) if solutions is not None else SOLUTIONS
    return {str(p): make_answer(p.read_text(encoding="utf-8")) for p in sorted(root.rglob("*"))
            if p.is_file() and p.name != "README.md" and has_markers(p.read_text(encoding="utf-8"))}


# -- what only the answer key has ---------------------------------------------------------------

def read_notebook(path: Path) -> Dict[str, Any]:
    notebook: Dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
    return notebook


def _src(cell: Dict[str, Any]) -> str:
    source = cell.get("source", "")
    return "".join(source) if isinstance(source, list) else source


def solution_texts(solutions: PathLike = SOLUTIONS, course_dir: PathLike = NOTEBOOKS) -> Dict[str, List[str]]:
    """Where -> the lines inside its solution regions: the answer key's files and the notebooks' solution cells.

    A notebook solution cell without markers (a written answer) is a region as a whole.
    Lines that the same file or notebook also has outside its regions (a given line the
    answer repeats) are left out: finding them in the bundle proves nothing.
    """
    texts: Dict[str, List[str]] = {}
    for path in sorted(p for p in Path(solutions).rglob("*") if p.is_file() and p.name != "README.md"):
        text = path.read_text(encoding="utf-8")
        lines = solution_lines(text)
        if lines:
            public = {line.strip() for line in make_template(text, kind_of(path), str(path)).split("\n")}
            texts[str(path)] = [line for line in lines if line.strip() not in public]
    for notebook in sorted(Path(course_dir).glob("source/*/*.ipynb")):
        cells = read_notebook(notebook)["cells"]
        public = {line.strip() for cell in cells if not cell.get("metadata", {}).get("nbgrader", {}).get("solution")
                  for line in _src(cell).split("\n")}
        for number, cell in enumerate(cells):
            if not cell.get("metadata", {}).get("nbgrader", {}).get("solution"):
                continue
            source = _src(cell)
            lines = solution_lines(source) if has_markers(source) else source.split("\n")
            lines = [line for line in lines if line.strip() not in public]
            if lines:
                texts[f"{notebook}#cell{number}"] = lines
    return texts


def _bundle_lines(path: Path) -> List[str]:
    if path.suffix == ".ipynb":
        return [line for cell in read_notebook(path)["cells"] for line in _src(cell).split("\n")]
    return path.read_text(encoding="utf-8", errors="replace").split("\n")


def distinctive(line: str) -> bool:
    """True for a region line that proves a leak wherever it appears, even inside a longer line:
    at least 24 characters, with code's marks (an ``=``, brackets, a tag), no solution marker."""
    stripped = line.strip()
    return len(stripped) >= _MIN_EMBEDDED_CHARS and bool(_CODE_MARK.search(stripped)) and not has_markers(stripped)


def _shipped_files(bundle: Path) -> List[Path]:
    """Every file under ``bundle`` but an installed virtual environment's (third-party packages): a ``.venv``
    folder is not entered (nor, as with rglob, a linked folder)."""
    found: List[Path] = []
    for root, folders, files in os.walk(bundle):
        folders[:] = [name for name in folders if name != ".venv"]
        found.extend(Path(root, name) for name in files if name != ".venv")
    return sorted(p for p in found if p.is_file())


def bundle_leaks(bundle: PathLike, texts: Optional[Dict[str, List[str]]] = None) -> List[str]:
    """Every place where the student bundle holds a solution marker or a line from inside a solution region.

    A line leaks when a line of a bundle file (or of a notebook cell), stripped, equals it;
    lines shorter than 8 characters (``else:``, ``})``) are too common to tell. A
    :func:`distinctive` line also leaks anywhere inside a line (a grader hint's string that
    quotes the answer). A ``.venv`` folder (an installed toolkit's packages) is not scanned.
    """
    texts = solution_texts() if texts is None else texts
    needles: Dict[str, str] = {}
    for where, lines in texts.items():
        for line in lines:
            stripped = line.strip()
            if len(stripped) >= _MIN_LEAK_CHARS and not has_markers(stripped):
                needles.setdefault(stripped, where)
    embedded = {needle: where for needle, where in needles.items() if distinctive(needle)}
    problems = []
    for path in _shipped_files(Path(bundle)):
        lines = _bundle_lines(path)
        if any(has_markers(line) for line in lines):
            problems.append(f"{path}: holds a solution marker")
        whole = dict.fromkeys(line.strip() for line in lines)
        for line in whole:
            if line in needles:
                problems.append(f"{path}: holds solution text {line!r} (from {needles[line]})")
        text = "\n".join(lines)
        for needle, where in embedded.items():
            if needle not in whole and needle in text:
                problems.append(f"{path}: holds solution text {needle!r} inside a longer line (from {where})")
    return problems
