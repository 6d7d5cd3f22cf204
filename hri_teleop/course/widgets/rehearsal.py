"""RehearsalOffer: a fresh analysis notebook offers to rehearse a study instead of failing.

With no recorded trials in the folder, the widget says so and offers the rehearsal of
``python -m hri_teleop.apps.trial rehearse --quick``: scripted participants in the simulated
lab over real ROS (a private roscore, teleoperation.launch sim:=true, rosbag), about 10 s a
trial, written into the folder as the lab's trials are. With trials there, it says how
many. The analysis cells then read the folder as they read a lab session.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, List, Optional, Union

import ipywidgets as widgets

from hri_teleop.ros.trial import load_trials, rehearse

__all__ = ["RehearsalOffer", "count_trials"]


def count_trials(folder: Path) -> int:
    """How many trials the folder holds (a ``*.yaml`` sidecar beside its ``*.bag``)."""
    if not folder.is_dir():
        return 0
    return sum(1 for sidecar in folder.glob("*.yaml") if sidecar.with_suffix(".bag").is_file())


def _default_rehearse(participants: List[str], objects: List[str], out: Path,
                      progress: Callable[[str], None]) -> Any:
    return rehearse(participants, objects, out, quick=True, analyse=False, progress=progress)


class RehearsalOffer(widgets.VBox):
    """The folder's trials, or a button that rehearses a simulated session into it."""

    def __init__(self, folder: Union[str, Path], *, objects: Optional[List[str]] = None,
                 rehearse: Callable[..., Any] = _default_rehearse) -> None:
        self.folder = Path(folder)
        self.objects = list(objects or ["egg"])
        self._rehearse = rehearse
        self.status = widgets.HTML()
        self.participants = widgets.IntSlider(value=4, min=2, max=12, description="participants")
        self.button = widgets.Button(description="Rehearse", button_style="primary",
                                     tooltip="scripted participants in the simulated lab, about 10 s a trial")
        self.output = widgets.Output()
        self.button.on_click(lambda _b: self.rehearse())
        super().__init__([self.status, widgets.HBox([self.participants, self.button]), self.output])
        self.refresh()

    def refresh(self) -> int:
        """Show how many trials the folder holds; the offer only when it holds none."""
        n = count_trials(self.folder)
        if n:
            self.status.value = f"{n} trial(s) in <code>{self.folder}</code>."
        else:
            self.status.value = (f"No recorded trials in <code>{self.folder}</code> yet. Rehearse a session in the "
                                 "simulated lab (scripted participants, both conditions, counterbalanced; about 10 s "
                                 "a trial), or record one in the lab (README, <i>Ex. 14 experiment</i>).")
        for child in (self.participants, self.button):
            child.layout.display = "none" if n else ""
        return n

    def rehearse(self) -> int:
        """Rehearse ``participants`` scripted participants into the folder; returns the trials it then holds."""
        codes = [f"P{k:02d}" for k in range(1, self.participants.value + 1)]
        self.button.disabled = True
        try:
            with self.output:
                print(f"rehearsing {len(codes)} participants x 2 conditions into {self.folder} ...", flush=True)
                self._rehearse(codes, self.objects, self.folder, progress=lambda line: print(line, flush=True))
        except Exception as exc:  # noqa: BLE001 - one line in the widget, the notebook goes on
            with self.output:
                print(f"rehearsal stopped: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}")
        finally:
            self.button.disabled = False
        return self.refresh()

    def trials(self) -> List[Any]:
        """The folder's trials (loaded), or [] with one line saying how to get some."""
        if not count_trials(self.folder):
            print(f"no trials in {self.folder} yet: press Rehearse above (or record them in the lab), then run "
                  "the cells below again")
            return []

        return load_trials(self.folder)
