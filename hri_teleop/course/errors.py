"""The course's one error: a release, validation or notebook step failed."""

from __future__ import annotations

from typing import List

from hri_teleop.core.errors import HriTeleopError

__all__ = ["CourseError"]


class CourseError(HriTeleopError, RuntimeError):
    """A release or validation step failed (one line: what and the fix)."""

    def _render_traceback_(self) -> List[str]:  # IPython shows the one line, not a traceback
        return [f"{type(self).__name__}: {self}"]

