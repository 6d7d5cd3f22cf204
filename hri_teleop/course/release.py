"""The instructor's release tools: student versions, templates, a bundle without answers, checks.

``make release`` runs nbgrader's ``generate_assignment``, writes the student files' templates from
``solutions/`` and refuses a bundle with solution text in it; ``check`` runs every notebook (the
answer key must pass, the student version fail). Course layout: ``notebooks/README.md``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import nbformat
from nbclient import NotebookClient
from nbgrader.utils import determine_grade, is_grade, is_solution
from nbgrader.validator import Validator

from hri_teleop.core.paths import NOTEBOOKS, REPO, SOLUTIONS
from hri_teleop.course.bundle import (
    answer_files,
    assemble_bundle,
    bundle_leaks,
    pack_bundle,
    read_notebook,
    solution_texts,
    toolkit_leaks,
)
from hri_teleop.course.errors import CourseError
from hri_teleop.course.nodes import STUDENT_PACKAGE
from hri_teleop.grading.assignments import ASSIGNMENTS, nbgrader_env
from hri_teleop.grading.cases.templates import generate_templates
from hri_teleop.grading.run.workspace import DELIVERABLES
from hri_teleop.ros.kernel import install_kernelspec, ipc_kernel_config

__all__ = ["copy_answer_key",
    "REPO", "COURSE_DIR", "SOLUTIONS", "STUDENT_MAKES_EXECUTABLE",
    "student_files", "exclude_overwriting", "link_answer_key", "source_notebooks", "solution_texts",
    "bundle_leaks", "generate_assignments", "build_release", "notebook_output_problems", "strip_outputs",
    "validate_release", "run_source", "prepare_course_copy", "run_course", "check_course",
]

PathLike = Union[str, Path]
COURSE_DIR = NOTEBOOKS
#: Scripts the handout has students make executable (Ex. 9, Ex. 12 c): released without the bit.
STUDENT_MAKES_EXECUTABLE = ("scripts/teleoperation.py", "scripts/gripper_manager.py")


# -- the course's files -------------------------------------------------------------------------

def student_files() -> List[str]:
    """The files a student writes, relative to the assignment folder (``hri_lab/...``)."""
    return [f"{STUDENT_PACKAGE}/{sub}" for sub in DELIVERABLES.values()]


def exclude_overwriting() -> Dict[str, List[str]]:
    """nbgrader's ``Autograde.exclude_overwriting``: autograde never puts the instructor's file over the student's."""
    return {assignment: student_files() + [f"{STUDENT_PACKAGE}/CMakeLists.txt"] for assignment in ASSIGNMENTS}


def link_answer_key(course_dir: PathLike = COURSE_DIR, solutions: PathLike = SOLUTIONS) -> List[Path]:
    """Make ``source/<assignment>/hri_lab`` a link to the answer key (relative inside the repo)."""
    links = []
    for assignment in ASSIGNMENTS:
        folder = Path(course_dir) / "source" / assignment
        if not folder.is_dir():
            raise CourseError(f"{folder}: no such assignment folder; the course needs source/{assignment}/")
        link = folder / STUDENT_PACKAGE
        target = Path(os.path.relpath(Path(solutions).resolve(), folder.resolve()))
        if link.is_symlink() and Path(os.readlink(link)) == target:
            links.append(link)
            continue
        if link.exists() and not link.is_symlink():
            raise CourseError(f"{link}: a real folder; source/ must link to the answer key (solutions/hri_lab), "
                              "never hold a copy: move your changes into solutions/ and remove it")
        if link.is_symlink():
            link.unlink()
        link.symlink_to(target, target_is_directory=True)
        links.append(link)
    return links


def source_notebooks(course_dir: PathLike = COURSE_DIR) -> List[Path]:
    """Every source notebook, assignment by assignment, in name order."""
    found: List[Path] = []
    for assignment in ASSIGNMENTS:
        found += sorted((Path(course_dir) / "source" / assignment).glob("*.ipynb"))
    return found


# -- release -----------------------------------------------------------------------------------

def _nbgrader(args: Sequence[str], course_dir: Path) -> str:
    argv = [sys.executable, "-m", "nbgrader", *args, f"--CourseDirectory.root={course_dir}"]
    proc = subprocess.run(argv, cwd=str(course_dir), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, env=nbgrader_env())
    if proc.returncode != 0:
        tail = "\n".join(proc.stdout.strip().splitlines()[-15:])
        raise CourseError(f"nbgrader {' '.join(args)} failed (exit {proc.returncode}):\n{tail}")
    return proc.stdout


def generate_assignments(course_dir: PathLike = COURSE_DIR) -> List[Path]:
    """``nbgrader generate_assignment`` for every assignment, then its hri_lab templates; release folders."""
    course = Path(course_dir).resolve()
    link_answer_key(course)
    released = []
    for assignment in ASSIGNMENTS:
        _nbgrader(["generate_assignment", assignment, "--force", "--create"], course)
        folder = course / "release" / assignment
        generate_templates(SOLUTIONS, folder / STUDENT_PACKAGE, not_executable=STUDENT_MAKES_EXECUTABLE)
        released.append(folder)
    return released


def build_release(course_dir: PathLike = COURSE_DIR, archive: Optional[PathLike] = None) -> Tuple[Path, Path]:
    """``make release``: the student versions and templates, proven free of solution text, packed.

    Returns (the release folder, the .tar.gz of it). CourseError when anything leaks.
    """
    course = Path(course_dir).resolve()
    problems = notebook_output_problems(source_notebooks(course))
    if problems:
        raise CourseError("source notebooks have outputs (run `python -m hri_teleop.apps.course strip`): "
                          + "; ".join(problems[:5]))
    generate_assignments(course)
    release = course / "release"
    leaks = bundle_leaks(release, solution_texts(SOLUTIONS, course))
    if leaks:
        raise CourseError("the student bundle holds solution text; nothing was packed:\n" + "\n".join(leaks[:20]))
    target = Path(archive) if archive else REPO / "out" / "task4-student-bundle.tar.gz"
    folder = assemble_bundle(release, target.parent / "task4-student-bundle", ASSIGNMENTS)
    leaks = toolkit_leaks(folder, solution_texts(SOLUTIONS, course), answer_files())
    if leaks:
        raise CourseError("the student bundle's toolkit holds answers; nothing was packed:\n" + "\n".join(leaks[:20]))
    pack_bundle(folder, target)
    shutil.rmtree(folder)
    return release, target


# -- notebooks without outputs -------------------------------------------------------------------

def notebook_output_problems(paths: Iterable[PathLike]) -> List[str]:
    """One line per code cell that has outputs or an execution count (committed notebooks must have none)."""
    problems = []
    for path in paths:
        for number, cell in enumerate(read_notebook(Path(path))["cells"]):
            if cell.get("cell_type") != "code":
                continue
            if cell.get("outputs"):
                problems.append(f"{path}: cell {number} has {len(cell['outputs'])} output(s)")
            if cell.get("execution_count") is not None:
                problems.append(f"{path}: cell {number} has execution_count {cell['execution_count']}")
    return problems


def strip_outputs(paths: Iterable[PathLike]) -> List[Path]:
    """Remove outputs and execution counts (and nbgrader checksums of source cells); the files changed."""
    changed = []
    for path in map(Path, paths):
        nb = nbformat.read(str(path), as_version=4)
        before = nbformat.writes(nb)
        for cell in nb.cells:
            if cell.cell_type == "code":
                cell.outputs = []
                cell.execution_count = None
            cell.metadata.get("nbgrader", {}).pop("checksum", None)
            cell.metadata.pop("execution", None)
        after = nbformat.writes(nb)
        if after != before:
            path.write_text(after, encoding="utf-8")
            changed.append(path)
    return changed


# -- validate: the answer key passes, the student version fails ------------------------------------

def validate_release(notebook: PathLike, timeout_s: int = 300) -> Dict[str, Any]:
    """nbgrader's ``validate --invert`` on one student version: the autograded cells that PASS (should be none)."""
    with ipc_kernel_config() as config:
        config.Validator.invert = True
        config.Execute.timeout = timeout_s
        config.Execute.startup_timeout = 120
        result: Dict[str, Any] = Validator(config=config).validate(str(notebook))
        return result


def run_source(notebook: PathLike, timeout_s: int = 300) -> Dict[str, Any]:
    """Execute a source notebook top to bottom (nbclient, its own kernel: ``hri-teleop``) and grade it as nbgrader would.

    Returns ``errors`` (every code cell that raised or wrote to stderr), ``grades``
    ({grade_id: [score, max]} of the autograded cells) and ``seconds``.
    """
    path = Path(notebook)
    nb = nbformat.read(str(path), as_version=4)
    started = time.monotonic()
    with ipc_kernel_config() as config:
        NotebookClient(nb, config=config, timeout=timeout_s, startup_timeout=120, allow_errors=True,
                       resources={"metadata": {"path": str(path.parent)}}).execute()
    errors, grades = [], {}
    for number, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        for out in cell.outputs:
            if out.output_type == "error":
                errors.append(f"cell {number}: {out.ename}: {out.evalue.strip()[:800]}")
            elif out.output_type == "stream" and out.name == "stderr":
                errors.append(f"cell {number} wrote to stderr: {out.text.strip()[:800]}")
        if is_grade(cell) and not is_solution(cell):
            got, most = determine_grade(cell)
            grades[cell.metadata.nbgrader["grade_id"]] = [got, most]
    return {"errors": errors, "grades": grades, "seconds": time.monotonic() - started}


def _validate_job(job: Tuple[str, str]) -> Tuple[str, str, Dict[str, Any]]:
    kind, path = job

    started = time.monotonic()
    if kind == "source":
        result = run_source(path)
    else:
        result = validate_release(path)
        result["seconds"] = time.monotonic() - started
    return kind, path, result


#: Left out of a copy of the course where git cannot say what is tracked (as the release leaves them out).
_UNTRACKED = ("catkin_ws", "__pycache__", "*.pyc", ".ipynb_checkpoints")


def tracked_below(folder: PathLike) -> Optional[List[str]]:
    """The files git tracks below ``folder`` (relative to it; a link as itself), or None where git tracks
    none there (a course folder outside a checkout)."""
    try:
        listed = subprocess.run(["git", "-C", str(folder), "ls-files", "-z", "--", "."], capture_output=True,
                                check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    names = [n for n in listed.decode("utf-8", "surrogateescape").split("\0") if n]
    return names or None


def copy_course_sources(course_dir: PathLike, course: Path) -> None:
    """The course's nbgrader_config.py and each assignment's source folder, less its student package, into
    ``course``: the files git tracks, never what a run in place left there (the catkin_ws/build of the lab's
    notebooks, plots, checkpoints), as the release leaves them out."""
    source = Path(course_dir)
    (course / "source").mkdir(parents=True)
    shutil.copy(source / "nbgrader_config.py", course / "nbgrader_config.py")
    for assignment in ASSIGNMENTS:
        folder, target = source / "source" / assignment, course / "source" / assignment
        tracked = tracked_below(folder)
        if tracked is None:
            shutil.copytree(folder, target, ignore=shutil.ignore_patterns(STUDENT_PACKAGE, *_UNTRACKED))
            continue
        target.mkdir(parents=True)
        for name in tracked:
            if Path(name).parts[0] == STUDENT_PACKAGE or not os.path.lexists(folder / name):
                continue
            (target / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(folder / name, target / name, follow_symlinks=False)


def prepare_course_copy(work_dir: PathLike, course_dir: PathLike = COURSE_DIR, release: bool = True) -> Path:
    """A copy of the course under ``work_dir/course`` with the student versions generated (and the kernel installed).

    ``release=False``: only the source half, each assignment linked to the answer key, for
    running the source notebooks (nbgrader's generate_assignment takes ~10 s).
    """
    course = Path(work_dir) / "course"
    if course.exists():
        shutil.rmtree(course)
    copy_course_sources(course_dir, course)
    if release:
        generate_assignments(course)
    else:
        link_answer_key(course)
    install_kernelspec()  # the notebooks' kernel: .venv's Python in the lab's shell (tools/kernel.sh)
    return course


def run_course(course: PathLike, jobs: int = 2) -> Dict[str, Dict[str, Any]]:
    """Run every source notebook of a prepared course (must pass every autograded cell) and
    ``validate --invert`` every student version (no autograded cell may pass), ``jobs`` at a time.

    Returns {notebook name: {"source": run_source(...), "release": validate_release(...)}}.
    Real-time cells run short (:func:`fast`). The student versions run in place.
    """
    course = Path(course)
    os.environ["HRI_NOTEBOOK_FAST"] = "1"
    jobs_list = []
    for notebook in source_notebooks(course):
        jobs_list.append(("source", str(notebook)))
        jobs_list.append(("release", str(course / "release" / notebook.parent.name / notebook.name)))
    results: Dict[str, Dict[str, Any]] = {}
    with ProcessPoolExecutor(max_workers=max(1, jobs)) as pool:
        for kind, path, result in pool.map(_validate_job, jobs_list):
            results.setdefault(Path(path).stem, {})[kind] = result
    return results


def check_course(work_dir: PathLike, course_dir: PathLike = COURSE_DIR, jobs: int = 2) -> Dict[str, Dict[str, Any]]:
    """The whole course checked in a copy under ``work_dir``: :func:`prepare_course_copy`, then :func:`run_course`."""
    return run_course(prepare_course_copy(work_dir, course_dir), jobs)


def copy_answer_key(bundle: Path, course: Path) -> None:
    """What a student who knows every answer hands in, put into an unpacked ``bundle``: the answer key's files
    (executable where the handout has students chmod +x) and the solution cells of ``course``'s source notebooks
    (tests and ``make bench`` grade a bundle that gets full marks with it)."""
    import json  # noqa: PLC0415 - only the tests' and benchmarks' helper reads notebooks here

    from hri_teleop.course.bundle import answer_files  # noqa: PLC0415 - as above

    for assignment in ASSIGNMENTS:
        package = bundle / assignment / STUDENT_PACKAGE
        for where, text in answer_files().items():
            relative = Path(where).relative_to(SOLUTIONS)
            if (package / relative).is_file():
                (package / relative).write_text(text)
                if relative.suffix == ".py":
                    (package / relative).chmod(0o755)
        for script in STUDENT_MAKES_EXECUTABLE:  # the handout's chmod +x (Ex. 9, Ex. 12 c)
            if (package / script).is_file():
                (package / script).chmod(0o755)
        for notebook in (bundle / assignment).glob("ex*.ipynb"):
            source = json.loads((course / "source" / assignment / notebook.name).read_text())
            answers = {c["metadata"]["nbgrader"]["grade_id"]: c["source"] for c in source["cells"]
                       if c.get("metadata", {}).get("nbgrader", {}).get("solution")}
            student = json.loads(notebook.read_text())
            for cell in student["cells"]:
                grade_id = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")
                if grade_id in answers:
                    cell["source"] = answers[grade_id]
            notebook.write_text(json.dumps(student))
