"""Every ``python -m hri_teleop...`` the toolkit tells a person to type runs: the module has a main guard.

The commands a message, a docstring or a page names are copied into terminals; a module that merely
imports (no ``if __name__ == "__main__"``, no ``__main__.py``) does nothing and says nothing. This reads
the package's strings (adjacent literals joined, as Python joins them), the lab's scripts, the pages
in docs/, the READMEs and the Makefiles.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path
from typing import Iterator, List, Optional, Tuple

ROOT = Path(__file__).resolve().parents[2]
COMMAND = re.compile(r"python3? -m (hri_teleop(?:\.\w+)*)(\.?<)?")
MAIN_GUARD = re.compile(r"""^if __name__ == ["']__main__["']:""", re.MULTILINE)
PAGES = ("docs/*.md", "*.md", "Makefile", "notebooks/**/*.md", "notebooks/**/*.ipynb", "notebooks/**/Makefile",
         "hri_lab/**/*.md", "grading/*.md", "firmware/*.md", "solutions/*.md", "tools/*.sh")


def commands_in(text: str) -> List[str]:
    """The modules of the ``python -m hri_teleop...`` commands in ``text`` (not a ``<placeholder>``'s)."""
    return [m.group(1) for m in COMMAND.finditer(text) if not m.group(2)]


def strings_of(source: str) -> Iterator[str]:
    """Every string literal of a Python source, adjacent literals joined as the parser joins them."""
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            yield node.value


def runnable(module: str) -> Optional[str]:
    """None when ``python -m module`` runs something, else why not."""
    path = ROOT.joinpath(*module.split("."))
    if path.is_dir():
        return None if (path / "__main__.py").is_file() else "a package without __main__.py"
    file = path.with_suffix(".py")
    if not file.is_file():
        return "no such module"
    return None if MAIN_GUARD.search(file.read_text(encoding="utf-8")) else "no `if __name__ == \"__main__\"`"


def _named() -> Iterator[Tuple[str, str]]:
    """(where, module) of every command named in the package, the lab's scripts and the pages."""
    for path in sorted(ROOT.glob("hri_teleop/**/*.py")) + sorted(ROOT.glob("hri_lab/scripts/*.py")):
        source = path.read_text(encoding="utf-8")
        if "python -m" not in source and "python3 -m" not in source:  # the rest need no parsing
            continue
        for text in strings_of(source):
            for module in commands_in(text):
                yield path.relative_to(ROOT).as_posix(), module
    for pattern in PAGES:
        for path in sorted(ROOT.glob(pattern)):
            for module in commands_in(path.read_text(encoding="utf-8")):
                yield path.relative_to(ROOT).as_posix(), module


def test_every_command_the_toolkit_names_runs():
    named = list(_named())
    assert len(named) > 20
    broken = sorted({f"{where}: python -m {module}: {runnable(module)}"
                     for where, module in named if runnable(module) is not None})
    assert broken == []


def test_a_command_split_over_two_literals_is_read_whole_and_a_placeholder_is_not_a_command():
    source = 'MSG = ("run `python -m hri_teleop.hardware.real."\n       "pad_check` to check")\n'
    assert [m for text in strings_of(source) for m in commands_in(text)] == ["hri_teleop.hardware.real.pad_check"]
    assert commands_in("each `python -m hri_teleop.ros.lab_twin.<module>`, and `python -m hri_teleop.apps.demo`") \
        == ["hri_teleop.apps.demo"]
    assert runnable("hri_teleop.hardware.real.pad_check") == "no such module"
    assert runnable("hri_teleop.core.fsr") is not None and runnable("hri_teleop.apps.demo") is None
