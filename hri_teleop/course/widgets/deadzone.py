"""Dead-zone explorer (handout Fig. 8): what ``normalize_analog_input`` does to a stick.

Why: a centred stick never reads exactly 0, and the handout's filter is easier to
understand as a curve and a dot than as code. The curve and the filtered stick come from
:func:`hri_teleop.core.gamepad.normalize_analog_input`, the function the teleoperation node
applies to each stick axis on its own (as :class:`~hri_teleop.core.teleop.TeleopController` does).
"""

from __future__ import annotations

from typing import Optional, Tuple

import ipywidgets as widgets
import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Rectangle

from hri_teleop.core.gamepad import check_deadzone, normalize_analog_input
from hri_teleop.course.widgets._base import FigureView, lab_teleop_config

__all__ = ["deadzone_curve", "filter_stick", "DeadzoneExplorer"]


def deadzone_curve(deadzone: float, points: int = 401) -> Tuple[np.ndarray, np.ndarray]:
    """(raw, filtered): the filter over the whole stick travel -1..1."""
    dz = check_deadzone(deadzone)
    raw = np.linspace(-1.0, 1.0, int(points))
    return raw, np.array([normalize_analog_input(float(v), dz) for v in raw])


def filter_stick(x: float, y: float, deadzone: float) -> Tuple[float, float]:
    """A stick position after the filter, each axis on its own (as the controller does)."""
    dz = check_deadzone(deadzone)
    return normalize_analog_input(x, dz), normalize_analog_input(y, dz)


class DeadzoneExplorer(widgets.VBox):
    """A dead-zone slider and a stick (x, y sliders): the filter's curve and the 2-D stick view.

    ``deadzone`` defaults to the lab's (hri_lab/config/teleop.yaml). Controls: ``deadzone``,
    ``stick_x``, ``stick_y``; ``explorer.filtered`` is the filtered (x, y).
    """

    def __init__(self, deadzone: Optional[float] = None, *, stick_x: float = 0.05, stick_y: float = 0.5,
                 figure: str = "auto") -> None:
        dz = check_deadzone(lab_teleop_config().params.deadzone if deadzone is None else deadzone)
        style = {"description_width": "90px"}
        self.deadzone = widgets.FloatSlider(value=dz, min=0.0, max=0.5, step=0.01, description="dead zone",
                                            style=style, layout=widgets.Layout(width="420px"))
        self.stick_x = widgets.FloatSlider(value=stick_x, min=-1.0, max=1.0, step=0.01, description="stick x",
                                           style=style, layout=widgets.Layout(width="420px"))
        self.stick_y = widgets.FloatSlider(value=stick_y, min=-1.0, max=1.0, step=0.01, description="stick y",
                                           style=style, layout=widgets.Layout(width="420px"))
        self.readout = widgets.HTML()

        fig = Figure(figsize=(9.0, 4.0), dpi=90, constrained_layout=True)
        self._ax_curve, self._ax_stick = fig.subplots(1, 2)
        self._build_axes()
        self.view = FigureView(fig, figure)
        super().__init__([self.deadzone, self.stick_x, self.stick_y, self.readout, self.view.widget])
        for control in (self.deadzone, self.stick_x, self.stick_y):
            control.observe(lambda _change: self._update(), names="value")
        self._update()

    @property
    def filtered(self) -> Tuple[float, float]:
        return filter_stick(self.stick_x.value, self.stick_y.value, self.deadzone.value)

    def _build_axes(self) -> None:
        ax = self._ax_curve
        ax.plot([-1, 1], [-1, 1], color="0.6", ls=":", lw=1, label="no filter")
        (self._curve,) = ax.plot([], [], color="tab:blue", lw=2, label="normalize_analog_input")
        (self._curve_point,) = ax.plot([], [], "o", color="tab:red", ms=8, label="stick x")
        # x in data units, y over the whole axes height
        self._band = ax.add_patch(Rectangle((-0.1, 0.0), 0.2, 1.0, transform=ax.get_xaxis_transform(),
                                            color="tab:orange", alpha=0.15, lw=0, label="dead zone"))
        ax.set_xlim(-1.05, 1.05)
        ax.set_ylim(-1.05, 1.05)
        ax.set_xlabel("stick input")
        ax.set_ylabel("filtered output")
        ax.set_title("handout Fig. 8: filter for an analog stick", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")

        ax = self._ax_stick
        ax.add_patch(Circle((0, 0), 1.0, fill=False, color="0.5"))
        self._band_x = ax.add_patch(Rectangle((-0.1, -1), 0.2, 2, color="tab:orange", alpha=0.15, lw=0))
        self._band_y = ax.add_patch(Rectangle((-1, -0.1), 2, 0.2, color="tab:orange", alpha=0.15, lw=0))
        (self._link,) = ax.plot([], [], color="0.5", lw=1, ls="--")
        (self._raw_dot,) = ax.plot([], [], "o", mfc="none", mec="tab:red", ms=12, mew=2, label="raw")
        (self._filtered_dot,) = ax.plot([], [], "o", color="tab:blue", ms=9, label="filtered")
        ax.set_xlim(-1.1, 1.1)
        ax.set_ylim(-1.1, 1.1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (right = +1)")
        ax.set_ylabel("y (up = +1)")
        ax.set_title("stick: each axis is filtered on its own", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")

    def _update(self) -> None:
        dz = self.deadzone.value
        raw, filtered = deadzone_curve(dz)
        self._curve.set_data(raw, filtered)
        x, y = self.stick_x.value, self.stick_y.value
        fx, fy = self.filtered
        self._curve_point.set_data([x], [fx])
        self._band.set_bounds(-dz, 0.0, 2 * dz, 1.0)
        self._band_x.set_bounds(-dz, -1.0, 2 * dz, 2.0)
        self._band_y.set_bounds(-1.0, -dz, 2.0, 2 * dz)
        self._raw_dot.set_data([x], [y])
        self._filtered_dot.set_data([fx], [fy])
        self._link.set_data([x, fx], [y, fy])
        self.readout.value = (f"<code>dead zone {dz:.2f}: raw ({x:+.2f}, {y:+.2f}) -> filtered "
                              f"({fx:+.3f}, {fy:+.3f})</code>")
        self.view.redraw()
