"""Raw ADC count -> mapped force in [0, 1]: the rule of the handout's ``mapping_node.py``.

Why a separate module: the mapping node, the teleoperation rumble, the notebooks and the
grader must agree on one rule.  ``/max_sensor_force`` is the count measured with the
piston pressed level with the housing (Ex. 11, about 700 in the lab); it arrives from
the parameter server, i.e. from a student's YAML or a ``rosparam set``, so it is
validated here with a message that says how to fix it instead of dividing by zero or
by a string later.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from hri_teleop.core.checks import ADC_MAX_COUNT, is_int, is_number
from hri_teleop.core.errors import HriTeleopError

__all__ = ["ADC_MAX_COUNT", "MappingError", "validate_max_sensor_force", "map_force"]

class MappingError(HriTeleopError, ValueError):
    """``/max_sensor_force`` is missing or not a usable number (one line with the fix)."""


def validate_max_sensor_force(value: object, name: str = "/max_sensor_force") -> float:
    """Return ``value`` as a float if it is a number with ``0 < value <= 1023``.

    Booleans and strings are refused although Python would happily divide by them
    (``True`` is 1, YAML turns ``yes`` into ``True`` and ``"700"`` is a common slip in
    launch files).  Anything else raises :class:`MappingError` naming ``name``, what was
    found and the fix.
    """
    fix = f"set it with `rosparam set {name} 700` or in the launch file (the count with the piston pressed in, Ex. 11)"
    if value is None:
        raise MappingError(f"{name} is not set; {fix}")
    if not is_number(value, numpy=True):
        raise MappingError(
            f"{name} must be a number of ADC counts (0 < value <= {ADC_MAX_COUNT}), "
            f"got {value!r} of type {type(value).__name__}; {fix}"
        )
    number = float(value)
    if not (math.isfinite(number) and 0.0 < number <= ADC_MAX_COUNT):
        raise MappingError(f"{name} must be > 0 and <= {ADC_MAX_COUNT} ADC counts, got {value!r}; {fix}")
    return number


def map_force(count: Any, max_sensor_force: float) -> Any:
    """``clip(count / max_sensor_force, 0, 1)``: a float for a scalar, an ndarray for arrays.

    Counts above ``max_sensor_force`` (a firmer press than at calibration) give 1, and
    NaN gives 0 (no usable reading means no feedback).
    """
    maximum = validate_max_sensor_force(max_sensor_force)
    if is_int(count, numpy=True):
        # Exact for any Python int (a float conversion would overflow beyond 1e308).
        return 0.0 if count <= 0 else (1.0 if count >= maximum else float(count) / maximum)
    counts = np.asarray(count, dtype=float)
    mapped = np.clip(counts / maximum, 0.0, 1.0)
    mapped = np.where(np.isnan(mapped), 0.0, mapped)
    if mapped.ndim == 0:
        return float(mapped)
    return mapped
