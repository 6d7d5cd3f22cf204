"""Figures of a class's grades: the distribution of totals and the pass rate of every graded item.

The numbers come in already computed (bins, rates), so these only draw: any grader's class report
can use them, and the arithmetic is tested where it is computed.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence, Tuple

import matplotlib
import matplotlib.pyplot as plt

from hri_teleop.plots.common import save_figure

__all__ = ["score_histogram", "pass_rate_chart"]

#: (lower edge, upper edge, count) of one bar.
Bin = Tuple[float, float, int]


def score_histogram(panels: Sequence[Tuple[str, Sequence[Bin], float]], path: Path) -> Path:
    """One histogram per (title, bins, maximum points), side by side, as a PNG."""
    matplotlib.use("Agg")
    panels = list(panels) or [("no graded submissions", [], 1.0)]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.5 * len(panels) + 1, 3.6), dpi=100, squeeze=False)
    for ax, (title, bins, maximum) in zip(axes[0], panels):
        if bins:
            ax.bar([lo for lo, _hi, _n in bins], [n for _lo, _hi, n in bins],
                   width=[hi - lo for lo, hi, _n in bins], align="edge", color="tab:blue", edgecolor="white")
        ax.set_xlim(0, maximum or 1.0)
        ax.set_xlabel("points")
        ax.set_ylabel("students")
        ax.set_title(title, fontsize=10)
        ax.yaxis.get_major_locator().set_params(integer=True)
    return save_figure(fig, path)


def pass_rate_chart(items: Sequence[Tuple[str, float]], path: Path, title: str = "") -> Path:
    """A horizontal bar per (label, rate in 0..1), in the order given (top first), as a PNG."""
    matplotlib.use("Agg")
    items = list(items) or [("no graded items", 0.0)]
    height = max(2.5, 0.22 * len(items) + 1.2)
    fig, ax = plt.subplots(figsize=(10, height), dpi=100)
    positions = list(range(len(items)))[::-1]
    rates = [100.0 * rate for _label, rate in items]
    colours = ["tab:red" if r < 50 else "tab:orange" if r < 80 else "tab:green" for r in rates]
    ax.barh(positions, rates, color=colours, height=0.7)
    ax.set_yticks(positions)
    ax.set_yticklabels([label for label, _rate in items], fontsize=7)
    ax.set_xlim(0, 100)
    ax.set_xlabel("students with full points (%)")
    ax.set_title(title, fontsize=10)
    ax.grid(axis="x", alpha=0.3)
    return save_figure(fig, path)
