"""The experiment's figures: force over time, peak force, success and crush rates, the paired test.

Force over time per condition, peak force by condition and object, and the paired comparison in
words. The analysis notebook and the tests draw the same page, so a figure a student hands in is
the one the tests checked.
"""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional, Sequence, Tuple, Union

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.experiment.analysis import StudyResult
from hri_teleop.core.experiment.metrics import (
    CONDITIONS,
    TrialMetrics,
    calibrated_force_n,
    paired_by_participant,
)
from hri_teleop.core.experiment.stats import PairedComparison, StatsError, paired_comparison
from hri_teleop.core.run_record import LabRecord
from hri_teleop.plots.common import save_figure

__all__ = ["PANEL_TITLES", "COLOURS", "StudyFigureError", "draw_study", "study_figure"]

#: The condition colours (the tests look for them in the PNG).
COLOURS = {"feedback": "tab:blue", "no_feedback": "tab:red"}
#: The titles of the four panels, in reading order (the fourth is the text panel).
PANEL_TITLES = ("Grasp force over time", "Peak force by object (bar: median)", "Outcomes", "Paired comparison")


class StudyFigureError(HriTeleopError, ValueError):
    """The study's figure asked for with calibrations that do not match its trials."""


def _per_trial(max_sensor_force: Union[float, Sequence[float]], n: int) -> List[float]:
    if isinstance(max_sensor_force, (int, float)):
        return [float(max_sensor_force)] * n
    values = [float(v) for v in max_sensor_force]
    if len(values) != n:
        raise StudyFigureError(f"max_sensor_force: {len(values)} values for {n} trials; "
                               "give one per trial or one for all")
    return values


def study_figure(trials: Sequence[Tuple[TrialMetrics, LabRecord]], max_sensor_force: Union[float, Sequence[float]],
                 path: Path, comparison: Optional[PairedComparison] = None) -> Path:
    """A four-panel PNG of a study (see the module doc); returns its path."""
    return save_figure(draw_study(trials, max_sensor_force, comparison), path)


def draw_study(trials: Sequence[Tuple[TrialMetrics, LabRecord]], max_sensor_force: Union[float, Sequence[float]],
               comparison: Optional[PairedComparison] = None) -> Figure:
    """The study's figure (a pyplot Figure; :func:`study_figure` saves and closes it).

    ``max_sensor_force``: the calibration, one for all trials or one per trial (sessions on
    different days are calibrated anew).  ``comparison``: the paired comparison of peak
    force (no feedback minus feedback) to print; None computes it from the trials.
    """
    matplotlib.use("Agg")

    metrics = [m for m, _ in trials]
    calibrations = _per_trial(max_sensor_force, len(trials))
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), dpi=100)
    ax = axes[0][0]
    for (m, rec), max_count in zip(trials, calibrations):
        if not rec.count:
            continue
        t0 = rec.start_s()
        t = np.array([s for s, _ in rec.count]) - t0
        f = calibrated_force_n([c for _, c in rec.count], max_count)
        ax.plot(t, f, color=COLOURS[m.meta.condition], alpha=0.35, lw=0.9)
    for c in CONDITIONS:
        ax.plot([], [], color=COLOURS[c], label=c.replace("_", " "))
    ax.set_xlabel("time in trial (s)")
    ax.set_ylabel("FSR force (N)")
    ax.set_title(PANEL_TITLES[0])
    ax.legend(fontsize=8)

    ax = axes[0][1]
    objects = sorted({m.meta.object_name for m in metrics})
    for j, c in enumerate(CONDITIONS):
        for i, obj in enumerate(objects):
            values = [m.peak_force_n for m in metrics if m.meta.condition == c and m.meta.object_name == obj]
            x = i + (j - 0.5) * 0.3
            ax.scatter([x] * len(values), values, color=COLOURS[c], alpha=0.7, s=18)
            if values:
                ax.hlines(np.median(values), x - 0.12, x + 0.12, color=COLOURS[c], lw=2)
    ax.set_xticks(range(len(objects)))
    ax.set_xticklabels(objects)
    ax.set_xlim(-0.5, len(objects) - 0.5)
    ax.set_ylabel("peak FSR force (N)")
    ax.set_title(PANEL_TITLES[1])

    ax = axes[1][0]
    width = 0.35
    for j, c in enumerate(CONDITIONS):
        group = [m for m in metrics if m.meta.condition == c]
        n = max(len(group), 1)
        rates = [sum(m.success for m in group) / n, sum(m.crushed for m in group) / n]
        ax.bar(np.arange(2) + (j - 0.5) * width, rates, width, color=COLOURS[c], label=f"{c.replace('_', ' ')} (n={len(group)})")
    ax.set_xticks(range(2))
    ax.set_xticklabels(["success (lifted, intact)", "crushed"])
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("rate")
    ax.legend(fontsize=8)
    ax.set_title(PANEL_TITLES[2])

    ax = axes[1][1]
    ax.axis("off")
    ax.set_title(PANEL_TITLES[3])
    lines: List[str] = ["Peak force, per participant: mean over trials", ""]
    try:
        if comparison is None:
            _both, without, with_fb, _left = paired_by_participant(metrics, "peak_force_n")
            comparison = paired_comparison(without, with_fb)
        result = comparison
        lines += [f"pairs: {result.n_pairs}", f"median(no feedback - feedback) = {result.median_difference:.3f} N",
                  f"{result.test}:", f"  W+ = {result.w_plus:g}, W- = {result.w_minus:g}, p = {result.p_value:.3f}",
                  f"rank-biserial r = {result.rank_biserial:+.2f}", "", "Assumptions:"]
        lines += _wrap(result.assumptions, 60)
    except StatsError as exc:
        lines += ["not computed:"] + _wrap(str(exc), 60)
    ax.text(0.0, 1.0, "\n".join(lines), va="top", family="monospace", fontsize=8.5, transform=ax.transAxes)
    fig.suptitle("Force feedback experiment (handout Ex. 14)")
    return fig


def _wrap(text: str, width: int) -> List[str]:
    out, line = [], ""
    for word in text.split():
        if len(line) + len(word) + 1 > width:
            out.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    return out + ([line] if line else [])


def save_result_figure(result: StudyResult, path: Union[str, Path]) -> StudyResult:
    """Draw an analysed study (:func:`~hri_teleop.core.experiment.analysis.analyse_trials`) to a PNG at ``path``.

    Sets ``result.figure`` (the file) and ``result.figure_panels`` (the panels' titles); returns ``result``.
    """
    fig = draw_study(list(zip(result.metrics, [t.record for t in result.trials])), result.max_sensor_force,
                     result.peak_force)
    result.figure_panels = tuple(ax.get_title() for ax in fig.axes)
    result.figure = save_figure(fig, Path(path))
    return result
