"""A message a person reads is raised as one of the toolkit's errors, not as a bare ValueError.

The toolkit's errors (:class:`hri_teleop.core.errors.HriTeleopError`) are the ones a node, a cell or
the grader prints as one line; a plain built-in is a bug and keeps its traceback. So a ``raise
ValueError("...")`` (or KeyError, TypeError, RuntimeError, OSError, FileNotFoundError) with a message in hri_teleop is either one
of the few internal checks listed in INTERNAL below, each with why no person ever reads it, or a
mistake: it should raise the module's own error class (``HriTeleopError`` and the same built-in).
"""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Dict, Iterator, List, Tuple

import pytest

from hri_teleop.core.errors import HriTeleopError

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "hri_teleop"
#: The built-ins a message must not be raised as, outside INTERNAL.
PLAIN = ("ValueError", "KeyError", "TypeError", "RuntimeError", "OSError", "FileNotFoundError")
#: (module, enclosing function, built-in) -> why the raise is a programming error no person reads.
INTERNAL: Dict[Tuple[str, str, str], str] = {
    ("hri_teleop/core/paramfile.py", "_Tag.value_of", "KeyError"):
        "called only for an attribute the caller has checked is there: firing is a bug in paramfile",
    ("hri_teleop/grading/results.py", "CheckResult.part", "KeyError"):
        "a lookup by part name for code and tests; a wrong name is the caller's bug, and KeyError is a lookup's error",
    ("hri_teleop/grading/session.py", "_observe", "TypeError"):
        "every plan the judge builds has a session; another type is a bug in the grader",
    ("hri_teleop/course/answers.py", "_read_capped", "OSError"):
        "a file reader's contract: rosparam_model.file_reader turns an OSError into the command's note",
    ("hri_teleop/grading/run/probe.py", "rosparam_commands.read", "OSError"):
        "a file reader's contract in the grader's box: rosparam_model.file_reader makes it the command's note",
    ("hri_teleop/grading/run/probe.py", "rosparam_commands.read", "FileNotFoundError"):
        "a file reader's contract in the grader's box: rosparam_model.file_reader makes it the command's note",
}


def plain_raises(source: str, plain: Tuple[str, ...] = PLAIN) -> List[Tuple[str, str, int]]:
    """(enclosing function, built-in, line) of each ``raise Builtin(message, ...)`` in ``source``."""
    found: List[Tuple[str, str, int]] = []

    def visit(node: ast.AST, scope: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                visit(child, f"{scope}.{child.name}" if scope else child.name)
                continue
            if (isinstance(child, ast.Raise) and isinstance(child.exc, ast.Call)
                    and isinstance(child.exc.func, ast.Name) and child.exc.func.id in plain
                    and (child.exc.args or child.exc.keywords)):
                found.append((scope, child.exc.func.id, child.lineno))
            visit(child, scope)

    visit(ast.parse(source), "")
    return found


def _package_raises() -> Iterator[Tuple[str, str, str, int]]:
    for path in sorted(PACKAGE.rglob("*.py")):
        relative = path.relative_to(ROOT).as_posix()
        for scope, name, line in plain_raises(path.read_text(encoding="utf-8")):
            yield relative, scope, name, line


def test_no_message_for_a_person_is_raised_as_a_plain_builtin():
    outside = [f"{path}:{line}: raise {name}(...) in {scope or 'the module'}"
               for path, scope, name, line in _package_raises() if (path, scope, name) not in INTERNAL]
    assert outside == [], ("raise the module's error class (HriTeleopError and the same built-in), "
                           "or list the raise in INTERNAL with why no person reads it")


def test_every_internal_raise_listed_is_still_there_and_says_why():
    there = {(path, scope, name) for path, scope, name, _line in _package_raises()}
    assert [key for key in INTERNAL if key not in there] == []
    assert all(len(reason) > 20 for reason in INTERNAL.values())


def test_the_scan_finds_a_plain_raise_with_a_message_and_its_function():
    source = ("class A:\n    def f(self):\n        raise ValueError('x must be > 0')\n"
              "def g():\n    raise KeyError\n"
              "def h():\n    raise LookupError('not one of PLAIN')\n"
              "raise TypeError(f'{1}')\n")
    assert plain_raises(source) == [("A.f", "ValueError", 3), ("", "TypeError", 8)]


@pytest.mark.parametrize("module, name", [
    ("hri_teleop.sim.operators", "OperatorError"),
    ("hri_teleop.plots.study", "StudyFigureError"),
    ("hri_teleop.core.rosserial_frames", "FrameError"),
])
def test_operator_figure_and_frame_errors_are_the_toolkits_and_still_value_errors(module, name):
    import importlib

    cls = getattr(importlib.import_module(module), name)
    assert issubclass(cls, HriTeleopError) and issubclass(cls, ValueError)
    assert name in importlib.import_module(module).__all__


def test_a_study_operator_with_an_unknown_condition_says_which_ones_there_are():
    from hri_teleop.sim.operators import OperatorError, study_operator, study_scenario

    with pytest.raises(OperatorError, match="condition must be feedback or no_feedback, got 'fast'"):
        study_operator("fast", 1)
    with pytest.raises(OperatorError, match="give the object's width in m"):
        study_operator("feedback", 1, object_width_m=0.2)
    with pytest.raises(ValueError, match="use one of"):  # except ValueError still catches it
        study_scenario("feedback", 1, "cup")


def test_a_study_figure_with_too_few_calibrations_says_to_give_one_per_trial_or_one():
    from hri_teleop.plots.study import StudyFigureError, draw_study

    with pytest.raises(StudyFigureError, match="2 values for 0 trials; give one per trial or one for all"):
        draw_study([], [1.0, 2.0])


@pytest.mark.parametrize("decoder, payload", [
    ("decode_topic_info", b"\x01"), ("decode_time", b"\x01"), ("decode_param_request", b"\x05"),
    ("decode_param_answer", b"\x02\x00\x00\x00\x01"), ("decode_int16", b"\x01\x02\x03"),
    ("decode_log", b""), ("decode_log", b"\x01\x09\x00"),
])
def test_a_malformed_rosserial_message_is_one_line_naming_the_fix(decoder, payload):
    from hri_teleop.core import rosserial_frames

    with pytest.raises(rosserial_frames.FrameError) as caught:
        getattr(rosserial_frames, decoder)(payload)
    message = str(caught.value)
    assert "\n" not in message and "make_libraries.py" in message


def test_a_student_file_missing_from_show_file_is_one_line_and_still_a_file_not_found_error(tmp_path):
    from hri_teleop.course.cells import show_file
    from hri_teleop.course.errors import MissingFileError

    with pytest.raises(FileNotFoundError) as caught:
        show_file(tmp_path / "mapping_node.py")
    assert isinstance(caught.value, MissingFileError) and isinstance(caught.value, HriTeleopError)
    assert caught.value._render_traceback_() == [f"MissingFileError: {caught.value}"]  # IPython: one line
    assert "restore it from the released version" in str(caught.value)
