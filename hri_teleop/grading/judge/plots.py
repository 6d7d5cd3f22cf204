"""Expected-against-actual figures for failed trace comparisons (PNG, matplotlib's Agg backend).

Why: a list of three wrong numbers says *that* a mapping is wrong; a plot of the whole
trace says *how* (flat at 0: integer division; a line past 1.0: no clipping; a line with
the wrong slope: the wrong range), which is what a student needs to find the mistake.
"""

from __future__ import annotations

import functools
import math
import threading
from pathlib import Path
from typing import Any, Callable, List, Optional, Sequence, Tuple, TypeVar

from hri_teleop.grading.judge.compare_common import as_float

__all__ = ["expected_vs_actual", "series_plot", "timeline"]

F = TypeVar("F", bound=Callable[..., Any])
# pyplot keeps one registry of figures: checks graded side by side (grade_submission's jobs) draw one at a time
_DRAWING = threading.RLock()


def _one_at_a_time(draw: F) -> F:
    @functools.wraps(draw)
    def locked(*args: Any, **kwargs: Any) -> Any:
        with _DRAWING:
            return draw(*args, **kwargs)
    return locked  # type: ignore[return-value]


def _finite(values: Sequence[object]) -> List[float]:
    """Each value as a float; nan for what is none (None, text, a list...) or not finite."""
    out = []
    for v in values:
        try:
            f = float(v) if isinstance(v, (int, float, str)) else math.nan
        except ValueError:
            f = math.nan
        out.append(f if math.isfinite(f) else math.nan)
    return out


@_one_at_a_time
def expected_vs_actual(path: Path, title: str, x: Sequence[float], expected: Sequence[float],
                       actual: Sequence[Optional[float]], xlabel: str, ylabel: str,
                       inputs: Optional[Sequence[float]] = None, input_label: str = "",
                       marks: Sequence[int] = (), levels: Sequence[float] = ()) -> str:
    """Draw expected (line) and actual (dots, None = nothing arrived) over ``x``; returns the path.

    ``inputs`` go on a second axis (e.g. the counts sent); ``marks`` are indices of wrong
    values, circled in red; ``levels`` are values that must be reached (dashed lines).
    """
    import matplotlib  # noqa: PLC0415 - matplotlib (0.2 s) only when a plot is drawn

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: PLC0415 - after use("Agg")

    from hri_teleop.plots.common import save_figure  # noqa: PLC0415 - it imports pyplot

    fig, ax = plt.subplots(figsize=(9, 3.6), dpi=90)
    ax.plot(list(x), _finite(expected), color="tab:green", lw=1.6, label="expected", drawstyle="steps-post")
    act = _finite(actual)
    ax.plot(list(x), act, "o", ms=3, color="tab:orange", label="actual")
    if marks:
        ax.plot([x[i] for i in marks], [act[i] if not math.isnan(act[i]) else _finite(expected)[i] for i in marks],
                "o", ms=9, mfc="none", mec="tab:red", label="wrong or missing")
    for level in levels:
        ax.axhline(level, color="tab:green", ls="--", lw=1)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if inputs is not None:
        right = ax.twinx()
        right.plot(list(x), list(inputs), color="tab:blue", lw=0.8, alpha=0.5, drawstyle="steps-post")
        right.set_ylabel(input_label, color="tab:blue")
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(title, fontsize=10)
    return str(save_figure(fig, path))


def series_plot(plot_dir: Optional[Path], name: str, title: str, expected: List[float], actual: List[Any],
                ylabel: str, marks: List[int]) -> List[str]:
    """One attribute tick by tick, expected against the student's ([] without a folder)."""
    if plot_dir is None:
        return []
    return [expected_vs_actual(Path(plot_dir) / name, title, list(range(len(expected))), expected,
                               [as_float(a) for a in actual], "tick", ylabel, marks=marks)]


Series = Sequence[Tuple[float, Optional[float]]]


@_one_at_a_time
def timeline(path: Path, title: str, panels: Sequence[Tuple[str, Sequence[Tuple[str, Series]]]]) -> str:
    """Panels of (label, [(legend, [(t_s, value), ...]), ...]) stacked on one time axis; returns the path.

    For a run where several things had to happen in order (a launch file in simulation):
    the panel that stays flat shows which link of the chain did not work.
    """
    import matplotlib  # noqa: PLC0415 - matplotlib (0.2 s) only when a plot is drawn

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: PLC0415 - after use("Agg")

    from hri_teleop.plots.common import save_figure  # noqa: PLC0415 - it imports pyplot

    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 1.9 * len(panels)), dpi=90, sharex=True, squeeze=False)
    for ax, (label, lines) in zip(axes[:, 0], panels):
        for legend, series in lines:
            points = list(series)
            if points:
                ax.plot([t for t, _ in points], _finite([v for _, v in points]), lw=1.2, label=legend)
            else:
                ax.plot([], [], lw=1.2, label=f"{legend}: nothing arrived")
        ax.set_ylabel(label, fontsize=8)
        ax.legend(loc="upper left", fontsize=7)
    axes[-1, 0].set_xlabel("time since the launch (s)")
    axes[0, 0].set_title(title, fontsize=10)
    return str(save_figure(fig, path))
