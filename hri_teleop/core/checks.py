"""Is this value a number? Checks that refuse bools, for every module that validates input.

``bool`` is a subclass of ``int``, and YAML and rosparam give bools for ``true``, ``yes`` and ``on``:
a student's ``deadzone: yes`` would silently become 1 unless every check says "not bool" too.
``numpy=False`` accepts Python ``int`` and ``float`` (what YAML, rosparam and JSON give);
``numpy=True`` also numpy integer and floating scalars, never ``numpy.bool_``. numpy is looked up
in ``sys.modules``, never imported, so the gamepad modules stay numpy-free.
"""

from __future__ import annotations

import math
import sys
import typing  # typing.TypeGuard (Python 3.10) only in annotations, which 3.8 never evaluates here
from typing import Tuple, Type

__all__ = ["ADC_MAX_COUNT", "checked_float", "is_number", "is_finite_number", "is_positive_number", "is_int", "is_count",
           "is_calibration_count"]

#: Largest count the Arduino's 10-bit ADC reads (``analogRead`` gives 0..1023).
ADC_MAX_COUNT = 1023


def _numpy_types(*names: str) -> Tuple[type, ...]:
    """numpy's scalar classes ``names``, or () if numpy is not loaded (then no value is one)."""
    np = sys.modules.get("numpy")
    return tuple(getattr(np, name) for name in names) if np is not None else ()


def is_number(value: object, *, numpy: bool = False) -> typing.TypeGuard[float]:
    """True for an int or a float (NaN and inf included), False for a bool, str or None."""
    if isinstance(value, bool):
        return False
    if isinstance(value, (int, float)):
        return True
    return numpy and isinstance(value, _numpy_types("integer", "floating"))


def is_finite_number(value: object, *, numpy: bool = False) -> typing.TypeGuard[float]:
    """``is_number`` and neither NaN nor +-inf."""
    return is_number(value, numpy=numpy) and math.isfinite(value)


def checked_float(value: object, name: str, fix: str, error: Type[Exception], *, lowest: str = "") -> float:
    """``value`` as a finite float, else ``error`` naming ``name`` and the ``fix``.

    ``lowest`` ``">0"`` or ``">=0"`` also bounds it from below (NaN never passes).
    """
    if not is_finite_number(value, numpy=True):
        raise error(f"{name} must be a finite number, got {value!r}; {fix}")
    number = float(value)
    if (lowest == ">0" and not number > 0.0) or (lowest == ">=0" and not number >= 0.0):
        raise error(f"{name} must be {lowest.replace('0', ' 0')}, got {value!r}; {fix}")
    return number


def is_positive_number(value: object, *, numpy: bool = False) -> typing.TypeGuard[float]:
    """``is_number`` and ``0 < value < inf`` (refuses NaN): a rate, a duration, a gain."""
    return is_number(value, numpy=numpy) and 0 < value < math.inf


def is_int(value: object, *, numpy: bool = False) -> typing.TypeGuard[int]:
    """True for an integer (``numpy=True``: numpy integers too), False for a bool or a float."""
    if isinstance(value, bool):
        return False
    if isinstance(value, int):
        return True
    return numpy and isinstance(value, _numpy_types("integer"))


def is_count(value: object, *, numpy: bool = False) -> typing.TypeGuard[int]:
    """A reading of the board: a whole count 0..1023 (``is_int``, so no bool, no float)."""
    return is_int(value, numpy=numpy) and 0 <= value <= ADC_MAX_COUNT


def is_calibration_count(value: object, *, numpy: bool = False) -> typing.TypeGuard[int]:
    """A ``/max_sensor_force`` given as a count: a whole count 1..1023 (0 would divide by zero)."""
    return is_count(value, numpy=numpy) and value != 0
