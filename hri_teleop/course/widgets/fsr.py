"""FSR explorer (handout Ex. 1 and 5): force -> resistance -> voltage -> ADC count -> mapped 0..1.

Why: the students never see newtons in the lab, only the count on ``/pub_force``; the
explorer lets them feel the chain and its nonlinearity before they write
``mapping_node.py``. Every number comes from :mod:`hri_teleop.core.fsr` (the sensor model the
simulated board uses) and :func:`hri_teleop.core.mapping.map_force` (the mapping node's rule);
nothing is computed here twice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Tuple

import ipywidgets as widgets
import numpy as np
from matplotlib.figure import Figure

from hri_teleop.core import fsr
from hri_teleop.core.mapping import ADC_MAX_COUNT, map_force
from hri_teleop.course.widgets._base import FigureView, WidgetError

__all__ = ["FsrReading", "FsrCurve", "fsr_reading", "fsr_curve", "format_ohm", "describe_reading", "datasheet_note",
           "PULLDOWN_CHOICES_OHM", "SUPPLY_CHOICES_V", "FsrExplorer"]

#: Pull-down resistors to try (E6 series, ohm): the lab's is 10 kOhm.
PULLDOWN_CHOICES_OHM: Tuple[float, ...] = (1e3, 2.2e3, 3.3e3, 4.7e3, 10e3, 22e3, 47e3, 100e3)
#: Supplies of the boards students meet (V): the Uno's 5 V, 3.3 V boards.
SUPPLY_CHOICES_V: Tuple[float, ...] = (3.3, 5.0)


@dataclass(frozen=True)
class FsrReading:
    """One point of the chain, with units in the names."""

    force_n: float
    resistance_ohm: float  # inf: open circuit (no force)
    voltage_v: float
    count: int
    mapped: float  # /force_mapped for max_sensor_force
    max_sensor_force: int


@dataclass(frozen=True)
class FsrCurve:
    """The chain sampled over a force range (arrays of equal length)."""

    force_n: np.ndarray
    resistance_ohm: np.ndarray
    voltage_v: np.ndarray
    count: np.ndarray


def fsr_reading(force_n: float, *, pulldown_ohm: float = fsr.PULLDOWN_OHM, supply_v: float = fsr.SUPPLY_V,
                adc_bits: int = fsr.ADC_BITS, max_sensor_force: int = 700) -> FsrReading:
    """The resistance, divider voltage, count and mapped value at ``force_n`` (N)."""
    resistance = fsr.force_to_resistance(force_n)
    voltage = fsr.resistance_to_voltage(resistance, pulldown_ohm, supply_v)
    count = fsr.voltage_to_count(voltage, supply_v, adc_bits)
    mapped = map_force(int(count), max_sensor_force)
    return FsrReading(float(force_n), float(resistance), float(voltage), int(count), float(mapped),
                      int(max_sensor_force))


def fsr_curve(max_force_n: float, *, pulldown_ohm: float = fsr.PULLDOWN_OHM, supply_v: float = fsr.SUPPLY_V,
              adc_bits: int = fsr.ADC_BITS, points: int = 400) -> FsrCurve:
    """The chain from 0 N to ``max_force_n``, denser at light touch where the curve is steep."""
    if not (isinstance(max_force_n, (int, float)) and 0 < max_force_n < math.inf):
        raise WidgetError(f"max_force_n must be a positive force in N, got {max_force_n!r}; e.g. 20")
    force = np.concatenate(([0.0], np.geomspace(max_force_n * 1e-4, max_force_n, int(points) - 1)))
    resistance = fsr.force_to_resistance(force)
    voltage = fsr.resistance_to_voltage(resistance, pulldown_ohm, supply_v)
    count = fsr.voltage_to_count(voltage, supply_v, adc_bits)
    return FsrCurve(force, resistance, voltage, count)


def format_ohm(resistance_ohm: float) -> str:
    """'7.1 kOhm', '250 Ohm', 'open circuit' (inf)."""
    if math.isinf(resistance_ohm):
        return "open circuit"
    if resistance_ohm >= 1e6:
        return f"{resistance_ohm / 1e6:.3g} MOhm"
    if resistance_ohm >= 1e3:
        return f"{resistance_ohm / 1e3:.3g} kOhm"
    return f"{resistance_ohm:.3g} Ohm"


def describe_reading(reading: FsrReading) -> str:
    """The chain in one line, as the explorer shows it."""
    return (f"F = {reading.force_n:.2f} N  ->  R = {format_ohm(reading.resistance_ohm)}  ->  "
            f"V = {reading.voltage_v:.2f} V  ->  count {reading.count}  ->  "
            f"/force_mapped = {reading.mapped:.3f} (max_sensor_force {reading.max_sensor_force})")


def datasheet_note(force_n: float) -> str:
    """Why the curve and the datasheet differ: at a datasheet force, both resistances side by side."""
    worst = max(abs(float(fsr.force_to_resistance(f)) / r - 1.0) for f, r in fsr.FSR402_POINTS)
    note = (f"The blue curve is one power law fitted through the datasheet's four points (x); it misses each "
            f"by up to {100 * worst:.0f} % (a typical part, not a calibration).")
    for point_n, point_ohm in fsr.FSR402_POINTS:
        if abs(force_n - point_n) <= 0.01 * point_n:
            note += (f" At {point_n:g} N the datasheet gives {format_ohm(point_ohm)}, the curve "
                     f"{format_ohm(float(fsr.force_to_resistance(point_n)))}; a question that quotes the datasheet "
                     "uses its value.")
    return note


class FsrExplorer(widgets.VBox):
    """Force slider, pull-down and supply controls, the curves with the current point, and the numbers.

    ``explorer.reading`` is the current :class:`FsrReading`; the controls are
    ``force``, ``pulldown``, ``supply`` and ``max_sensor_force`` (ipywidgets you may set).
    """

    def __init__(self, force_n: float = 1.0, *, pulldown_ohm: float = fsr.PULLDOWN_OHM,
                 supply_v: float = fsr.SUPPLY_V, max_sensor_force: int = 700, max_force_n: float = 20.0,
                 figure: str = "auto") -> None:
        if not 0.0 <= force_n <= max_force_n:
            raise WidgetError(f"force_n must be in 0..{max_force_n} N, got {force_n!r}")
        pulldowns = sorted(set(PULLDOWN_CHOICES_OHM) | {float(pulldown_ohm)})
        supplies = sorted(set(SUPPLY_CHOICES_V) | {float(supply_v)})
        self.max_force_n = float(max_force_n)
        style = {"description_width": "150px"}
        wide = widgets.Layout(width="520px")
        self.force = widgets.FloatSlider(value=force_n, min=0.0, max=self.max_force_n, step=0.01,
                                         description="force (N)", readout_format=".2f", style=style, layout=wide)
        self.pulldown = widgets.Dropdown(options=[(format_ohm(r), r) for r in pulldowns], value=float(pulldown_ohm),
                                         description="pull-down resistor", style=style)
        self.supply = widgets.Dropdown(options=[(f"{v:g} V", v) for v in supplies], value=float(supply_v),
                                       description="supply", style=style)
        self.max_sensor_force = widgets.IntSlider(value=int(max_sensor_force), min=1, max=ADC_MAX_COUNT,
                                                  description="max_sensor_force", style=style, layout=wide)
        self.readout = widgets.HTML()

        fig = Figure(figsize=(9.5, 3.6), dpi=90, constrained_layout=True)
        self._ax_r, self._ax_c = fig.subplots(1, 2)
        self._build_axes()
        self.view = FigureView(fig, figure)
        super().__init__([self.force, widgets.HBox([self.pulldown, self.supply]), self.max_sensor_force,
                          self.readout, self.view.widget])
        for control in (self.force, self.pulldown, self.supply, self.max_sensor_force):
            control.observe(self._changed, names="value")
        self._update(curve=True)

    @property
    def reading(self) -> FsrReading:
        return fsr_reading(self.force.value, pulldown_ohm=self.pulldown.value, supply_v=self.supply.value,
                           max_sensor_force=self.max_sensor_force.value)

    def _build_axes(self) -> None:
        ax = self._ax_r
        law = fsr.FSR402
        grid = np.geomspace(0.05, 100.0, 200)
        ax.loglog(grid, fsr.force_to_resistance(grid), color="tab:blue", lw=1.5,
                  label=f"model R = {law.r_at_1n_ohm / 1e3:.1f} kOhm * F^-{law.exponent:.2f}")
        points = np.asarray(fsr.FSR402_POINTS)
        ax.loglog(points[:, 0], points[:, 1], "x", color="k", label="datasheet points")
        (self._point_r,) = ax.loglog([], [], "o", color="tab:red", ms=8)
        ax.set_xlabel("force (N)")
        ax.set_ylabel("FSR resistance (Ohm)")
        ax.set_title("FSR 402 (handout Fig. 4)", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")

        ax = self._ax_c
        (self._curve_c,) = ax.plot([], [], color="tab:green", lw=1.5, label="ADC count")
        (self._point_c,) = ax.plot([], [], "o", color="tab:red", ms=8)
        self._max_line = ax.axhline(700, color="tab:orange", ls="--", lw=1)
        ax.set_xlim(0, self.max_force_n)
        ax.set_ylim(-20, 1043)
        ax.set_xlabel("force (N)")
        ax.set_ylabel("ADC count on /pub_force")
        ax.grid(True, alpha=0.3)
        self._ax_v = ax.twinx()
        self._ax_v.set_ylabel("divider voltage (V)")
        ax.legend(fontsize=7, loc="lower right")

    def _changed(self, change: Any) -> None:
        self._update(curve=change["owner"] in (self.pulldown, self.supply))

    def _update(self, curve: bool = False) -> None:
        reading = self.reading
        if curve:
            data = fsr_curve(self.max_force_n, pulldown_ohm=self.pulldown.value, supply_v=self.supply.value)
            self._curve_c.set_data(data.force_n, data.count)
            steps = 2 ** fsr.ADC_BITS
            # Same scale on both axes: count c reads as c * supply / 2**bits volt.
            low, high = self._ax_c.get_ylim()
            self._ax_v.set_ylim(low * self.supply.value / steps, high * self.supply.value / steps)
            self._ax_c.set_title(f"divider: FSR over {format_ohm(self.pulldown.value)} at {self.supply.value:g} V",
                                 fontsize=10)
        pressed = reading.force_n > 0  # no force: open circuit, no point on a log axis
        self._point_r.set_data([reading.force_n] if pressed else [], [reading.resistance_ohm] if pressed else [])
        self._point_c.set_data([reading.force_n], [reading.count])
        self._max_line.set_ydata([reading.max_sensor_force, reading.max_sensor_force])
        self._max_line.set_label(f"max_sensor_force {reading.max_sensor_force} -> /force_mapped 1.0")
        self._ax_c.legend(fontsize=7, loc="lower right")
        self.readout.value = (f"<code>{describe_reading(reading)}</code><br>"
                              f"<small>{datasheet_note(reading.force_n)}</small>")
        self.view.redraw()
