"""What a notebook cell calls besides nodes: scoring, the teleoperation check's halves, files.

``score`` is the last line of an autograded cell (prints the feedback, returns the points for
nbgrader's partial credit); ``fast``/``seconds`` shorten real-time cells under tests and grading.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import os
import sys
from pathlib import Path
from typing import Any, Union

from hri_teleop.course.errors import CourseError
from hri_teleop.grading.judge.checks import grade_teleoperation
from hri_teleop.grading.judge.compare import TELEOP
from hri_teleop.grading.results import feedback_text

__all__ = ["FAST_ENV", "fast", "seconds", "score", "show_file", "import_student_file",
           "grade_teleoperation_parts", "grade_teleoperation_node"]

PathLike = Union[str, Path]
#: Environment variables that make :func:`fast` true (nbgrader sets NBGRADER_EXECUTION).
FAST_ENV = ("HRI_NOTEBOOK_FAST", "NBGRADER_EXECUTION")


def fast() -> bool:
    """True under ``make test``, ``nbgrader validate`` and ``nbgrader autograde``: run real-time cells short."""
    return any(os.environ.get(name, "").strip().lower() not in ("", "0", "false", "no") for name in FAST_ENV)


def seconds(interactive_s: float, fast_s: float = 1.0) -> float:
    """How long a real-time cell runs: ``interactive_s`` for a student, ``fast_s`` under tests and grading."""
    return float(fast_s if fast() else interactive_s)


def score(result: Any) -> float:
    """Print a check's feedback and return its points: the last line of an autograded cell.

    nbgrader gives a test cell whose last value is a number that many points (partial
    credit), so a student loses the points of the parts that fail and keeps the rest,
    exactly as ``hri-grade`` and ``make grade`` score them.
    """
    print(feedback_text([result]))
    return float(result.score)


def _node_part_names() -> set:
    return {name for key, (name, _points) in TELEOP.items() if key.startswith("node_")}


def grade_teleoperation_parts(path: PathLike, **kwargs: Any) -> Any:
    """Ex. 8: the teleoperation check's parts of the class (gripper, sticks, toggle, rumble), no ROS node."""
    result = grade_teleoperation(path, node=False, **kwargs)
    node = _node_part_names()
    return dataclasses.replace(result, parts=[p for p in result.parts if p.name not in node])


def grade_teleoperation_node(path: PathLike, **kwargs: Any) -> Any:
    """Ex. 9: the teleoperation check's parts of the ROS node (topics, types, values with the virtual pad)."""
    result = grade_teleoperation(path, **kwargs)
    node = _node_part_names()
    failed_ex8 = [p.name for p in result.parts if p.name not in node and not p.passed]
    notes = tuple(result.notes) + ((f"Ex. 8 parts still failing (see notebook 08): {'; '.join(failed_ex8)}",)
                                   if failed_ex8 else ())
    return dataclasses.replace(result, parts=[p for p in result.parts if p.name in node], notes=notes)


def show_file(path: PathLike) -> Path:
    """Show where a student file is: a link that opens it in JupyterLab's editor, and its text."""
    target = Path(path)
    if not target.is_file():
        raise FileNotFoundError(f"{target}: not found next to this notebook; it comes with the assignment "
                                f"(restore it from the released version if you deleted it)")
    try:
        from IPython.display import Code, Markdown, display  # noqa: PLC0415 - plain Python has no IPython
    except ImportError:  # plain Python: print it
        print(f"{target.resolve()}\n{target.read_text(encoding='utf-8')}")
        return target
    language = {".py": "python", ".yaml": "yaml", ".launch": "xml"}.get(target.suffix, "text")
    display(Markdown(f"**[{target.as_posix()}]({target.as_posix()})** (click to edit; save with Ctrl+S) "
                     f"-- on disk: `{target.resolve()}`"))
    display(Code(target.read_text(encoding="utf-8"), language=language))
    return target


def import_student_file(path: PathLike) -> Any:
    """The student's Python file as a fresh module (re-read on every call, so edits take effect)."""
    script = Path(path)
    if not script.is_file():
        raise CourseError(f"{script}: no such file next to this notebook")
    name = f"student_{script.stem}"
    spec = importlib.util.spec_from_file_location(name, str(script.resolve()))
    module = importlib.util.module_from_spec(spec)
    sys.modules.pop(name, None)
    spec.loader.exec_module(module)  # type: ignore[union-attr]
    return module
