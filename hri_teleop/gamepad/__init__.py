"""Last term's path of the pad's state, dead zone and opener: a shim over hri_teleop.student until 2.0."""

from __future__ import annotations

from typing import Any

from hri_teleop import student
from hri_teleop.student.deprecation import OldPath

_OLD = OldPath(__name__, ["PadState", "normalize_analog_input", "open_gamepad"], student)
__all__ = list(_OLD.order)


def __getattr__(name: str) -> Any:
    return _OLD.get(name)
