"""Check results make grade's files job wrote, for the notebooks' check cells of the same submission.

A check judges only its package's files, with the submission's seed, on the grader's clock: the
same files give the same parts. So the files job stores each result under a digest of the check,
the seed and every file, and a check cell whose package is byte for byte the same takes it. The
files job only writes, a notebook only reads (its kernel runs student code); outside make grade
nothing is stored or read (grading/README.md).
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path
from typing import Optional

from hri_teleop.grading.results import CheckResult
from hri_teleop.grading.run.untrusted_files import UntrustedFileError, read_regular
from hri_teleop.grading.run.workspace import DELIVERABLES, locate, package_files

__all__ = ["WRITE_ENV", "READ_ENV", "REUSED_NOTE", "package_digest", "store", "load"]

#: Set by make grade for its files jobs: the folder they store results in.
WRITE_ENV = "HRI_GRADE_RESULTS_WRITE"
#: Set by make grade for nbgrader's kernels: the folder their check cells read results from.
READ_ENV = "HRI_GRADE_RESULTS"
REUSED_NOTE = ("make grade graded these same files in its files job: this is that result (the check was not run "
               "a second time)")


def package_digest(root: Path) -> str:
    """SHA-256 over every file a check's workspace takes from the package: path and bytes (each read without
    following a link, under the size cap; one that cannot be read so counts as a marker of its own)."""
    files = set(package_files(root))
    files.update(p for p in (locate(root, key) for key in DELIVERABLES) if p is not None)
    digest = hashlib.sha256()
    for path in sorted(files):
        digest.update(os.path.relpath(path, root).encode("utf-8", "surrogateescape") + b"\0")
        try:
            digest.update(hashlib.sha256(read_regular(path, root=root)).digest())
        except UntrustedFileError as exc:
            digest.update(b"\0refused\0" + str(exc).encode("utf-8", "surrogateescape"))
    return digest.hexdigest()


def _entry(folder: Path, check: str, seed: int, root: Path) -> Path:
    key = hashlib.sha256(f"{check}\0{seed}\0{package_digest(root)}".encode()).hexdigest()
    return folder / f"{check}-{key[:32]}.json"


def store(folder: Path, check: str, seed: int, root: Path, result: CheckResult) -> None:
    """Keep ``result`` for a later reader of the same package (written whole or not at all)."""
    folder.mkdir(parents=True, exist_ok=True)
    data = result.to_dict()
    data["target"] = os.path.relpath(Path(result.target).resolve(), root.resolve()) if result.target else ""
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-")
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        json.dump(data, fh)
    os.replace(tmp, _entry(folder, check, seed, root))


def load(folder: Path, check: str, seed: int, root: Path) -> Optional[CheckResult]:
    """The stored result of ``check`` for this very package and seed, or None."""
    try:
        data = json.loads(_entry(folder, check, seed, root).read_text(encoding="utf-8"))
        result = CheckResult.from_dict(data)
    except (OSError, ValueError, KeyError, TypeError):
        return None
    target = str(root / result.target) if result.target else ""
    return CheckResult(result.check, target, result.parts, result.seed, result.duration_s,
                       tuple(result.notes) + (REUSED_NOTE,))
