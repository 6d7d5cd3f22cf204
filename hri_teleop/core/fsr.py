"""The FSR 402 force sensor as the lab wires it, from force to ADC count and back.

Students only see the Arduino's 10-bit count on ``/pub_force``; the simulated board, the notebooks
and the grader need the same physics (steep at a light touch, saturating under a firm press) and
read a count back as a force. The chain (docs/lab-facts.md): force -> resistance (a power law fitted
to :data:`FSR402_POINTS`) -> divider voltage -> count. Functions take numpy arrays or scalars; the
divider, supply and ADC bits are arguments for other boards. A typical part, not a calibration.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Iterable, Tuple, Union

import numpy as np
import numpy.typing as npt

from hri_teleop.core.checks import is_int, is_number, is_positive_number
from hri_teleop.core.errors import HriTeleopError

__all__ = [
    "FsrError",
    "PowerLaw",
    "FSR402_POINTS",
    "fit_power_law",
    "FSR402",
    "PULLDOWN_OHM",
    "SUPPLY_V",
    "ADC_BITS",
    "force_to_resistance",
    "resistance_to_force",
    "resistance_to_voltage",
    "voltage_to_resistance",
    "voltage_to_count",
    "count_to_voltage",
    "force_to_count",
    "count_to_force",
]


class FsrError(HriTeleopError, ValueError):
    """A sensor-model argument is out of range (one line: what and how to fix it)."""


@dataclass(frozen=True)
class PowerLaw:
    """``R_ohm = r_at_1n_ohm * force_n ** (-exponent)``: an FSR's resistance curve.

    ``r_at_1n_ohm`` is the resistance at 1 N (ohm) and ``exponent`` the (positive) slope of
    the log-log line; the FSR 402 has about 0.8.
    """

    r_at_1n_ohm: float
    exponent: float

    def __post_init__(self) -> None:
        if not (is_number(self.r_at_1n_ohm, numpy=True) and self.r_at_1n_ohm > 0 and math.isfinite(self.r_at_1n_ohm)):
            raise FsrError(
                f"PowerLaw.r_at_1n_ohm must be a positive finite resistance in ohm, got {self.r_at_1n_ohm!r}; "
                "pass e.g. 6000.0"
            )
        if not (is_number(self.exponent, numpy=True) and self.exponent > 0 and math.isfinite(self.exponent)):
            raise FsrError(
                f"PowerLaw.exponent must be a positive finite number (R falls as force rises), "
                f"got {self.exponent!r}; pass e.g. 0.8"
            )


#: FSR 402 datasheet points (force in N, resistance in ohm), from Adafruit's FSR guide
#: as listed in docs/lab-facts.md.  No force is an open circuit and is not a point of the fit.
FSR402_POINTS: Tuple[Tuple[float, float], ...] = ((0.2, 30e3), (1.0, 6e3), (10.0, 1e3), (100.0, 250.0))

#: The lab's divider: 10 kOhm pull-down, 5 V supply, the Uno's 10-bit ADC.
PULLDOWN_OHM = 10e3
SUPPLY_V = 5.0
ADC_BITS = 10


def fit_power_law(points: Iterable[Tuple[float, float]]) -> PowerLaw:
    """Least-squares fit of ``log R = log R1 - n log F`` to ``(force_n, resistance_ohm)`` points.

    Why log-log: the datasheet curve spans three decades in both axes; a linear fit
    would be dominated by the light-touch points.
    """
    pts = [tuple(p) for p in points]
    if len(pts) < 2 or any(len(p) != 2 for p in pts):
        raise FsrError(f"fit_power_law needs at least two (force_n, resistance_ohm) pairs, got {pts!r}; pass more points")
    arr = np.asarray(pts, dtype=float)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
        raise FsrError(f"fit_power_law needs positive finite forces and resistances, got {pts!r}; drop the zero/open-circuit point")
    if np.unique(arr[:, 0]).size < 2:
        raise FsrError(f"fit_power_law needs at least two different forces, got {pts!r}; pass points at different forces")
    slope, intercept = np.polyfit(np.log(arr[:, 0]), np.log(arr[:, 1]), 1)
    return PowerLaw(r_at_1n_ohm=float(np.exp(intercept)), exponent=float(-slope))


#: The typical FSR 402, fitted to :data:`FSR402_POINTS`: about 7.1 kOhm at 1 N, exponent about
#: 0.77.  The datasheet curve is not a pure power law, so the fit misses each point by up to
#: about 20 % in resistance (0.2 V at the divider), comparable to the +-10 % part spread.
FSR402: PowerLaw = fit_power_law(FSR402_POINTS)


def _out(values: npt.NDArray[Union[np.float64, np.int64]]) -> Any:
    """0-d arrays become numpy scalars, other arrays stay arrays."""
    return values[()]


def _check_supply(supply_v: float) -> None:
    if not is_positive_number(supply_v, numpy=True):
        raise FsrError(f"supply_v must be a positive finite voltage in volt, got {supply_v!r}; the lab's Uno uses 5.0")


def _check_divider(pulldown_ohm: float, supply_v: float) -> None:
    if not is_positive_number(pulldown_ohm, numpy=True):
        raise FsrError(f"pulldown_ohm must be a positive finite resistance in ohm, got {pulldown_ohm!r}; the lab uses 10e3")
    _check_supply(supply_v)


def _check_bits(adc_bits: int) -> None:
    if not (is_int(adc_bits, numpy=True) and 1 <= adc_bits <= 24):
        raise FsrError(f"adc_bits must be an integer from 1 to 24, got {adc_bits!r}; the Uno's ADC has 10 bits")


def _check_law(law: object) -> None:
    if not isinstance(law, PowerLaw):
        raise FsrError(f"law must be a PowerLaw(r_at_1n_ohm, exponent), got {law!r}; pass e.g. fsr.FSR402 or "
                       "fsr.fit_power_law(points)")


def force_to_resistance(force_n: Any, law: PowerLaw = FSR402) -> Any:
    """Resistance (ohm) at a force (N); ``inf`` (open circuit) at zero or negative force."""
    _check_law(law)
    force = np.asarray(force_n, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        resistance = np.where(force > 0, law.r_at_1n_ohm * np.power(np.where(force > 0, force, 1.0), -law.exponent), np.inf)
    resistance = np.where(np.isnan(force), np.nan, resistance)
    return _out(resistance)


def resistance_to_force(resistance_ohm: Any, law: PowerLaw = FSR402) -> Any:
    """Force (N) that gives a resistance (ohm); 0 for an open circuit (``inf``), ``inf`` for 0 ohm.

    Negative resistances are not physical and raise :class:`FsrError`.
    """
    _check_law(law)
    resistance = np.asarray(resistance_ohm, dtype=float)
    if np.any(resistance < 0):
        raise FsrError("resistance_ohm must be >= 0 ohm (inf for an open circuit); check the divider arithmetic")
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        force = np.power(resistance / law.r_at_1n_ohm, -1.0 / law.exponent)
    force = np.where(np.isposinf(resistance), 0.0, force)
    return _out(force)


def resistance_to_voltage(resistance_ohm: Any, pulldown_ohm: float = PULLDOWN_OHM, supply_v: float = SUPPLY_V) -> Any:
    """Divider output (V) with the FSR on top and the pull-down below: ``Vcc*Rpd/(Rpd+R)``.

    An open circuit (``inf``) reads 0 V, a short (0 ohm) the full supply.
    """
    _check_divider(pulldown_ohm, supply_v)
    resistance = np.asarray(resistance_ohm, dtype=float)
    if np.any(resistance < 0):
        raise FsrError("resistance_ohm must be >= 0 ohm (inf for an open circuit); check the divider arithmetic")
    with np.errstate(invalid="ignore"):  # inf / inf: an open circuit where supply_v * pulldown_ohm overflows
        voltage = supply_v * pulldown_ohm / (pulldown_ohm + resistance)
    voltage = np.where(np.isposinf(resistance), 0.0, voltage)
    return _out(voltage)


def voltage_to_resistance(voltage_v: Any, pulldown_ohm: float = PULLDOWN_OHM, supply_v: float = SUPPLY_V) -> Any:
    """FSR resistance (ohm) behind a divider voltage; ``inf`` at 0 V, 0 ohm at the supply.

    Voltages are clipped to ``0 .. supply_v`` first: the divider cannot produce more.
    """
    _check_divider(pulldown_ohm, supply_v)
    voltage = np.clip(np.asarray(voltage_v, dtype=float), 0.0, supply_v)
    with np.errstate(divide="ignore", invalid="ignore"):
        resistance = pulldown_ohm * (supply_v - voltage) / voltage
    resistance = np.where(voltage == 0.0, np.inf, resistance)
    return _out(resistance)


def voltage_to_count(voltage_v: Any, supply_v: float = SUPPLY_V, adc_bits: int = ADC_BITS) -> Any:
    """ADC count (integer array) for a voltage: ``floor(V * 2**bits / Vref)``, clipped to the range.

    A relative 1e-9 of a step is added before the floor so that ``count_to_voltage``
    round-trips despite floating-point rounding (the ADC's own noise is far larger).
    NaN reads as 0.
    """
    _check_supply(supply_v)
    _check_bits(adc_bits)
    steps = 2 ** int(adc_bits)
    voltage = np.asarray(voltage_v, dtype=float)
    voltage = np.where(np.isnan(voltage), 0.0, voltage)
    raw = np.floor(np.clip(voltage, 0.0, supply_v) * steps / supply_v + 1e-9)
    return _out(np.clip(raw, 0, steps - 1).astype(np.int64))


def count_to_voltage(count: Any, supply_v: float = SUPPLY_V, adc_bits: int = ADC_BITS) -> Any:
    """Lowest voltage (V) that reads as ``count``: ``count * Vref / 2**bits`` (Arduino's convention).

    The lower edge of the step makes count 0 read as 0 V, i.e. no force.
    """
    _check_supply(supply_v)
    _check_bits(adc_bits)
    steps = 2 ** int(adc_bits)
    counts = np.asarray(count, dtype=float)
    return _out(np.clip(counts, 0, steps - 1) * supply_v / steps)


def force_to_count(
    force_n: Any,
    *,
    law: PowerLaw = FSR402,
    pulldown_ohm: float = PULLDOWN_OHM,
    supply_v: float = SUPPLY_V,
    adc_bits: int = ADC_BITS,
) -> Any:
    """The count the Arduino publishes on ``/pub_force`` for a force (N); 0 N reads 0."""
    resistance = force_to_resistance(force_n, law)
    voltage = resistance_to_voltage(resistance, pulldown_ohm, supply_v)
    return voltage_to_count(voltage, supply_v, adc_bits)


def count_to_force(
    count: Any,
    *,
    law: PowerLaw = FSR402,
    pulldown_ohm: float = PULLDOWN_OHM,
    supply_v: float = SUPPLY_V,
    adc_bits: int = ADC_BITS,
) -> Any:
    """Estimated force (N) behind a count: the smallest force that reads as that count.

    Why the smallest: the ADC floors, so ``force_to_count(count_to_force(c)) == c`` and
    the estimate never exceeds the true force.  Count 0 estimates 0 N.
    """
    voltage = count_to_voltage(count, supply_v, adc_bits)
    resistance = voltage_to_resistance(voltage, pulldown_ohm, supply_v)
    return resistance_to_force(resistance, law)
