"""The lab's FSR attachment (handout Fig. 5): piston, spring, FSR and divider, as force to count.

A piston sticks out of a housing on one finger; closing on an object pushes it in against a
spring that presses the FSR, until it is level with the housing and the force saturates at
the count students record as ``/max_sensor_force``. The model and its numbers: docs/simulation.md.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field
from typing import Optional, Tuple

import numpy as np

from hri_teleop.core import fsr
from hri_teleop.core.checks import checked_float
from hri_teleop.core.errors import HriTeleopError

__all__ = ["AttachmentError", "PISTON_TRAVEL_M", "SPRING_N_PER_M", "Attachment"]

#: How far the piston sticks out of the housing when relaxed (m).  Not given by the
#: handout; 3 mm is a small piston's travel and a window the operator can hit.
PISTON_TRAVEL_M = 0.003
#: Piston spring (N/m): full travel gives 1.77 N, which the FSR model reads as ~700 counts
#: (``fsr.count_to_force(700)`` is 1.76 N), the handout's value at full travel.
SPRING_N_PER_M = 590.0


class AttachmentError(HriTeleopError, ValueError):
    """An attachment setting is unusable (names the field and a usable value)."""


def _check(value: object, name: str, fix: str, *, lowest: str = "") -> float:
    return checked_float(value, name, fix, AttachmentError, lowest=lowest)


@dataclass(frozen=True)
class Attachment:
    """The FSR attachment of handout Fig. 5: piston, spring, FSR and the lab's divider.

    The FSR wiring arguments are those of :func:`hri_teleop.core.fsr.force_to_count`; the
    count is that function's, computed from a table of its thresholds
    (:func:`hri_teleop.core.fsr.count_to_force`) because one call of it costs about 35 us and
    the simulation steps at 1 kHz.  Forces within one part in a million of a threshold are
    handed to ``force_to_count`` itself, so the result is always exactly its result.
    """

    piston_travel_m: float = PISTON_TRAVEL_M
    spring_n_per_m: float = SPRING_N_PER_M
    law: fsr.PowerLaw = fsr.FSR402
    pulldown_ohm: float = fsr.PULLDOWN_OHM
    supply_v: float = fsr.SUPPLY_V
    adc_bits: int = fsr.ADC_BITS
    _thresholds_n: Optional[Tuple[float, ...]] = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "piston_travel_m", _check(
            self.piston_travel_m, "Attachment.piston_travel_m", "e.g. 0.003 (3 mm)", lowest=">0"))
        object.__setattr__(self, "spring_n_per_m", _check(
            self.spring_n_per_m, "Attachment.spring_n_per_m", "e.g. 590.0", lowest=">0"))
        # Checks the wiring (raises fsr.FsrError with its own fix) before the table is built.
        fsr.force_to_count(1.0, law=self.law, pulldown_ohm=self.pulldown_ohm, supply_v=self.supply_v,
                           adc_bits=self.adc_bits)
        if int(self.adc_bits) <= 16:
            counts = np.arange(2 ** int(self.adc_bits))
            table = fsr.count_to_force(counts, law=self.law, pulldown_ohm=self.pulldown_ohm,
                                       supply_v=self.supply_v, adc_bits=self.adc_bits)
            object.__setattr__(self, "_thresholds_n", tuple(float(f) for f in table))

    @property
    def full_travel_force_n(self) -> float:
        """The spring's force with the piston level with the housing (N): the FSR's maximum."""
        return self.spring_n_per_m * self.piston_travel_m

    @property
    def full_travel_count(self) -> int:
        """The count at full piston travel: what students record as ``/max_sensor_force``."""
        return self.count(self.full_travel_force_n)

    def spring_force_n(self, compression_m: float) -> float:
        """Spring (= FSR) force for a piston pushed in by ``compression_m``, clipped to the travel."""
        x = min(max(float(compression_m), 0.0), self.piston_travel_m)
        return self.spring_n_per_m * x

    def count(self, force_n: float) -> int:
        """The ADC count for an FSR force: exactly ``int(fsr.force_to_count(force_n, ...))``."""
        f = float(force_n)
        if not f > 0.0:  # no force (and NaN) is an open circuit: 0 V, count 0, as in hri_teleop.core.fsr
            return 0
        table = self._thresholds_n
        if table is None or math.isinf(f):
            return int(fsr.force_to_count(f, law=self.law, pulldown_ohm=self.pulldown_ohm,
                                          supply_v=self.supply_v, adc_bits=self.adc_bits))
        c = bisect.bisect_right(table, f) - 1
        low = table[c]
        high = table[c + 1] if c + 1 < len(table) else math.inf
        if f - low <= 1e-6 * low or high - f <= 1e-6 * high:
            return int(fsr.force_to_count(f, law=self.law, pulldown_ohm=self.pulldown_ohm,
                                          supply_v=self.supply_v, adc_bits=self.adc_bits))
        return c
