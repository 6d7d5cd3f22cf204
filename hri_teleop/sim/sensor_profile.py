"""A deterministic simulated piston press, as the sensor board would report it.

Without an Arduino, ``/pub_force`` must still look like the lab's; ``FSR_sensor.py``, the notebooks
and the tests use :func:`press_profile_count`, so they see the same numbers. The force follows a
smooth raised-cosine press through the FSR model of :mod:`hri_teleop.core.fsr`, so the count jumps
at a light touch and flattens under a firm press; the top of each press reads exactly ``max_count``.
"""

from __future__ import annotations

import math

from hri_teleop.core.checks import ADC_MAX_COUNT, is_finite_number, is_int
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.fsr import count_to_force, force_to_count

__all__ = ["FSR_SENSOR_RATE_HZ", "SensorProfileError", "press_profile_count"]

#: FSR_sensor.py's publish rate when its ~rate_hz is not set, Hz.
FSR_SENSOR_RATE_HZ = 10.0


class SensorProfileError(HriTeleopError, ValueError):
    """A profile argument is out of range (one line with the fix)."""


def press_profile_count(t_s: float, period_s: float, max_count: int, *, press_fraction: float = 0.6) -> int:
    """The simulated sensor's ADC count at time ``t_s`` (s): presses repeating every ``period_s``.

    ``max_count`` (0..1023) is the count at the top of each press; the result is always
    within ``0 .. max_count``.  ``press_fraction`` (0 < f <= 1) of each period is the press,
    the rest is the released piston (count 0).  Deterministic: the same ``t_s`` always gives
    the same count.
    """
    if not is_finite_number(t_s):
        raise SensorProfileError(f"t_s must be a finite time in seconds, got {t_s!r}; pass the node's clock")
    if not is_finite_number(period_s) or period_s <= 0:
        raise SensorProfileError(f"period_s must be a positive duration in seconds, got {period_s!r}; e.g. 4.0")
    if not is_int(max_count) or not 0 <= max_count <= ADC_MAX_COUNT:
        raise SensorProfileError(f"max_count must be an integer count 0..{ADC_MAX_COUNT}, got {max_count!r}; e.g. 700")
    if not is_finite_number(press_fraction) or not 0 < press_fraction <= 1:
        raise SensorProfileError(f"press_fraction must be in (0, 1], got {press_fraction!r}; e.g. 0.6")
    if max_count == 0:
        return 0
    phase = (float(t_s) % float(period_s)) / float(period_s)  # 0 <= phase < 1, also for t < 0
    if phase >= press_fraction:
        return 0
    shape = 0.5 - 0.5 * math.cos(2.0 * math.pi * phase / press_fraction)  # 0 -> 1 -> 0, smooth
    peak_force_n = float(count_to_force(max_count))  # the smallest force reading max_count
    count = int(force_to_count(peak_force_n * shape))
    return max(0, min(max_count, count))
