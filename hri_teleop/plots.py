"""Figures of recorded traces, written as PNG files (matplotlib's Agg backend: no screen).

Why a module: the demo, the notebooks and the grader's feedback draw the same kinds of
timeline, and a figure says more than a table about a force that ramps and saturates.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence, Tuple

Trace = Sequence[Tuple[float, float]]


def sensor_timeline(counts: Trace, mapped: Trace, max_sensor_force: float, path: Path) -> Path:
    """/pub_force (counts, left axis) and /force_mapped (0..1, right axis) over time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t0 = min(counts[0][0] if counts else float("inf"), mapped[0][0] if mapped else float("inf"))
    fig, ax = plt.subplots(figsize=(9, 3.5), dpi=100)
    ax.plot([t - t0 for t, _ in counts], [v for _, v in counts], color="tab:blue", lw=1.2, label="/pub_force (count)")
    ax.axhline(max_sensor_force, color="tab:blue", ls=":", lw=1, label=f"/max_sensor_force = {max_sensor_force:g}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("ADC count (0..1023)", color="tab:blue")
    ax.set_ylim(-20, 1043)
    right = ax.twinx()
    right.plot([t - t0 for t, _ in mapped], [v for _, v in mapped], color="tab:orange", lw=1.2, label="/force_mapped")
    right.set_ylabel("/force_mapped (0..1)", color="tab:orange")
    right.set_ylim(-0.02, 1.02)
    lines = ax.get_legend_handles_labels()
    more = right.get_legend_handles_labels()
    ax.legend(lines[0] + more[0], lines[1] + more[1], loc="upper right", fontsize=8)
    ax.set_title("Sensor pipeline: counts clip to 1.0 above /max_sensor_force")
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path
