"""The force-feedback experiment's analysis notebook: recorded trials, their statistics and NASA-TLX."""

from __future__ import annotations

from hri_teleop.core.experiment.analysis import analyse_trials, default_trials_folder
from hri_teleop.course.widgets.rehearsal import RehearsalOffer
from hri_teleop.course.widgets.tlx import TlxWidget
from hri_teleop.plots.study import save_result_figure

__all__ = ["analyse_trials", "default_trials_folder", "save_result_figure", "RehearsalOffer", "TlxWidget"]
