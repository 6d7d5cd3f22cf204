"""One error base: every error class the toolkit defines derives from HriTeleopError (and keeps its
built-in base), and a node reports those in one line while a bug keeps its traceback."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from hri_teleop.core.errors import HriTeleopError

PACKAGE = Path(__file__).resolve().parents[2] / "hri_teleop"


def _error_classes():
    """(module path, class name, base names) of every class named *Error in hri_teleop."""
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef) and node.name.endswith("Error"):
                yield path.relative_to(PACKAGE.parent), node.name, [ast.unparse(b) for b in node.bases]


def test_every_error_class_of_the_toolkit_derives_from_the_one_base():
    classes = list(_error_classes())
    names = {name for _path, name, _bases in classes}
    assert len(classes) >= 40
    orphans = [f"{path}: {name}({', '.join(bases)})" for path, name, bases in classes
               if name != "HriTeleopError" and "HriTeleopError" not in bases
               and not any(base in names for base in bases)]
    assert orphans == []


def test_the_errors_keep_their_builtin_base():
    from hri_teleop.core.config import ConfigError
    from hri_teleop.ros.master import MasterError

    assert issubclass(ConfigError, ValueError) and issubclass(ConfigError, HriTeleopError)
    assert issubclass(MasterError, RuntimeError) and issubclass(MasterError, HriTeleopError)


@pytest.mark.parametrize("exc, ours", [
    ("ConfigError", True),
    ("TlxError", True),  # derives through MetricsError
    ("ValueError", False),  # a bug: its traceback is kept
    ("RuntimeError", False),
])
def test_a_node_reports_only_the_toolkits_errors_in_one_line(exc, ours):
    from hri_teleop.core.config import ConfigError
    from hri_teleop.core.experiment.tlx import TlxError
    from hri_teleop.ros.params import is_project_error

    kinds = {"ConfigError": ConfigError, "TlxError": TlxError, "ValueError": ValueError, "RuntimeError": RuntimeError}
    assert is_project_error(kinds[exc]("x")) is ours
