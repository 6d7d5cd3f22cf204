"""The workload questionnaire (raw NASA-TLX) after a trial, stored with the trial.

On paper the sheet must be matched to the recording and typed in, two places for a mix-up. Here
the experimenter picks the trial (the newest without answers is preselected), the participant moves
six sliders, and *save* writes them into that trial's sidecar
(:func:`hri_teleop.core.experiment.tlx.store_tlx`). The rules are the core's; this is the form, no
ROS needed. Programmatic use: :meth:`TlxWidget.set_ratings`, :meth:`~TlxWidget.save`.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, List, Optional, Union

import ipywidgets as widgets

from hri_teleop.core.experiment.metrics import MetricsError
from hri_teleop.core.experiment.sidecar import read_sidecar
from hri_teleop.core.experiment.tlx import STEP, SUBSCALES, TlxRatings, optional_tlx, store_tlx
from hri_teleop.course.widgets._base import WidgetError, message_html, replace_in_cell

__all__ = ["TlxWidget", "trial_sidecars"]

#: Where each slider starts for a trial not rated yet (the middle of the scale).
START_RATING = 50


def trial_sidecars(folder: Union[str, Path]) -> List[Path]:
    """The trial sidecars (``*.yaml`` beside a ``*.bag``) in ``folder``, oldest first by modification time."""
    folder = Path(folder)
    if not folder.is_dir():
        raise WidgetError(f"{folder}: no such folder of trials; give the folder `trial record` writes to")
    found = [p for p in folder.glob("*.yaml") if p.with_suffix(".bag").exists()]
    return sorted(found, key=lambda p: (p.stat().st_mtime, p.name))


class TlxWidget(widgets.VBox):
    """Six sliders, the raw TLX score, and *save* into the chosen trial's sidecar.

    ``trial``: a sidecar path (e.g. ``trials/P01_t03.yaml``); or ``folder``: a trials folder
    to choose from (a *refresh* button lists new trials).  The sliders show the trial's
    stored ratings when it has some.
    """

    def __init__(self, trial: Union[str, Path, None] = None, *, folder: Union[str, Path, None] = None) -> None:
        if trial is None and folder is None:
            raise WidgetError("give the trial's sidecar (trial='trials/P01_t01.yaml') or a folder of trials "
                              "(folder='trials')")
        self.folder = None if folder is None else Path(folder)
        self.sliders: Dict[str, widgets.IntSlider] = {}
        rows = []
        for s in SUBSCALES:
            slider = widgets.IntSlider(value=START_RATING, min=0, max=100, step=STEP, description=s.title,
                                       continuous_update=True, style={"description_width": "120px"},
                                       layout=widgets.Layout(width="520px"))
            slider.observe(lambda _change: self._show_score(), names="value")
            self.sliders[s.key] = slider
            rows.append(widgets.VBox([
                widgets.HTML(f"<b>{s.title}</b>: {s.question}"),
                widgets.HBox([slider, widgets.HTML(f"<small>0 = {s.low}, 100 = {s.high}</small>")]),
            ]))
        self.score = widgets.HTML()
        self.status = widgets.HTML()
        self.save_button = widgets.Button(description="save", button_style="success", icon="save")
        self.save_button.on_click(lambda _b: self._guarded(self.save))
        if self.folder is not None:
            self.trial = widgets.Dropdown(description="trial", layout=widgets.Layout(width="520px"))
            self.refresh_button = widgets.Button(description="refresh", icon="refresh")
            self.refresh_button.on_click(lambda _b: self._guarded(self.refresh))
            chooser = widgets.HBox([self.trial, self.refresh_button])
        else:
            self.trial = widgets.Text(value=str(trial), description="trial", layout=widgets.Layout(width="520px"))
            self.refresh_button = None
            chooser = widgets.HBox([self.trial])
        self.trial.observe(lambda _change: self._guarded(self.load), names="value")
        super().__init__([chooser] + rows + [widgets.HBox([self.score, self.save_button]), self.status])
        self._show_score()
        self._guarded(self.refresh if self.folder is not None else self.load)
        replace_in_cell(self)

    # -- helpers ---------------------------------------------------------------------
    def _guarded(self, action: Any) -> None:
        try:
            message = action()
        except (MetricsError, WidgetError, OSError) as exc:
            self.status.value = message_html(str(exc), error=True)
            return
        if isinstance(message, str):
            self.status.value = message_html(message)

    def _show_score(self) -> None:
        self.score.value = f"<b>raw TLX {self.ratings().raw_tlx:.1f}</b> (mean of the six) &nbsp;"

    @property
    def path(self) -> Optional[Path]:
        """The chosen trial's sidecar (None when nothing is chosen)."""
        value = self.trial.value
        return Path(value) if value else None

    # -- actions ---------------------------------------------------------------------
    def ratings(self) -> TlxRatings:
        """The sliders' current answers."""
        return TlxRatings(**{key: int(slider.value) for key, slider in self.sliders.items()})

    def set_ratings(self, **ratings: int) -> None:
        """Move sliders (keys: mental, physical, temporal, performance, effort, frustration)."""
        unknown = sorted(set(ratings) - set(self.sliders))
        if unknown:
            raise WidgetError(f"unknown TLX subscale(s) {', '.join(unknown)}; use {', '.join(self.sliders)}")
        checked = TlxRatings(**{**{k: s.value for k, s in self.sliders.items()}, **ratings})
        for key in ratings:
            self.sliders[key].value = getattr(checked, key)

    def refresh(self) -> str:
        """List the folder's trials again; preselect the newest one without answers."""
        if self.folder is None:
            return self.load()
        sidecars = trial_sidecars(self.folder)
        if not sidecars:
            self.trial.options = []
            return f"no trials in {self.folder} yet: record one, then press refresh"
        pending = [p for p in sidecars if "tlx" not in read_sidecar(p)]
        self.trial.options = [(p.name, str(p)) for p in sidecars]
        chosen = pending[-1] if pending else sidecars[-1]
        if self.trial.value == str(chosen):
            return self.load()
        self.trial.value = str(chosen)  # load() runs through the observer
        return self._loaded_message()

    def _loaded_message(self) -> str:
        path = self.path
        if path is None:
            return "choose a trial"
        data = read_sidecar(path)
        stored = optional_tlx(data, str(path))
        label = f"{data.get('participant', '?')} trial {data.get('trial', '?')} ({data.get('object_name', '?')}, " \
                f"{data.get('condition', '?')})"
        if stored is None:
            return f"{label}: not rated yet; the participant moves the sliders, then save"
        return f"{label}: rated (raw TLX {stored.raw_tlx:.1f}); saving again replaces the answers"

    def load(self) -> str:
        """Show the chosen trial's stored answers (or the scale's middle when it has none)."""
        path = self.path
        if path is None:
            return "choose a trial"
        stored = optional_tlx(read_sidecar(path), str(path))
        values = {k: START_RATING for k in self.sliders} if stored is None else {
            k: getattr(stored, k) for k in self.sliders}
        for key, value in values.items():
            self.sliders[key].value = value
        return self._loaded_message()

    def save(self, path: Union[str, Path, None] = None) -> str:
        """Store the sliders' answers in the trial's sidecar (``path`` or the chosen one); returns what was done."""
        target = Path(path) if path is not None else self.path
        if target is None:
            raise WidgetError("no trial chosen: pick the trial the participant just did")
        ratings = self.ratings()
        store_tlx(target, ratings)
        return f"saved to {os.fspath(target)}: raw TLX {ratings.raw_tlx:.1f}"
