"""The course's errors: a release, validation or notebook step failed, or a file a notebook needs is missing."""

from __future__ import annotations

from typing import List

from hri_teleop.core.errors import HriTeleopError

__all__ = ["CourseError", "MissingFileError"]


class CourseError(HriTeleopError, RuntimeError):
    """A release or validation step failed (one line: what and the fix)."""

    def _render_traceback_(self) -> List[str]:  # IPython shows the one line, not a traceback
        return [f"{type(self).__name__}: {self}"]


class MissingFileError(CourseError, FileNotFoundError):
    """A file the assignment comes with is not where the notebook looks (one line: which, and how to get it back)."""

