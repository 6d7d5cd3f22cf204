"""The handout's stick dead zone (Ex. 8, Figure 8), made continuous at the dead-zone edge.

The handout's filter passes the raw value outside the dead zone, so the velocity jumps from 0 to
``deadzone * k_trans`` as the stick leaves it, a step the Panda refuses. Here the output ramps up
from 0 at the edge and still reaches full scale at full deflection (the formula:
docs/teleoperation.md).
"""

from __future__ import annotations

import math

from hri_teleop.core.checks import is_number
from hri_teleop.core.gamepad.state import GamepadError

__all__ = ["normalize_analog_input", "check_deadzone"]


def check_deadzone(deadzone: object) -> float:
    """deadzone as a float in [0, 1), or GamepadError saying what to set instead."""
    value = float(deadzone) if is_number(deadzone, numpy=True) else float("nan")
    if not 0.0 <= value < 1.0:  # also refuses NaN
        raise GamepadError("dead zone %r is not a number in [0, 1): set deadzone to a fraction of "
                           "full stick travel, e.g. 0.1" % (deadzone,))
    return value


def normalize_analog_input(value: float, deadzone: float) -> float:
    """Stick value -1..1 -> filtered value -1..1: 0 inside the dead zone, a ramp outside.

    A NaN input gives 0.0 (no motion is the safe reading of a broken value); inputs
    beyond +-1 are clipped. Raises GamepadError if ``deadzone`` is not in [0, 1).
    """
    dz = check_deadzone(deadzone)
    v = float(value)
    if math.isnan(v):
        return 0.0
    magnitude = abs(v)
    if magnitude <= dz:
        return 0.0
    scaled = min(1.0, (magnitude - dz) / (1.0 - dz))
    return math.copysign(scaled, v)
