"""Finding a student's hri_lab and notebooks in a Gradescope upload, whatever its folder layout.

Students upload a zip of their package, the folder that holds it, a zip inside a zip, or the files
loose (Gradescope's drag and drop), often with macOS' ``__MACOSX`` and ``._`` copies. The grader
needs one ``hri_lab`` folder: this module unpacks the upload, picks the folder holding most of the
deliverables, fills what it lacks from files of the same name elsewhere, and says what it did.
"""

from __future__ import annotations

import os
import shutil
import stat
import zipfile
import zlib
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Dict, List, Optional, Sequence, Tuple

from hri_teleop.grading.results import GradingError
from hri_teleop.grading.run.untrusted_files import copy_tree
from hri_teleop.grading.run.workspace import DELIVERABLES

__all__ = ["Upload", "PACKAGE_FILES", "MAX_UNPACKED_BYTES", "MAX_UPLOAD_FILES", "MAX_ZIP_DEPTH", "find_upload",
           "is_junk", "printable"]

#: Files of the student's package the checks read: the deliverables and what catkin-package judges.
PACKAGE_FILES: Tuple[str, ...] = tuple(DELIVERABLES.values()) + ("CMakeLists.txt", "package.xml",
                                                                  "scripts/gripper_manager.py")
#: An upload that unpacks to more than this is refused (a zip bomb must not fill the grader's disk).
MAX_UNPACKED_BYTES = 200 * 1024 * 1024
#: ... and one that holds more files than this (zips inside zips counted in).
MAX_UPLOAD_FILES = 5000
#: Zips inside zips are opened this deep (the upload itself is depth 0).
MAX_ZIP_DEPTH = 3
_JUNK_DIRS = {"__MACOSX", ".git", ".ipynb_checkpoints", "__pycache__", ".idea", ".vscode", "build", "devel"}
_JUNK_FILES = {".DS_Store", "Thumbs.db", "desktop.ini"}


@dataclass
class Upload:
    """What was found: the assembled package (always a folder, maybe empty), notebooks, and what was done."""

    hri_lab: Path
    notebooks: List[Path] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)
    found: List[str] = field(default_factory=list)  # the package files found, relative to hri_lab


def is_junk(relative: PurePosixPath) -> bool:
    """True for what an archiver or an editor adds (``__MACOSX``, ``._x``, ``.DS_Store``, checkpoints)."""
    return (any(part in _JUNK_DIRS for part in relative.parts[:-1]) or relative.name in _JUNK_FILES
            or relative.name.startswith("._") or relative.name in _JUNK_DIRS)


class _Budget:
    """What the rest of the upload may still unpack to: bytes and files (a zip bomb stops here)."""

    def __init__(self) -> None:
        self.bytes = MAX_UNPACKED_BYTES
        self.files = MAX_UPLOAD_FILES

    def take(self, size: int, where: str) -> None:
        self.bytes -= size
        self.files -= 1
        if self.bytes < 0:
            raise GradingError(f"{where} unpacks to more than {MAX_UNPACKED_BYTES // 2**20} MB; upload only your "
                               "hri_lab folder (no bags, builds or videos)")
        if self.files < 0:
            raise GradingError(f"{where} holds more than {MAX_UPLOAD_FILES} files; upload only your hri_lab folder "
                               "(no builds, no virtual environments)")


def printable(text: str) -> str:
    """``text`` with what is not valid UTF-8 (a file name's stray bytes) shown as U+FFFD and control characters
    (a newline in a name) as ``?``: one line of the output, valid in any JSON parser."""
    text = text.encode("utf-8", "surrogateescape").decode("utf-8", "replace")
    return "".join(c if c.isprintable() else "?" for c in text)


def _left_out(where: str, skipped: Sequence[Tuple[str, str]]) -> List[str]:
    """One note naming what of ``where`` was not unpacked, and why (the first few)."""
    if not skipped:
        return []
    shown = "; ".join(f"{printable(name)} ({why})" for name, why in skipped[:5])
    more = f" and {len(skipped) - 5} more" if len(skipped) > 5 else ""
    return [f"left out of {where}: {shown}{more}; upload plain files and folders only"]


def _member_kind(info: zipfile.ZipInfo) -> str:
    """"" for a plain file member, else why it is left out (a link, a device, a FIFO in the zip's unix mode)."""
    kind = stat.S_IFMT(info.external_attr >> 16) if info.create_system == 3 else 0
    if not kind or stat.S_ISREG(kind):
        return ""
    return "a link (the grader follows none)" if stat.S_ISLNK(kind) else "not a regular file"


def _write_member(zf: zipfile.ZipFile, info: zipfile.ZipInfo, into: Path, parts: Tuple[str, ...]) -> str:
    """Write one member below ``into`` (only folders and files the grader made on the way): "" or why not."""
    folder = into
    for part in parts[:-1]:
        folder = folder / part
        if folder.is_symlink() or (folder.exists() and not folder.is_dir()):
            return "a file and a folder of the same name"
        folder.mkdir(exist_ok=True)
    target = folder / parts[-1]
    if target.is_symlink() or target.is_dir():
        return "a file and a folder of the same name"
    try:
        fd = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
    except (OSError, ValueError) as exc:
        return f"cannot be written here ({getattr(exc, 'strerror', None) or exc})"
    with os.fdopen(fd, "wb") as dst, zf.open(info) as src:
        shutil.copyfileobj(src, dst)
    mode = (info.external_attr >> 16) & 0o777
    target.chmod((mode or 0o644) | 0o444)
    return ""


def _extract(archive: Path, into: Path, budget: _Budget) -> List[str]:
    """Unpack ``archive`` into ``into``: no member outside it, junk, links and special files left out (named in
    the notes it returns), unix modes kept; GradingError (one line) for a zip that cannot be read or is too big."""
    shown = printable(archive.name)
    skipped: List[Tuple[str, str]] = []
    try:
        with zipfile.ZipFile(archive) as zf:
            for info in zf.infolist():
                name = PurePosixPath(info.filename.replace("\\", "/"))
                if info.is_dir() or is_junk(name):
                    continue
                if name.is_absolute() or ".." in name.parts:
                    raise GradingError(f"{shown}: member {printable(info.filename)!r} points outside the archive; "
                                       "zip your hri_lab folder with a normal zip tool and upload again")
                budget.take(info.file_size, shown)
                parts = tuple(p for p in name.parts if p not in ("", "."))
                why = _member_kind(info) or ("" if parts else "no name")
                if not why:
                    try:
                        why = _write_member(zf, info, into, parts)
                    except (RuntimeError, NotImplementedError) as exc:  # encrypted, an unknown compression
                        why = f"cannot be unpacked ({exc})"
                if why:
                    skipped.append((info.filename, why))
    except (zipfile.BadZipFile, zlib.error, EOFError, UnicodeDecodeError, ValueError, OSError) as exc:
        why = (printable(str(exc)).splitlines() or [type(exc).__name__])[0][:200]
        raise GradingError(f"{shown}: not a readable zip ({why}); make it again and upload it") from exc
    return _left_out(shown, skipped)


def _copy_upload(submission: Path, into: Path) -> List[str]:
    """The upload copied to ``into`` with every zip unpacked beside it (``x.zip`` -> ``x.zip.d/``): regular
    files and folders only, never through a link (:mod:`hri_teleop.grading.run.untrusted_files`)."""
    budget = _Budget()
    report = copy_tree(submission, into, limit_bytes=MAX_UNPACKED_BYTES, max_files=MAX_UPLOAD_FILES,
                       file_limit_bytes=MAX_UNPACKED_BYTES, skip_dirs=tuple(sorted(_JUNK_DIRS)))
    if any(why.startswith("past the first") for _, why in report.skipped):
        raise GradingError(f"the upload holds more than {MAX_UPLOAD_FILES} files; upload only your hri_lab folder")
    if any("larger than" in why for _, why in report.skipped) or report.bytes > MAX_UNPACKED_BYTES:
        raise GradingError(f"the upload is larger than {MAX_UNPACKED_BYTES // 2**20} MB; upload only your "
                           "hri_lab folder (no bags, builds or videos)")
    notes = _left_out("the upload", [(rel, why) for rel, why in report.skipped if not is_junk(PurePosixPath(rel))])
    budget.bytes -= report.bytes
    budget.files -= len(report.copied)
    for rel in report.copied:
        target = into / rel
        if is_junk(PurePosixPath(rel)):
            target.unlink()
            continue
        st = os.lstat(submission / rel)
        if stat.S_ISREG(st.st_mode):  # the student's modes (scripts stay executable), readable by all
            target.chmod(stat.S_IMODE(st.st_mode) & 0o777 | 0o444)
    for _depth in range(MAX_ZIP_DEPTH):
        archives = [p for p in sorted(into.rglob("*")) if p.is_file() and not p.is_symlink()
                    and p.suffix.lower() == ".zip" and not p.with_name(p.name + ".d").exists()]
        for archive in archives:
            target = archive.with_name(archive.name + ".d")
            target.mkdir()
            notes.append(f"opened {_shown(archive.relative_to(into))}")
            notes.extend(_extract(archive, target, budget))
        if not archives:
            break
    return notes


def _shown(relative: Path) -> str:
    """A path of the upload as the student knows it (``x.zip.d/`` reads as ``x.zip/``)."""
    return printable("/".join(part[:-2] if part.endswith(".zip.d") else part for part in relative.parts) or ".")


def _best_folder(root: Path) -> Tuple[Optional[Path], int]:
    """The folder holding most package files at their places (ties: named hri_lab, then the shallowest)."""
    best: Optional[Path] = None
    best_key: Tuple[int, int, int] = (0, 0, 0)
    for folder in [root] + sorted(p for p in root.rglob("*") if p.is_dir()):
        count = sum((folder / relative).is_file() for relative in PACKAGE_FILES)
        key = (count, int(folder.name == "hri_lab"), -len(folder.relative_to(root).parts))
        if count and key > best_key:
            best, best_key = folder, key
    return best, best_key[0]


def _loose_files(root: Path, skip: Optional[Path]) -> Dict[str, List[Path]]:
    """file name -> files of that name outside the chosen folder, shallowest first."""
    names = {PurePosixPath(relative).name for relative in PACKAGE_FILES}
    found: Dict[str, List[Path]] = {}
    for path in root.rglob("*"):
        if path.is_file() and path.name in names and (skip is None or skip not in path.parents):
            found.setdefault(path.name, []).append(path)
    for paths in found.values():
        paths.sort(key=lambda p: (len(p.parts), str(p)))
    return found


def find_upload(submission: Path, work: Path, package_files: Sequence[str] = PACKAGE_FILES) -> Upload:
    """Unpack ``submission`` under ``work`` and assemble ``work/hri_lab`` from what it holds.

    The folder with most package files at their places is copied whole; a package file it lacks
    is taken from a file of the same name elsewhere in the upload (the shallowest one). The notes
    say where things came from, in the student's words. Raises GradingError (one line) for an
    upload that cannot be opened.
    """
    if not submission.is_dir():
        raise GradingError(f"{submission}: no such folder; Gradescope puts the upload in /autograder/submission")
    unpacked, package = work / "upload", work / "hri_lab"
    for folder in (unpacked, package):
        if folder.exists():
            shutil.rmtree(folder)
    unpacked.mkdir(parents=True)
    notes = _copy_upload(submission, unpacked)
    best, _ = _best_folder(unpacked)
    if best is not None:
        shutil.copytree(best, package, ignore=shutil.ignore_patterns(*_JUNK_DIRS, "._*", ".DS_Store", "*.zip.d"))
        where = _shown(best.relative_to(unpacked))
        notes.append("found your package at the upload's top level" if where == "." else f"found your package in {where}/")
    else:
        package.mkdir()
    loose = _loose_files(unpacked, best if best is not None and best != unpacked else None)
    for relative in package_files:
        target = package / relative
        candidates = loose.get(PurePosixPath(relative).name, [])
        if target.is_file() or not candidates:
            continue
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(candidates[0], target)
        notes.append(f"took {relative} from {_shown(candidates[0].relative_to(unpacked))}")
    for path in [package, *package.rglob("*")]:  # the sandbox's student uid reads its copy of the package
        path.chmod(stat.S_IMODE(path.stat().st_mode) | (0o555 if path.is_dir() else 0o444))
    notebooks = sorted(p for p in unpacked.rglob("*.ipynb") if p.is_file())
    found = [relative for relative in package_files if (package / relative).is_file()]
    if not found:
        names = ", ".join(sorted({PurePosixPath(r).name for r in package_files}))
        notes.append(f"found none of the package's files ({names}) in the upload: upload your hri_lab folder "
                     "(zipped or as it is)")
    return Upload(package, notebooks, notes, found)
