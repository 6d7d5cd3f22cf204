"""Reading what a student handed in: regular files only, never through a link, never past a size.

A deliverable may be a link to ``/etc/shadow``, the answer key or another student's file, a FIFO
that blocks a reader for ever or ``/proc/self/pagemap``, which never ends; the grader often runs as
root. So every path is opened one component at a time below the submission's root with
``O_NOFOLLOW`` (a link anywhere on the way is refused, not followed), the last one must be a
regular file, and no more than ``limit_bytes`` are read.
"""

from __future__ import annotations

import errno
import os
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator, List, Optional, Tuple, Union

from hri_teleop.core.errors import HriTeleopError

__all__ = ["UntrustedFileError", "FILE_CAP_BYTES", "TREE_CAP_BYTES", "TREE_CAP_FILES", "read_regular",
           "regular_size", "is_regular", "copy_regular", "copy_tree", "CopyReport", "walk_regular", "kind_of",
           "refusal"]

#: The largest single file the grader reads from a submission.
FILE_CAP_BYTES = 2 * 1024 ** 2
#: The most a submission's tree may hold in all, and how many files.
TREE_CAP_BYTES = 20 * 1024 ** 2
TREE_CAP_FILES = 2000
_DIR_FLAGS = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC
_FILE_FLAGS = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC

PathLike = Union[str, Path]


class UntrustedFileError(HriTeleopError, OSError):
    """A submitted path is a link, not a regular file, or too large (one line: which, and what to hand in)."""


def _parts(path: Path, root: Optional[Path]) -> Tuple[Path, List[str]]:
    """(the folder to start from, the components below it): ``root`` when given, else the path's parent."""
    path = Path(os.path.abspath(path))
    if root is None:
        return path.parent, [path.name]
    root = Path(os.path.abspath(root))
    try:
        rel = path.relative_to(root)
    except ValueError:
        raise UntrustedFileError(f"{path}: not inside the submission {root}") from None
    parts = [p for p in rel.parts if p not in ("", ".")]
    if ".." in parts or not parts:
        raise UntrustedFileError(f"{path}: not a file inside the submission {root}")
    return root, parts


def kind_of(mode: int) -> str:
    """What a file of ``mode`` is, in the words of a feedback line ("a link", "a FIFO", ...)."""
    for test, name in ((stat.S_ISLNK, "a link"), (stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO"),
                       (stat.S_ISCHR, "a device"), (stat.S_ISBLK, "a device"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "a regular file" if stat.S_ISREG(mode) else "not a regular file"


def _open(path: PathLike, root: Optional[PathLike]) -> int:
    """A descriptor of ``path``, opened without following a link below ``root``; it is a regular file."""
    start, parts = _parts(Path(path), Path(root) if root is not None else None)
    try:
        fd = os.open(start, _DIR_FLAGS)
    except OSError as exc:
        raise UntrustedFileError(f"{start}: cannot be opened as a folder ({exc.strerror})") from None
    try:
        for i, name in enumerate(parts):
            last = i == len(parts) - 1
            try:
                nxt = os.open(name, _FILE_FLAGS if last else _DIR_FLAGS, dir_fd=fd)
            except OSError as exc:
                where = os.path.join(str(start), *parts[: i + 1])
                try:  # O_DIRECTORY answers ENOTDIR for a link as for a file: ask what it is
                    own = os.stat(name, dir_fd=fd, follow_symlinks=False).st_mode
                except OSError:
                    own = 0
                if exc.errno in (errno.ELOOP, errno.EMLINK) or stat.S_ISLNK(own):
                    what = "file" if last else "folder"
                    raise UntrustedFileError(f"{where} is a link; hand in the {what} itself, not a link to "
                                             "it") from None
                if exc.errno == errno.ENOTDIR:
                    raise UntrustedFileError(f"{where} is not a folder; hand in the package's folders "
                                             "as they are") from None
                raise UntrustedFileError(f"{where}: {exc.strerror}") from None
            os.close(fd)
            fd = nxt
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            raise UntrustedFileError(f"{os.path.join(str(start), *parts)} is {kind_of(mode)}, not a regular "
                                     "file; hand in the file itself")
        os.set_blocking(fd, True)
        return fd
    except BaseException:
        os.close(fd)
        raise


def read_regular(path: PathLike, limit_bytes: int = FILE_CAP_BYTES, root: Optional[PathLike] = None) -> bytes:
    """The bytes of ``path``, a regular file reached without a link below ``root`` (its parent when None),
    or UntrustedFileError: a link, a folder, a device or FIFO, or more than ``limit_bytes``."""
    fd = _open(path, root)
    with os.fdopen(fd, "rb") as fh:
        data = fh.read(limit_bytes + 1)
    if len(data) > limit_bytes:
        raise UntrustedFileError(f"{path}: larger than {limit_bytes // 1024} KB; hand in a smaller file")
    return data


def refusal(path: PathLike, root: Optional[PathLike] = None) -> str:
    """Why the grader will not read ``path`` (one line: a link on the way, not a regular file, missing),
    or "" when it is a regular file reached without a link below ``root``. Reads nothing of it."""
    try:
        os.close(_open(path, root))
    except UntrustedFileError as exc:
        return str(exc)
    return ""


def regular_size(path: PathLike) -> Optional[int]:
    """The size of ``path`` if it is a regular file itself (not a link to one), else None."""
    try:
        st = os.lstat(path)
    except OSError:
        return None
    return st.st_size if stat.S_ISREG(st.st_mode) else None


def is_regular(path: PathLike) -> bool:
    """Whether ``path`` is a regular file itself: a link to one is not (no stat follows it)."""
    return regular_size(path) is not None


def copy_regular(path: PathLike, target: PathLike, limit_bytes: int = FILE_CAP_BYTES,
                 root: Optional[PathLike] = None) -> int:
    """Copy one submitted file (as :func:`read_regular` reads it) to ``target``, replacing a file there;
    the number of bytes written. The copy is a new regular file: nothing of the source's links or modes."""
    data = read_regular(path, limit_bytes, root)
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    if target.is_symlink() or target.exists():
        target.unlink()
    fd = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
    with os.fdopen(fd, "wb") as fh:
        fh.write(data)
    return len(data)


@dataclass
class CopyReport:
    """What :func:`copy_tree` copied and what it left out, each with why (for the feedback)."""

    copied: List[str] = field(default_factory=list)
    skipped: List[Tuple[str, str]] = field(default_factory=list)
    bytes: int = 0


def walk_regular(root: PathLike, skip_dirs: Tuple[str, ...] = ()) -> Iterator[Tuple[str, str]]:
    """(relative path, "d" | "f" | why it is left out) for everything below ``root``, in sorted order,
    without following a link: folders and regular files are taken, links and special files are not."""
    root = os.path.abspath(root)
    stack = [""]
    while stack:
        rel_dir = stack.pop()
        try:
            names = sorted(os.listdir(os.path.join(root, rel_dir)))
        except OSError:
            continue
        below = []
        for name in names:
            rel = os.path.join(rel_dir, name) if rel_dir else name
            try:
                mode = os.lstat(os.path.join(root, rel)).st_mode
            except OSError:
                continue
            if stat.S_ISLNK(mode):
                yield rel, "a link (the grader follows none)"
            elif stat.S_ISDIR(mode):
                if name in skip_dirs:
                    continue
                yield rel, "d"
                below.append(rel)
            elif stat.S_ISREG(mode):
                yield rel, "f"
            else:
                yield rel, f"{kind_of(mode)}, not a regular file"
        stack.extend(reversed(below))


def copy_tree(root: PathLike, target: PathLike, limit_bytes: int = TREE_CAP_BYTES, max_files: int = TREE_CAP_FILES,
              file_limit_bytes: int = FILE_CAP_BYTES, skip_dirs: Tuple[str, ...] = ()) -> CopyReport:
    """Copy ``root``'s folders and regular files to ``target`` (links, devices, FIFOs and sockets left out),
    each file at most ``file_limit_bytes``, at most ``max_files`` files and ``limit_bytes`` in all; the rest is
    left out and listed in the report."""
    report = CopyReport()
    target = Path(target)
    target.mkdir(parents=True, exist_ok=True)
    for rel, kind in walk_regular(root, skip_dirs):
        if kind == "d":
            (target / rel).mkdir(exist_ok=True)
            continue
        if kind != "f":
            report.skipped.append((rel, kind))
            continue
        if len(report.copied) >= max_files:
            report.skipped.append((rel, f"past the first {max_files} files"))
            continue
        try:
            data = read_regular(os.path.join(str(root), rel), min(file_limit_bytes, limit_bytes - report.bytes),
                                root=root)
        except UntrustedFileError as exc:
            report.skipped.append((rel, str(exc).split(": ", 1)[-1]))
            continue
        fd = os.open(target / rel, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        report.copied.append(rel)
        report.bytes += len(data)
    return report
