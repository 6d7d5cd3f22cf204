"""Finding a student's hri_lab and notebooks in a Gradescope upload, whatever its folder layout.

Students upload a zip of their package, the folder that holds it, a zip inside a zip, or the files
loose (Gradescope's drag and drop), often with macOS' ``__MACOSX`` and ``._`` copies. The grader
needs one ``hri_lab`` folder: this module unpacks the upload, picks the folder holding most of the
deliverables, fills what it lacks from files of the same name elsewhere, and says what it did.
"""

from __future__ import annotations

import shutil
import stat
import zipfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Dict, List, Optional, Sequence, Tuple

from hri_teleop.grading.results import GradingError
from hri_teleop.grading.run.workspace import DELIVERABLES

__all__ = ["Upload", "PACKAGE_FILES", "MAX_UNPACKED_BYTES", "MAX_ZIP_DEPTH", "find_upload", "is_junk"]

#: Files of the student's package the checks read: the deliverables and what catkin-package judges.
PACKAGE_FILES: Tuple[str, ...] = tuple(DELIVERABLES.values()) + ("CMakeLists.txt", "package.xml",
                                                                  "scripts/gripper_manager.py")
#: An upload that unpacks to more than this is refused (a zip bomb must not fill the grader's disk).
MAX_UNPACKED_BYTES = 200 * 1024 * 1024
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


def _extract(archive: Path, into: Path, budget: List[int]) -> None:
    """Unpack ``archive`` into ``into``: no member outside it, junk left out, unix modes kept."""
    try:
        with zipfile.ZipFile(archive) as zf:
            for info in zf.infolist():
                name = PurePosixPath(info.filename.replace("\\", "/"))
                if info.is_dir() or is_junk(name):
                    continue
                if name.is_absolute() or ".." in name.parts:
                    raise GradingError(f"{archive.name}: member {info.filename!r} points outside the archive; "
                                       "zip your hri_lab folder with a normal zip tool and upload again")
                budget[0] -= info.file_size
                if budget[0] < 0:
                    raise GradingError(f"{archive.name}: unpacks to more than {MAX_UNPACKED_BYTES // 2**20} MB; "
                                       "upload only your hri_lab folder (no bags, builds or videos)")
                target = into / Path(*name.parts)
                target.parent.mkdir(parents=True, exist_ok=True)
                with zf.open(info) as src, open(target, "wb") as dst:
                    shutil.copyfileobj(src, dst)
                mode = (info.external_attr >> 16) & 0o777
                target.chmod((mode or 0o644) | 0o444)
    except zipfile.BadZipFile as exc:
        raise GradingError(f"{archive.name}: not a readable zip ({exc}); make it again and upload it") from exc


def _copy_upload(submission: Path, into: Path) -> List[str]:
    """The upload copied to ``into`` with every zip unpacked beside it (``x.zip`` -> ``x.zip.d/``)."""
    notes: List[str] = []
    budget = [MAX_UNPACKED_BYTES]
    for path in sorted(submission.rglob("*")):
        relative = PurePosixPath(path.relative_to(submission).as_posix())
        if is_junk(relative) or path.is_symlink() or not path.is_file():
            continue
        budget[0] -= path.stat().st_size
        if budget[0] < 0:
            raise GradingError(f"the upload is larger than {MAX_UNPACKED_BYTES // 2**20} MB; upload only your "
                               "hri_lab folder (no bags, builds or videos)")
        target = into / Path(*relative.parts)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path, target)
        target.chmod(stat.S_IMODE(path.stat().st_mode) | 0o444)
    for _depth in range(MAX_ZIP_DEPTH):
        archives = [p for p in sorted(into.rglob("*")) if p.is_file() and p.suffix.lower() == ".zip"
                    and not p.with_name(p.name + ".d").exists()]
        for archive in archives:
            _extract(archive, archive.with_name(archive.name + ".d"), budget)
            notes.append(f"opened {_shown(archive.relative_to(into))}")
        if not archives:
            break
    return notes


def _shown(relative: Path) -> str:
    """A path of the upload as the student knows it (``x.zip.d/`` reads as ``x.zip/``)."""
    return "/".join(part[:-2] if part.endswith(".zip.d") else part for part in relative.parts) or "."


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
