"""After nbgrader's autograde, the grader judges each autograded test cell in its own process.

The cell's LAST answer output (:func:`hri_teleop.course.answers.hand_in`), in that cell only and whether it
raised or not, goes through the cell's rule (:mod:`hri_teleop.grading.judge.notebook_answers`): the score
into nbgrader's gradebook (``auto_score``; a grade given by hand stays), the verdict into the cell's outputs,
so the feedback shows the grader's words. No answer: 0, "not judged: the cell handed in no value (...)".
Called by make grade and Gradescope alike (``nbgrader_batch.autograde_in``; docs/grading-internals.md).
"""

from __future__ import annotations

import json
import os
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.grading.batch.drive_check import ex10_values
from hri_teleop.grading.batch.notebook_commands import command_cells_values
from hri_teleop.grading.judge.notebook_answers import (
    MAX_ANSWER_BYTES,
    MIME,
    WORKED_OUT,
    apply_rule,
    expectations,
    has_rule,
)
from hri_teleop.grading.run.untrusted_files import UntrustedFileError, read_regular

__all__ = ["NotebookJudgeError", "CellVerdict", "handed_in", "judge_cell", "verdict_outputs", "judge_notebook",
           "judge_submission", "judge_autograded", "MAX_AUTOGRADED_BYTES"]

#: The largest autograded notebook read (nbgrader wrote it, with the kernel's outputs and images).
MAX_AUTOGRADED_BYTES = 200 * 1024 ** 2
_SUMMARY_CHARS = 300
_ERROR_CHARS = 160


class NotebookJudgeError(HriTeleopError, RuntimeError):
    """The grader could not judge a submission's notebooks (one line: the cause and the fix)."""


@dataclass(frozen=True)
class CellVerdict:
    """The grader's verdict on one autograded cell of one notebook."""

    notebook: str
    grade_id: str
    score: float
    max_score: float
    message: str
    values: Optional[Dict[str, Any]] = None
    source: str = "handed in"


def _first_line(text: Any, limit: int) -> str:
    line = str(text).strip().splitlines()[0] if str(text).strip() else ""
    return line if len(line) <= limit else line[:limit - 3] + "..."


def _no_value(cell: Dict[str, Any], outputs: List[Any]) -> str:
    errors = [o for o in outputs if isinstance(o, dict) and o.get("output_type") == "error"]
    if errors:
        name = _first_line(errors[-1].get("ename", "an error"), 80)
        value = _first_line(errors[-1].get("evalue", ""), _ERROR_CHARS)
        why = f"it raised {name}: {value}" if value else f"it raised {name}"
    elif cell.get("execution_count") is None and not outputs:
        why = "it did not run"
    else:
        why = "it ran without calling hand_in"
    return f"not judged: the cell handed in no value ({why})"


def handed_in(cell: Dict[str, Any]) -> Tuple[Optional[Dict[str, Any]], str]:
    """(values, "") of the cell's last answer output, or (None, why there is none to judge).

    Only this cell's outputs count, and only the last one of the answer MIME type: what a hook printed
    before the cell ran comes first, the cell's own ``hand_in`` after it. Whether the cell then raised
    does not matter: the rule judges the values."""
    outputs = cell.get("outputs")
    outputs = outputs if isinstance(outputs, list) else []
    answer: Any = None
    for out in outputs:
        if isinstance(out, dict) and out.get("output_type") in ("display_data", "execute_result"):
            data = out.get("data")
            if isinstance(data, dict) and MIME in data:
                answer = data[MIME]
    if answer is None:
        return None, _no_value(cell, outputs)
    try:
        text = answer if isinstance(answer, str) else json.dumps(answer, allow_nan=False)
        size = len(text.encode("utf-8"))
        if size > MAX_ANSWER_BYTES:
            return None, f"not judged: the cell handed in {size} bytes, more than {MAX_ANSWER_BYTES}"
        if isinstance(answer, str):
            answer = json.loads(text)
    except (ValueError, TypeError, RecursionError):
        return None, "not judged: the cell's answer is not plain JSON data"
    values = answer.get("values") if isinstance(answer, dict) else None
    if not isinstance(values, dict):
        return None, "not judged: the cell's answer holds no named values"
    return values, ""


def judge_cell(notebook: str, grade_id: str, max_score: float, cell: Optional[Dict[str, Any]],
               expected: Optional[Dict[str, Any]], worked_out: Optional[Dict[str, Any]] = None) -> CellVerdict:
    """The verdict on ``cell`` (None: not in the notebook) by the rule of ``grade_id`` against ``expected``
    (None: the grader holds no rule for it, and gives no point). ``worked_out``: the values the grader found
    itself (Ex. 3 and 4: from the notebook's commands), judged in place of what the cell handed in."""
    if expected is None or not has_rule(grade_id):
        return CellVerdict(notebook, grade_id, 0.0, max_score, "not judged: the grader holds no rule for this cell; "
                           "course staff will grade it (instructors: docs/instructors.md, a new graded cell)")
    if cell is None:
        return CellVerdict(notebook, grade_id, 0.0, max_score, "not judged: the cell is not in the notebook "
                           "handed in")
    if worked_out is not None and "not_judged" in worked_out:
        return CellVerdict(notebook, grade_id, 0.0, max_score, f"not judged: {worked_out['not_judged']}")
    values, why = (worked_out, "") if worked_out is not None else handed_in(cell)
    if values is None:
        return CellVerdict(notebook, grade_id, 0.0, max_score, why)
    verdict = apply_rule(grade_id, values, expected)
    source = WORKED_OUT.get(grade_id, "worked out by the grader") if worked_out is not None else "handed in"
    return CellVerdict(notebook, grade_id, max_score if verdict.passed else 0.0, max_score, verdict.message, values,
                       source)


def verdict_outputs(verdict: CellVerdict) -> List[Dict[str, Any]]:
    """The cell's outputs as the grader leaves them: what it handed in, then the grader's verdict."""
    outputs: List[Dict[str, Any]] = []
    if verdict.values is not None:
        shown = json.dumps(verdict.values, ensure_ascii=False, sort_keys=True)
        shown = shown if len(shown) <= _SUMMARY_CHARS else shown[:_SUMMARY_CHARS - 3] + "..."
        outputs.append({"output_type": "display_data", "metadata": {},
                        "data": {"text/plain": f"{verdict.source}: {shown}"}})
    points = "point" if verdict.max_score == 1 else "points"
    outputs.append({"output_type": "stream", "name": "stdout",
                    "text": f"the grader: {verdict.score:g} of {verdict.max_score:g} {points}: {verdict.message}\n"})
    return outputs


def _cells_by_id(notebook: Dict[str, Any]) -> Dict[str, Dict[str, Any]]:
    """grade id -> the first code cell carrying it (nbgrader restored the graded cells' metadata and source)."""
    found: Dict[str, Dict[str, Any]] = {}
    cells = notebook.get("cells")
    for cell in cells if isinstance(cells, list) else []:
        meta = cell.get("metadata") if isinstance(cell, dict) else None
        nbgrader = meta.get("nbgrader") if isinstance(meta, dict) else None
        grade_id = nbgrader.get("grade_id") if isinstance(nbgrader, dict) else None
        if isinstance(grade_id, str) and cell.get("cell_type") == "code":
            found.setdefault(grade_id, cell)
    return found


def _worked_out(folder: Path, notebook: Dict[str, Any], grade_ids: List[str]) -> Dict[str, Dict[str, Any]]:
    """grade id -> the values the grader found itself (:data:`WORKED_OUT`), for those among ``grade_ids``."""
    found = command_cells_values(folder, notebook, grade_ids)
    if "ex10_drives" in grade_ids:
        found["ex10_drives"] = ex10_values(folder)
    return found


def judge_notebook(name: str, notebook: Optional[Dict[str, Any]], tests: List[Tuple[str, float]],
                   expected: Dict[str, Optional[Dict[str, Any]]],
                   missing: str = "not judged: the notebook was not handed in",
                   folder: Optional[Path] = None) -> List[CellVerdict]:
    """Judge the autograded test cells ``tests`` ((grade id, points)) of ``notebook`` (None: there is none, and
    ``missing`` says why); each judged cell's outputs are replaced by the grader's verdict in ``notebook``.
    ``folder``: the notebook's, where the files its rosparam commands load are (Ex. 3 and 4)."""
    if notebook is None:
        return [CellVerdict(name, grade_id, 0.0, points, missing) for grade_id, points in tests]
    cells = _cells_by_id(notebook)
    worked_out = _worked_out(folder, notebook, [g for g, _ in tests if g in cells]) if folder is not None else {}
    verdicts = []
    for grade_id, points in tests:
        cell = cells.get(grade_id)
        verdict = judge_cell(name, grade_id, points, cell, expected.get(grade_id), worked_out.get(grade_id))
        if cell is not None:
            cell["outputs"] = verdict_outputs(verdict)
        verdicts.append(verdict)
    return verdicts


def _read_notebook(path: Path) -> Tuple[Optional[Dict[str, Any]], str]:
    """(the autograded notebook, "") or (None, why there is none to judge)."""
    if not os.path.lexists(path):
        return None, "not judged: the notebook was not handed in"
    try:
        notebook = json.loads(read_regular(path, MAX_AUTOGRADED_BYTES).decode("utf-8"))
    except UntrustedFileError as exc:
        return None, f"not judged: the autograded notebook could not be read ({_first_line(exc, _ERROR_CHARS)})"
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as exc:
        return None, f"not judged: the autograded notebook could not be read ({type(exc).__name__})"
    if not isinstance(notebook, dict) or not isinstance(notebook.get("cells"), list):
        return None, "not judged: the autograded notebook is no notebook"
    return notebook, ""


def _write_notebook(path: Path, notebook: Dict[str, Any]) -> None:
    """Replace ``path`` (never writing through a link that stands there)."""
    fd, scratch = tempfile.mkstemp(prefix=".judged-", suffix=".ipynb", dir=str(path.parent))
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(json.dumps(notebook, indent=1, sort_keys=True, ensure_ascii=False) + "\n")
        os.chmod(scratch, 0o644)
        os.replace(scratch, path)
    except BaseException:
        Path(scratch).unlink(missing_ok=True)
        raise


def _test_cells(db_url: str, course_id: str, student: str, assignment: str) -> Dict[str, List[Tuple[str, float]]]:
    """notebook -> (grade id, points) of its autograded test cells (graded code cells that are no answers)."""
    from nbgrader.api import Gradebook, MissingEntry  # noqa: PLC0415 - optional (not on Python 3.8): courses only

    found: Dict[str, List[Tuple[str, float]]] = {}
    gb = Gradebook(db_url, course_id)
    try:
        for notebook in gb.find_assignment(assignment).notebooks:
            try:
                submitted = gb.find_submission_notebook(notebook.name, assignment, student)
            except MissingEntry:
                continue
            for grade in submitted.grades:
                if grade.cell_type != "code":
                    continue
                try:
                    gb.find_solution_cell(grade.name, notebook.name, assignment)
                    continue  # code written by the student and graded by hand
                except MissingEntry:
                    found.setdefault(notebook.name, []).append((str(grade.name), float(grade.max_score)))
    finally:
        gb.close()
        gb.engine.dispose()
    return found


def _save_scores(db_url: str, course_id: str, student: str, assignment: str, verdicts: List[CellVerdict]) -> None:
    from nbgrader.api import Gradebook  # noqa: PLC0415 - optional (not on Python 3.8): courses only

    gb = Gradebook(db_url, course_id)
    try:
        for verdict in verdicts:
            grade = gb.find_grade(verdict.grade_id, verdict.notebook, assignment, student)
            grade.auto_score = verdict.score
            grade.needs_manual_grade = grade.manual_score is not None  # a grade given by hand stays, to review
        gb.db.commit()
    finally:
        gb.close()
        gb.engine.dispose()


def judge_submission(course_root: Path, db_url: str, course_id: str, student: str, assignment: str,
                     lock: Optional[threading.Lock] = None) -> List[CellVerdict]:
    """Judge every autograded test cell of ``student``'s autograded ``assignment``; scores into the gradebook,
    verdicts into the autograded notebooks. ``lock``: held while the gradebook is open (make grade's)."""
    guard = lock or threading.Lock()
    with guard:
        tests = _test_cells(db_url, course_id, student, assignment)
    folder = course_root / "autograded" / student / assignment
    verdicts: List[CellVerdict] = []
    for name, cells in sorted(tests.items()):
        expected = {grade_id: expectations(grade_id) if has_rule(grade_id) else None for grade_id, _ in cells}
        path = folder / f"{name}.ipynb"
        notebook, why = _read_notebook(path)
        verdicts += judge_notebook(name, notebook, cells, expected, why, folder)
        if notebook is not None:
            _write_notebook(path, notebook)
    with guard:
        _save_scores(db_url, course_id, student, assignment, verdicts)
    return verdicts


def judge_autograded(course_root: Path, db_url: str, course_id: str, student: str, assignment: str,
                     lock: Optional[threading.Lock] = None) -> str:
    """:func:`judge_submission`, and "" or the one line why it could not judge (the job is then not graded)."""
    from sqlalchemy.exc import SQLAlchemyError  # noqa: PLC0415 - nbgrader's, as above

    try:
        judge_submission(course_root, db_url, course_id, student, assignment, lock)
    except (NotebookJudgeError, SQLAlchemyError, OSError) as exc:
        return f"the grader could not judge the notebooks' answers: {_first_line(exc, 240)}"
    return ""
