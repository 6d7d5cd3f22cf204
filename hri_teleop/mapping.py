"""Last term's path of the ADC's range as FSR_sensor.py used it: a shim over hri_teleop.student until 2.0."""

from __future__ import annotations

from typing import Any

from hri_teleop import student
from hri_teleop.student.deprecation import OldPath

_OLD = OldPath(__name__, ["ADC_MAX_COUNT"], student)
__all__ = list(_OLD.order)


def __getattr__(name: str) -> Any:
    return _OLD.get(name)
