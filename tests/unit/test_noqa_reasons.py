"""Every ``noqa`` in the checkout names its rules and says why: ``# noqa: PLC0415 - <why here>``.

A silenced rule is a decision; the next reader needs its reason on the same line (docs/architecture.md,
"Tooling"). ruff checks that a noqa still silences something (RUF100) but not that it says why, so this
test reads every comment of the files ruff lints (Python files and notebooks' code cells).
"""

from __future__ import annotations

import io
import json
import os
import re
import tokenize
from pathlib import Path
from typing import Iterator, List, Tuple

ROOT = Path(__file__).resolve().parents[2]
#: Folders ruff does not lint (its defaults and pyproject's extend-exclude) or that are not the project's.
SKIPPED = {".git", ".venv", ".venv38", "out", "build", "dist", "node_modules", "__pycache__", ".mypy_cache",
           ".ruff_cache", ".hypothesis", ".ipynb_checkpoints", "hri_teleop.egg-info"}
NOQA = re.compile(r"#\s*noqa\b", re.IGNORECASE)
#: The project's form: the word noqa, a colon, the codes (commas between), then a dash and words.
WITH_REASON = re.compile(r"#\s*noqa:\s*[A-Z]+[0-9]+(\s*,\s*[A-Z]+[0-9]+)*\s+-\s+\w")


def comments(source: str) -> Iterator[Tuple[int, str]]:
    """(line, text) of each comment in ``source``; each line with a ``#`` when it does not tokenize (a magic)."""
    try:
        for token in tokenize.generate_tokens(io.StringIO(source).readline):
            if token.type == tokenize.COMMENT:
                yield token.start[0], token.string
    except (tokenize.TokenError, IndentationError, SyntaxError):
        for number, line in enumerate(source.splitlines(), start=1):
            if "#" in line:
                yield number, line[line.index("#"):]


def noqa_without_reason(source: str) -> List[Tuple[int, str]]:
    """(line, comment) of each noqa in ``source`` that does not name its codes and a reason."""
    found: List[Tuple[int, str]] = []
    if not NOQA.search(source):  # most files: no need to tokenize them
        return found
    for number, text in comments(source):
        for match in NOQA.finditer(text):
            if not WITH_REASON.match(text, match.start()):
                found.append((number, text.strip()))
    return found


def _sources() -> Iterator[Tuple[str, str]]:
    """(where, source) of every Python file and notebook code cell of the checkout."""
    for folder, subfolders, files in os.walk(ROOT):
        subfolders[:] = sorted(d for d in subfolders if d not in SKIPPED)
        for name in sorted(files):
            yield from _file_sources(Path(folder) / name)


def _file_sources(path: Path) -> Iterator[Tuple[str, str]]:
    relative = path.relative_to(ROOT)
    if path.suffix == ".py":
        yield relative.as_posix(), path.read_text(encoding="utf-8")
    elif path.suffix == ".ipynb":
        cells = json.loads(path.read_text(encoding="utf-8")).get("cells", [])
        for index, cell in enumerate(cells):
            if cell.get("cell_type") == "code":
                source = cell.get("source", "")
                yield f"{relative.as_posix()} cell {index}", "".join(source) if isinstance(source, list) else source


def test_every_noqa_in_the_checkout_says_why():
    bare = [f"{where}:{line}: {text}" for where, source in _sources() for line, text in noqa_without_reason(source)]
    assert bare == [], "write it as '# noqa: CODE - why here'"


def test_the_files_read_include_the_package_tests_and_notebooks():
    where = [w for w, _source in _sources()]
    assert any(w.startswith("hri_teleop/") for w in where) and any(w.startswith("tests/") for w in where)
    assert any(".ipynb cell" in w for w in where)


def test_a_noqa_without_codes_or_reason_is_found_and_one_in_a_string_is_not():
    source = ("import os  # noqa: F401\n"
              "import re  # noqa\n"
              "import sys  # noqa: F401 - only to fail early\n"
              "import io  # noqa: F401, PLC0415 - why\n"
              "import json  # NOQA: F401 (a reason, not in the project's form)\n"
              "TEXT = '# noqa: E501'\n")
    assert [line for line, _text in noqa_without_reason(source)] == [1, 2, 5]
    assert noqa_without_reason("%matplotlib inline\nimport os  # noqa: F401\n") == [(2, "# noqa: F401")]
