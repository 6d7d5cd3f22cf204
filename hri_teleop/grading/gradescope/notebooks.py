"""The course's notebooks in a Gradescope upload: nbgrader's autograde, a test per autograded cell.

The zip carries the source notebooks with their solution regions emptied (hidden tests kept), so
no answer travels in it. run_autograder generates the assignment from them in a scratch course
(the stubs come back as in the release), puts the student's notebooks beside their hri_lab and
runs nbgrader's autograde as make grade does; the gradebook gives each cell's points.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Sequence, Tuple

from hri_teleop.grading.assignments import ASSIGNMENTS
from hri_teleop.grading.batch.nbgrader_batch import autograde_one, nbgrader_job_env
from hri_teleop.grading.cases.templates import empty_regions, has_markers
from hri_teleop.grading.results import GradingError
from hri_teleop.grading.run.jobs import run_job
from hri_teleop.grading.run.kernel_sandbox import KernelPolicy, kernel_sandbox
from hri_teleop.grading.run.untrusted_files import UntrustedFileError, read_regular
from hri_teleop.ros.kernel import install_kernelspec

__all__ = ["COURSE", "NOTEBOOKS_TIMEOUT_S", "NotebookTests", "course_members", "without_solutions",
           "course_notebooks", "cell_tests", "grade_notebooks", "notebook_problem", "MAX_NOTEBOOK_BYTES"]

#: The folder of the zip holding the course (nbgrader_config.py, source/<assignment>/*.ipynb).
COURSE = "course"
#: nbgrader autograde of one assignment's uploaded notebooks (each cell also has the course's 300 s).
NOTEBOOKS_TIMEOUT_S = 600.0
_HIDDEN = "BEGIN HIDDEN TESTS"
#: The largest uploaded notebook graded (outputs and images included).
MAX_NOTEBOOK_BYTES = 50 * 1024 ** 2
_OUTPUT_CHARS = 1500
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


def _source(cell: Dict[str, Any]) -> str:
    """A cell's text (nbformat stores it as one string or as a list of lines)."""
    source = cell["source"]
    return "".join(source) if isinstance(source, list) else str(source)


def without_solutions(notebook: Dict[str, Any]) -> Dict[str, Any]:
    """``notebook`` (nbformat JSON) with its solution cells' answers and every output removed.

    A region between the markers keeps its markers and loses its lines; a solution cell without
    markers becomes empty. nbgrader's generate_assignment puts the course's stubs back in both.
    """
    cells = []
    for cell in notebook.get("cells", []):
        cell = dict(cell)
        meta = cell.get("metadata", {}).get("nbgrader", {})
        if meta.get("solution"):
            text = _source(cell)
            cell["source"] = empty_regions(text) if has_markers(text) else ""
        if cell.get("cell_type") == "code":
            cell["outputs"], cell["execution_count"] = [], None
        cells.append(cell)
    return dict(notebook, cells=cells)


def course_members(course_dir: Path) -> Iterator[Tuple[str, bytes]]:
    """(name in the zip, bytes) of the course: its nbgrader_config.py and every source notebook, answers removed."""
    yield f"{COURSE}/nbgrader_config.py", (course_dir / "nbgrader_config.py").read_bytes()
    for assignment in ASSIGNMENTS:
        for path in sorted((course_dir / "source" / assignment).glob("*.ipynb")):
            try:
                notebook = without_solutions(json.loads(path.read_text(encoding="utf-8")))
            except (ValueError, KeyError, TypeError) as exc:
                raise GradingError(f"{path}: not a notebook nbgrader can read ({exc}); fix it and build again") from exc
            text = json.dumps(notebook, indent=1, sort_keys=True, ensure_ascii=False) + "\n"
            yield f"{COURSE}/source/{assignment}/{path.name}", text.encode("utf-8")


def course_notebooks(course: Path) -> Dict[str, str]:
    """notebook name (no suffix) -> its assignment, for the course shipped in the zip (``course``)."""
    return {path.stem: assignment for assignment in ASSIGNMENTS
            for path in sorted((course / "source" / assignment).glob("*.ipynb"))}


@dataclass
class NotebookTests:
    """Gradescope tests of the graded notebooks (notebook -> tests), the notebooks not judged and why, notes."""

    tests: Dict[str, List[Dict[str, Any]]] = field(default_factory=dict)
    unjudged: List[Tuple[str, str]] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)


def _cells(path: Path) -> List[Dict[str, Any]]:
    return list(json.loads(path.read_text(encoding="utf-8")).get("cells", []))


def _manual_points(source: Path) -> float:
    """The points of the notebook's answers nbgrader leaves to course staff (written answers)."""
    return sum(float(c["metadata"]["nbgrader"].get("points", 0)) for c in _cells(source)
               if c.get("metadata", {}).get("nbgrader", {}).get("grade")
               and c["metadata"]["nbgrader"].get("solution"))


def _autograded_cells(source: Path) -> List[Tuple[str, float, bool]]:
    """(grade id, points, holds hidden tests) of the source notebook's autograded cells, in order."""
    found = []
    for cell in _cells(source):
        meta = cell.get("metadata", {}).get("nbgrader", {})
        if meta.get("grade") and not meta.get("solution") and cell.get("cell_type") == "code":
            text = _source(cell)
            found.append((str(meta["grade_id"]), float(meta.get("points", 0)), _HIDDEN in text))
    return found


def _cell_output(autograded: Path) -> Dict[str, str]:
    """grade id -> what the autograded cell printed and the error it raised (ANSI colours removed)."""
    outputs: Dict[str, str] = {}
    if not autograded.is_file():
        return outputs
    for cell in _cells(autograded):
        grade_id = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")
        if not grade_id or cell.get("cell_type") != "code":
            continue
        parts = []
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream":
                parts.append("".join(out.get("text", "")))
            elif out.get("output_type") == "error":
                parts.append(f"{out.get('ename', 'Error')}: {out.get('evalue', '')}")
        text = _ANSI.sub("", "".join(p if p.endswith("\n") else p + "\n" for p in parts)).strip()
        outputs[str(grade_id)] = text[-_OUTPUT_CHARS:]
    return outputs


def notebook_problem(path: Path) -> str:
    """Why the uploaded ``path`` is no notebook nbgrader can run ("" when it is one): not a regular file, too
    large, not UTF-8 JSON, not nbformat 4 with a list of cells. Read without following a link."""
    try:
        notebook = json.loads(read_regular(path, MAX_NOTEBOOK_BYTES).decode("utf-8"))
    except UntrustedFileError as exc:  # the message without the scratch folder's path
        why = str(exc)
        return why[len(str(path)):].lstrip(": ") if why.startswith(str(path)) else why.split(": ", 1)[-1]
    except UnicodeDecodeError:
        return "not UTF-8 text"
    except (ValueError, RecursionError):
        return "not a Jupyter notebook (not JSON)"
    if not isinstance(notebook, dict) or notebook.get("nbformat") != 4 or not isinstance(notebook.get("cells"), list) \
            or not all(isinstance(c, dict) and isinstance(c.get("source", ""), (str, list)) for c in notebook["cells"]):
        return "not a Jupyter notebook of format 4"
    return ""


def cell_tests(name: str, source: Path, scores: Dict[str, float], outputs: Dict[str, str],
               not_judged: str = "", refused: str = "") -> List[Dict[str, Any]]:
    """A Gradescope test per autograded cell of the ``source`` notebook: ``scores`` and ``outputs`` by grade
    id (nbgrader's); cells with hidden tests are ``after_published``; all at 0 when ``not_judged`` says why
    (the grader's fault) or ``refused`` (the upload's: e.g. the file is no notebook)."""
    tests = []
    for grade_id, points, hidden in _autograded_cells(source):
        score = 0.0 if not_judged or refused else scores.get(grade_id, 0.0)
        if refused:
            output = (f"not graded: the uploaded {Path(name).name} is {refused}; open it in Jupyter, save it "
                      "and upload it again")
        elif not_judged:
            output = f"not judged: {not_judged}; course staff will regrade it (no need to resubmit)"
        elif score >= points:
            output = outputs.get(grade_id, "") or "passed"
        else:
            output = ((outputs.get(grade_id, "") + "\n").lstrip() + "This cell checks the answers above it: fill "
                      "them in, run the notebook from the top, and upload it again.")
        tests.append({"name": f"{name}: {grade_id}", "score": score, "max_score": points,
                      "status": "passed" if score >= points else "failed",
                      "visibility": "after_published" if hidden else "visible", "output": output})
    return tests


def _scores(db: Path, assignment: str, notebook: str, student: str) -> Dict[str, float]:
    from nbgrader.api import Gradebook  # noqa: PLC0415 - optional (not on Python 3.8): notebooks only

    with Gradebook(f"sqlite:///{db}") as gb:
        return {g.name: float(g.score) for g in gb.find_submission_notebook(notebook, assignment, student).grades}


def _alembic_on_path(work: Path) -> None:
    """nbgrader's gradebook runs the ``alembic`` command: put one on PATH (this Python's, or a shim
    running ``python -m alembic``, for a venv that borrows another one's packages)."""
    os.environ["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    if shutil.which("alembic") is None:
        shim = work / "bin" / "alembic"
        shim.parent.mkdir(parents=True, exist_ok=True)
        shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m alembic "$@"\n', encoding="utf-8")
        shim.chmod(0o755)
        os.environ["PATH"] = os.pathsep.join([str(shim.parent), os.environ["PATH"]])


def _generate(course: Path, assignment: str, log: Path) -> str:
    """nbgrader generate_assignment in ``course``: "" or why it failed."""
    argv = [sys.executable, "-m", "nbgrader", "generate_assignment", assignment, "--create", "--force",
            f"--CourseDirectory.root={course}"]
    run = run_job(argv, log, 300.0, cwd=course, env=nbgrader_job_env())
    if run.returncode == 0 and not run.timed_out:
        return ""
    lines = log.read_text(encoding="utf-8", errors="replace").strip().splitlines()
    errors = [line for line in lines if re.match(r"^\s*\w*(Error|Exception)\b", line)]
    print(f"run_autograder: nbgrader generate_assignment {assignment} failed:\n" + "\n".join(lines[-40:]), flush=True)
    return f"the course could not be prepared ({(errors or lines or ['no output'])[-1].strip()[:200]})"


def grade_notebooks(notebooks: Sequence[Path], package: Path, shipped: Path, work: Path,
                    timeout_s: float = NOTEBOOKS_TIMEOUT_S, student: str = "student",
                    sandbox: Optional[KernelPolicy] = None, seed: Optional[int] = None) -> NotebookTests:
    """Autograde the course's notebooks among ``notebooks`` beside ``package`` (the course in ``shipped``).

    ``student`` names the submission's folder; ``seed`` is the check cells' hidden inputs' (the files'
    tests' seed, :func:`hri_teleop.grading.cases.inputs.student_seed`; None: ``student``'s). The check
    cells are no tests: their points are the files' (:mod:`hri_teleop.grading.points`). ``sandbox``: the
    kernels' (None: the grader's rights); where it cannot run, the notebooks are not judged.
    """
    result = NotebookTests()
    known = course_notebooks(shipped)
    chosen: Dict[str, Path] = {}
    for path in sorted(notebooks, key=lambda p: (len(p.parts), str(p))):
        if path.stem in known:
            chosen.setdefault(path.stem, path)
    twice = sorted({p.name for p in notebooks if p.stem in chosen and p != chosen[p.stem]})
    if twice:
        result.notes.append(f"{', '.join(twice)}: in the upload more than once; graded the copy nearest its top")
    ignored = sorted({p.name for p in notebooks if p.stem not in known})
    if ignored:
        result.notes.append(f"ignored {', '.join(ignored)}: not notebooks of the course (keep their names: "
                            f"{', '.join(sorted(known)[:3])}, ...)")
    broken = {stem: why for stem, path in chosen.items() if (why := notebook_problem(path))}
    for stem, why in sorted(broken.items()):  # no nbgrader run for them: the others of the assignment still run
        name = f"{known[stem]}/{stem}.ipynb"
        result.notes.append(f"{name}: not graded, the uploaded file is {why}")
        result.tests[name] = cell_tests(name, shipped / "source" / known[stem] / f"{stem}.ipynb", {}, {}, refused=why)
        del chosen[stem]
    course = work / "course"
    if chosen:
        install_kernelspec()  # the notebooks' kernel "hri-teleop", as make grade installs it
        _alembic_on_path(work)
    refused = ""
    if chosen and sandbox is not None:
        sandbox, refused = kernel_sandbox(sandbox)
    if refused:
        refused = (f"the autograder cannot sandbox the notebooks' code here ({refused}); the instructor can "
                   "rebuild it with make gradescope UNSANDBOXED=1 to grade them with the grader's rights")
    elif chosen and sandbox is None:
        result.notes.append("the notebooks ran without the sandbox (the autograder was built with UNSANDBOXED=1)")
    for assignment in ASSIGNMENTS:
        mine = {stem: path for stem, path in chosen.items() if known[stem] == assignment}
        if not mine:
            continue
        if course.exists():
            shutil.rmtree(course)
        course.mkdir(parents=True)
        shutil.copy(shipped / "nbgrader_config.py", course)
        shutil.copytree(shipped / "source" / assignment, course / "source" / assignment)
        why = refused or _generate(course, assignment, work / f"generate-{assignment}.log")
        if not why:
            folder = course / "submitted" / student / assignment
            folder.mkdir(parents=True)
            for stem, path in mine.items():
                shutil.copy(path, folder / f"{stem}.ipynb")
            shutil.copytree(package, folder / "hri_lab", symlinks=True)
            outcome = autograde_one(course, student, assignment, work / f"autograde-{assignment}", timeout_s,
                                    progress=lambda line: print(line, flush=True), sandbox=sandbox, seed=seed)
            why = "" if outcome.status == "graded" else outcome.message
            if why:  # for the instructor: run_autograder's log
                log = work / f"autograde-{assignment}" / "autograde.log"
                tail = log.read_text(encoding="utf-8", errors="replace").splitlines()[-40:] if log.is_file() else []
                print(f"run_autograder: {why}\n" + "\n".join(tail), flush=True)
        for stem in sorted(mine):
            name = f"{assignment}/{stem}.ipynb"
            source = course / "source" / assignment / f"{stem}.ipynb"
            manual = _manual_points(source)
            if manual:
                result.notes.append(f"{name}: {manual:g} more points of written answers are graded by course staff")
            if why:
                result.unjudged.append((name, why))
                result.tests[name] = cell_tests(name, source, {}, {}, why)
            else:
                autograded = course / "autograded" / student / assignment / f"{stem}.ipynb"
                result.tests[name] = cell_tests(name, source, _scores(course / "gradebook.db", assignment, stem,
                                                                      student), _cell_output(autograded))
    return result
