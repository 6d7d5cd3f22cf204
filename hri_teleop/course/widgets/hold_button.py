"""A button that acts only while it is held (widgets.HoldButton): the controller view's cross and circle.

A toggle button latches: clicked once, it stays pressed until clicked again, and a gripper driven by
it closes to 0 mm. This one is held only while the page says so (hold_button.js): pointer down on it
presses, pointer up, leaving the button, a cancelled touch, a window that loses focus or a hidden tab
release it. While held the page sends a beat every ``BEAT_PERIOD_MS``; no beat for ``HOLD_TIMEOUT_S``
(a closed tab, a lost link, a kernel that restarted) is a release too, decided in the kernel.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path
from typing import Any, Callable, Optional

import anywidget
import traitlets

__all__ = ["HoldButton", "BEAT_PERIOD_MS", "HOLD_TIMEOUT_S"]

#: How often the page confirms a button it holds, ms.
BEAT_PERIOD_MS = 100
#: No word from the page for this long and a held button counts as released, s (several beats lost).
HOLD_TIMEOUT_S = 0.5


class HoldButton(anywidget.AnyWidget):
    """Pressed while held in the page, and for one look after a press shorter than a tick (:meth:`take_press`).

    ``clock``: the kernel's monotonic clock (tests). ``lit``: shown pressed by the kernel (a real
    pad's button, mirrored), without being held.
    """

    _esm = Path(__file__).with_name("hold_button.js").read_text(encoding="utf-8")
    description = traitlets.Unicode("").tag(sync=True)
    tooltip = traitlets.Unicode("").tag(sync=True)
    disabled = traitlets.Bool(False).tag(sync=True)
    lit = traitlets.Bool(False).tag(sync=True)
    held = traitlets.Bool(False).tag(sync=True)       # page -> kernel
    beat = traitlets.Int(0).tag(sync=True)            # page -> kernel, counts up while held
    beat_period_ms = traitlets.Int(BEAT_PERIOD_MS).tag(sync=True)

    def __init__(self, description: str = "", *, tooltip: str = "", disabled: bool = False,
                 timeout_s: float = HOLD_TIMEOUT_S, clock: Callable[[], float] = time.monotonic) -> None:
        super().__init__(description=description, tooltip=tooltip, disabled=disabled)
        self.timeout_s = float(timeout_s)
        self._clock = clock
        self._lock = threading.Lock()
        self._heard_s: Optional[float] = None
        self._pressed_since_look = False
        self.observe(self._from_page, names=["held", "beat"])

    def _from_page(self, change: Any) -> None:
        with self._lock:
            self._heard_s = self._clock()
            if change["name"] == "held" and change["new"]:
                self._pressed_since_look = True

    def is_held(self, now: Optional[float] = None) -> bool:
        """Held in the page, and the page was heard within ``timeout_s`` (else it counts as released)."""
        at = self._clock() if now is None else now
        with self._lock:
            heard = self._heard_s
        return bool(self.held) and heard is not None and 0.0 <= at - heard <= self.timeout_s

    def take_press(self, now: Optional[float] = None) -> bool:
        """Whether it is held now, or was pressed since the last look (a click shorter than a tick counts once)."""
        held = self.is_held(now)
        with self._lock:
            pressed, self._pressed_since_look = self._pressed_since_look, False
        return held or pressed

    def release(self) -> None:
        """Released from the kernel's side (a reset): the page's next press holds it again."""
        with self._lock:
            self._heard_s = None
            self._pressed_since_look = False
        self.held = False
