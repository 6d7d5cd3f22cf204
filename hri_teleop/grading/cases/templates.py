"""Student templates from the answer key: the marked solution regions of ``solutions/`` removed.

Student deliverables have one source of truth, the completed files in ``solutions/``: a template
edited by hand drifts from the answer key (a renamed method, a new parameter) and students then
fill in code the grader no longer calls. Removing the regions mechanically keeps both in step, and
a template can be proven to hold no solution code. The markers and hints: solutions/README.md.
"""

from __future__ import annotations

import re
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import List, Sequence, Tuple, Union

from hri_teleop.core.errors import HriTeleopError

__all__ = ["TemplateError", "KINDS", "kind_of", "make_template", "make_answer", "has_markers", "solution_lines",
           "empty_regions", "generate_templates", "generate_answers", "GeneratedFile"]

_BEGIN = re.compile(r"^(?P<indent>\s*)(?:#+\s*|<!--\s*(?:###\s*)?)BEGIN SOLUTION\s*(?:-->)?\s*$")
_END = re.compile(r"^\s*(?:#+\s*|<!--\s*(?:###\s*)?)END SOLUTION\s*(?:-->)?\s*$")
_ANY_MARKER = re.compile(r"(BEGIN|END) SOLUTION")


def _split_regions(text: str) -> Tuple[List[str], List[str]]:
    """(the lines outside the solution regions, markers included; the lines inside them)."""
    outside: List[str] = []
    inside: List[str] = []
    within = False
    for line in text.split("\n"):
        if _BEGIN.match(line) or _END.match(line):
            within = bool(_BEGIN.match(line))
            outside.append(line)
        else:
            (inside if within else outside).append(line)
    return outside, inside


def solution_lines(text: str) -> List[str]:
    """The lines inside the solution regions of ``text`` (markers left out): what only the answer key has."""
    return _split_regions(text)[1]


def empty_regions(text: str) -> str:
    """``text`` with its solution regions' lines removed and the marker lines kept (nbgrader's
    generate_assignment puts a notebook's stubs back between them)."""
    return "\n".join(_split_regions(text)[0])

#: File suffix -> language of the hint.
KINDS = {".py": "python", ".yaml": "yaml", ".yml": "yaml", ".launch": "xml", ".xml": "xml"}
#: Files whose language is in their name, not their suffix.
NAMED_KINDS = {"CMakeLists.txt": "cmake"}


class TemplateError(HriTeleopError, ValueError):
    """A solution file's markers are unbalanced or in a file type without a hint (one line: where, fix)."""


def kind_of(path: Union[str, Path]) -> str:
    """"python", "yaml" or "xml" for a file name; TemplateError for other suffixes."""
    if Path(path).name in NAMED_KINDS:
        return NAMED_KINDS[Path(path).name]
    suffix = Path(path).suffix.lower()
    if suffix not in KINDS:
        raise TemplateError(f"{path}: no template rule for '{suffix}' files; use one of {', '.join(sorted(KINDS))} "
                            "or leave the solution markers out of it")
    return KINDS[suffix]


def _hint(kind: str, indent: str) -> List[str]:
    if kind == "python":
        return [f"{indent}# YOUR CODE HERE", f"{indent}raise NotImplementedError()"]
    if kind in ("yaml", "cmake"):
        return [f"{indent}# YOUR CODE HERE"]
    return [f"{indent}<!-- YOUR CODE HERE -->"]


def _regions(lines: List[str], source: str) -> List[Tuple[int, int, str]]:
    """(begin line index, end line index, indent) of every region; TemplateError if unbalanced."""
    regions: List[Tuple[int, int, str]] = []
    open_at = -1
    indent = ""
    for number, line in enumerate(lines):
        begin, end = _BEGIN.match(line), _END.match(line)
        if begin:
            if open_at >= 0:
                raise TemplateError(f"{source}:{number + 1}: BEGIN SOLUTION inside the region opened at line "
                                    f"{open_at + 1}; close it with END SOLUTION first")
            open_at, indent = number, begin.group("indent")
        elif end:
            if open_at < 0:
                raise TemplateError(f"{source}:{number + 1}: END SOLUTION without a BEGIN SOLUTION above it; "
                                    "add the BEGIN marker or remove this line")
            regions.append((open_at, number, indent))
            open_at = -1
        elif _ANY_MARKER.search(line):
            raise TemplateError(f"{source}:{number + 1}: a solution marker that is not alone on its line: {line.strip()!r}; "
                                "write it as a comment line of its own")
    if open_at >= 0:
        raise TemplateError(f"{source}:{open_at + 1}: BEGIN SOLUTION is never closed; add END SOLUTION after the answer")
    return regions


def has_markers(text: str) -> bool:
    """True if ``text`` contains any solution marker (a template must not)."""
    return bool(_ANY_MARKER.search(text))


def make_template(text: str, kind: str, source: str = "<text>") -> str:
    """``text`` with every solution region replaced by the hint of ``kind``."""
    lines = text.split("\n")
    out: List[str] = []
    position = 0
    for begin, end, indent in _regions(lines, source):
        out.extend(lines[position:begin])
        out.extend(_hint(kind, indent))
        position = end + 1
    out.extend(lines[position:])
    return "\n".join(out)


def make_answer(text: str, source: str = "<text>") -> str:
    """``text`` with the marker lines removed and the answers kept (what a student should hand in)."""
    lines = text.split("\n")
    markers = {i for begin, end, _ in _regions(lines, source) for i in (begin, end)}
    return "\n".join(line for i, line in enumerate(lines) if i not in markers)


@dataclass(frozen=True)
class GeneratedFile:
    source: Path
    target: Path
    regions: int


def generate_templates(solutions_dir: Union[str, Path], out_dir: Union[str, Path],
                       not_executable: Sequence[str] = ()) -> List[GeneratedFile]:
    """Write the template of every file under ``solutions_dir`` to the same place under ``out_dir``.

    Files without markers are copied as they are (README.md is the instructors' and is
    skipped); a link is copied as the file it points at. Executable bits are kept, so a
    template script runs with ``rosrun``, except for the ``not_executable`` paths (relative
    to the package): the handout has students ``chmod +x`` those themselves.
    ``out_dir`` is replaced, never merged: a file removed from the answer key must not
    linger in the student bundle.
    """
    root, out = Path(solutions_dir), Path(out_dir)
    if not root.is_dir():
        raise TemplateError(f"{root}: no such folder; pass the answer key folder (solutions/)")
    if out.resolve() == root.resolve() or root.resolve() in out.resolve().parents:
        raise TemplateError(f"{out}: inside the answer key {root}; write the templates somewhere else, e.g. build/templates")
    written: List[GeneratedFile] = []
    if out.exists():
        shutil.rmtree(out)
    for path in sorted(p for p in root.rglob("*") if p.is_file()):
        relative = path.relative_to(root)
        if relative == Path("README.md") or "__pycache__" in relative.parts:
            continue
        text = path.read_text(encoding="utf-8")
        target = out / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        count = len(_regions(text.split("\n"), str(path))) if has_markers(text) else 0
        target.write_text(make_template(text, kind_of(path), str(path)) if count else text, encoding="utf-8")
        shutil.copymode(path, target)
        if relative.as_posix() in not_executable:
            target.chmod(target.stat().st_mode & ~0o111)
        written.append(GeneratedFile(path, target, count))
    return written


def generate_answers(solutions_dir: Union[str, Path], out_dir: Union[str, Path]) -> Path:
    """The answer key as a good student hands it in: every file under ``solutions_dir`` (README.md, the
    instructors', skipped) written under ``out_dir`` with the marker lines dropped, its mode kept. Returns ``out_dir``."""
    root, out = Path(solutions_dir), Path(out_dir)
    if not root.is_dir():
        raise TemplateError(f"{root}: no such folder; pass the answer key folder (solutions/)")
    for path in sorted(p for p in root.rglob("*") if p.is_file()):
        relative = path.relative_to(root)
        if relative == Path("README.md") or "__pycache__" in relative.parts:
            continue
        target = out / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(make_answer(path.read_text(encoding="utf-8"), str(path)), encoding="utf-8")
        shutil.copymode(path, target)
    return out
