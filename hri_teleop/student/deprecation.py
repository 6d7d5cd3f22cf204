"""The deprecation warning of an old import path or an old name of the student API, said once.

Last term's templates imported ``hri_teleop.gamepad``, ``hri_teleop.limits`` and a few more; those
paths are thin shims over :mod:`hri_teleop.student` that warn once, on the line of the student's
file that imports them, until the student API's next major version (docs/student-api.md).
"""

from __future__ import annotations

import inspect
import warnings
from types import ModuleType
from typing import Any, FrozenSet, Iterable, Sequence

__all__ = ["OLD_PATHS_SINCE", "REMOVED_IN", "OldPath", "importer_stacklevel", "removed_in"]

#: The student API version that deprecated last term's import paths (the first one).
OLD_PATHS_SINCE = "1.0"


def removed_in(since: str) -> str:
    """The student API version in which what ``since`` deprecated is removed: the next major one."""
    return f"{int(since.split('.')[0]) + 1}.0"


#: The student API version in which last term's import paths are removed.
REMOVED_IN = removed_in(OLD_PATHS_SINCE)


def _importlib_frame(filename: str) -> bool:
    """True for importlib's bootstrap frames, which ``warnings.warn`` leaves out of its ``stacklevel``."""
    return "importlib" in filename and "_bootstrap" in filename


def importer_stacklevel(internal: Iterable[str]) -> int:
    """The ``stacklevel`` of ``warnings.warn``, called by the caller of this function, that points at the
    first frame neither in importlib nor in a module named in ``internal``: the student's import line."""
    skip = set(internal) | {__name__}
    frame = inspect.currentframe()
    frame = frame.f_back if frame is not None else None  # the caller of warnings.warn: stacklevel 1
    level = 1
    try:
        while frame is not None:
            if not _importlib_frame(frame.f_code.co_filename):
                if frame.f_globals.get("__name__", "") not in skip:
                    return level
                level += 1
            frame = frame.f_back
        return 1
    finally:
        del frame


class OldPath:
    """One old module path: the names it still gives (from the student API) and its one warning."""

    def __init__(self, old: str, names: Sequence[str], source: ModuleType) -> None:
        self.old = old
        self.names: FrozenSet[str] = frozenset(names)
        self.order = tuple(names)
        self.source = source
        self.warned = False

    @property
    def message(self) -> str:
        """The one line: the old path, the import to write instead, and when the old one goes."""
        return (f"{self.old} is deprecated: write 'from hri_teleop.student import {', '.join(self.order)}' "
                f"instead; it goes in {REMOVED_IN}")

    def get(self, name: str) -> Any:
        """The student API's ``name`` (AttributeError for a name the old path never gave); warns the first time."""
        if name not in self.names:
            raise AttributeError(f"module {self.old!r} has no attribute {name!r}")
        if not self.warned:
            warnings.warn(self.message, DeprecationWarning, stacklevel=importer_stacklevel([self.old]))
            self.warned = True
        return getattr(self.source, name)
