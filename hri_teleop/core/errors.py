"""The one base of every error the toolkit raises on purpose.

Each subpackage keeps its own error classes (``ConfigError``, ``MasterError``, ...) next to the
code that raises them; all of them derive from :class:`HriTeleopError` as well as from the
built-in they always had, so ``except ValueError`` keeps working. Their message is one line:
the cause and the fix. A node, a notebook or the grader shows that line and no traceback;
anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

__all__ = ["HriTeleopError"]


class HriTeleopError(Exception):
    """An error raised on purpose by hri_teleop: its message names the cause and the fix."""
