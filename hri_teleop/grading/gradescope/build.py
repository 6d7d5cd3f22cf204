"""``make gradescope``: the autograder zip Gradescope takes (setup.sh and run_autograder at its root).

The zip's root becomes /autograder/source: the two scripts, the assignment's settings
(gradescope.json), the toolkit's files the grader needs (the package, the lab's files, the
public traces, the setup scripts) and the course's notebooks with their answers removed
(course/, for uploaded notebooks). The answer key and the tests stay out of it.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Iterator, List, Sequence, Tuple

from hri_teleop.core.paths import REPO
from hri_teleop.grading.checks import CHECKS
from hri_teleop.grading.gradescope.container import CONFIG_NAME, Config
from hri_teleop.grading.gradescope.notebooks import course_members
from hri_teleop.grading.points import check_cell_problems
from hri_teleop.grading.results import GradingError

__all__ = ["SOURCE_PATHS", "SCRIPTS", "zip_members", "build_zip"]

#: What of the checkout goes into the zip (folders whole, less caches).
SOURCE_PATHS: Tuple[str, ...] = ("hri_teleop", "hri_lab", "grading/traces", "tools/setup.sh", "tools/env.sh",
                                 "tools/kernel.sh",
                                 "pyproject.toml", "setup.py", "constraints.txt", "README.md")
#: The two files Gradescope needs at the zip's root.
SCRIPTS: Tuple[str, ...] = ("setup.sh", "run_autograder")
_FILES = Path(__file__).resolve().parent / "files"
_SKIP = {"__pycache__", ".mypy_cache", ".pytest_cache", ".ruff_cache"}


def zip_members(repo: Path = REPO) -> Iterator[Tuple[Path, str]]:
    """(file on disk, name in the zip) for the toolkit's files, sorted."""
    for relative in SOURCE_PATHS:
        path = repo / relative
        if not path.exists():
            raise GradingError(f"{path}: missing from the checkout; make gradescope needs it (a full clone)")
        files = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
        for file in files:
            rel = file.relative_to(repo)
            if not _SKIP.intersection(rel.parts) and file.suffix != ".pyc":
                yield file, rel.as_posix()


def _add(zf: zipfile.ZipFile, source: Path, name: str) -> None:
    _add_bytes(zf, source.read_bytes(), name, 0o755 if source.stat().st_mode & 0o111 else 0o644)


def _add_bytes(zf: zipfile.ZipFile, data: bytes, name: str, mode: int = 0o644) -> None:
    info = zipfile.ZipInfo(name, date_time=(2020, 1, 1, 0, 0, 0))  # the same bytes for the same files
    info.external_attr = (mode | 0o100000) << 16
    info.compress_type = zipfile.ZIP_DEFLATED
    zf.writestr(info, data)


def build_zip(out_dir: Path, checks: Sequence[str] = tuple(CHECKS), repo: Path = REPO,
              unsandboxed: bool = False) -> Path:
    """Write ``out_dir/autograder.zip`` for an assignment grading ``checks``; its path. ``unsandboxed``: its
    run_autograder grades uploaded notebooks with the grader's rights where bubblewrap cannot run."""
    unknown = [c for c in checks if c not in CHECKS]
    if unknown or not checks:
        raise GradingError(f"unknown or no checks {unknown}; use some of {', '.join(CHECKS)}")
    counted_twice = check_cell_problems(repo / "notebooks" / "source")
    if counted_twice:  # a check's points are the files' tests': a graded check cell would count them again
        raise GradingError(counted_twice[0])
    out_dir.mkdir(parents=True, exist_ok=True)
    target = out_dir / "autograder.zip"
    names: List[str] = []
    with zipfile.ZipFile(target.with_suffix(".tmp"), "w") as zf:
        for script in SCRIPTS:
            _add(zf, _FILES / script, script)
        config = zipfile.ZipInfo(CONFIG_NAME, date_time=(2020, 1, 1, 0, 0, 0))
        config.external_attr = 0o100644 << 16
        zf.writestr(config, json.dumps(Config(tuple(checks), unsandboxed=unsandboxed).to_json(), indent=2) + "\n")
        for source, name in zip_members(repo):
            _add(zf, source, name)
            names.append(name)
        for name, data in course_members(repo / "notebooks"):
            _add_bytes(zf, data, name)
    target.with_suffix(".tmp").replace(target)
    return target
