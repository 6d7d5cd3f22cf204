"""What a notebook cell calls besides nodes and checks: the student's files, and time.

``fast``/``seconds`` shorten real-time cells under tests and grading.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path
from typing import Any, Union

from hri_teleop.course.errors import CourseError, MissingFileError

__all__ = ["FAST_ENV", "fast", "seconds", "show_file", "import_student_file"]

PathLike = Union[str, Path]
#: Environment variables that make :func:`fast` true (nbgrader sets NBGRADER_EXECUTION).
FAST_ENV = ("HRI_NOTEBOOK_FAST", "NBGRADER_EXECUTION")


def fast() -> bool:
    """True under ``make test``, ``nbgrader validate`` and ``nbgrader autograde``: run real-time cells short."""
    return any(os.environ.get(name, "").strip().lower() not in ("", "0", "false", "no") for name in FAST_ENV)


def seconds(interactive_s: float, fast_s: float = 1.0) -> float:
    """How long a real-time cell runs: ``interactive_s`` for a student, ``fast_s`` under tests and grading."""
    return float(fast_s if fast() else interactive_s)


def show_file(path: PathLike) -> Path:
    """Show where a student file is: a link that opens it in JupyterLab's editor, and its text."""
    target = Path(path)
    if not target.is_file():
        raise MissingFileError(f"{target}: not found next to this notebook; it comes with the assignment "
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
    if spec is None or spec.loader is None:
        raise CourseError(f"{script}: Python cannot load it as a module; name it something.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.pop(name, None)
    spec.loader.exec_module(module)
    return module
