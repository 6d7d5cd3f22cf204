"""The stale-input watchdog: a pad whose held stick reads bit for bit the same is treated as lost.

A wireless pad whose link drops without a removal event keeps reporting its last reading, so the
node's input timeout (which only sees that the pad answers) lets the arm run on. A hand never
holds a stick that still: it trembles by at least one step of the pad's resolution within a
fraction of a second. A resting pad may read the same forever; only a deflection counts.
"""

from __future__ import annotations

import math
from typing import Optional, Sequence, Tuple

from hri_teleop.core.checks import is_finite_number
from hri_teleop.core.gamepad.state import AXES, STICK_AXES, GamepadError, PadState

__all__ = ["StaleInputWatch", "STALE_INPUT_TIMEOUT_S"]

#: Default (s): a held stick reading identical for longer means a frozen link (teleop.yaml explains).
STALE_INPUT_TIMEOUT_S = 1.0


class StaleInputWatch:
    """Whether a connected pad's readings froze while a stick was held off its rest.

    ``update`` gets each reading and the time (s, any monotonic clock). The readings are all
    axes of the state, compared exactly; a stick counts as held when one of ``watched`` axes
    is beyond ``deadzone``. Stale once identical and held for more than ``timeout_s``; fresh
    again as soon as a reading changes or the sticks return to rest. ``timeout_s`` 0: off.
    """

    def __init__(self, timeout_s: float = STALE_INPUT_TIMEOUT_S, deadzone: float = 0.0,
                 watched: Sequence[str] = STICK_AXES) -> None:
        if not is_finite_number(timeout_s) or timeout_s < 0:
            raise GamepadError(f"stale_input_timeout must be >= 0 s (0: off), got {timeout_s!r}; e.g. 1.0")
        if not is_finite_number(deadzone) or not 0.0 <= deadzone < 1.0:
            raise GamepadError(f"deadzone must be in [0, 1), got {deadzone!r}; e.g. 0.1")
        unknown = [a for a in watched if a not in AXES]
        if unknown:
            raise GamepadError(f"unknown axis {unknown[0]!r} to watch; use names of {', '.join(AXES)}")
        self.timeout_s = float(timeout_s)
        self.deadzone = float(deadzone)
        self.watched = tuple(watched)
        self._last: Optional[Tuple[float, ...]] = None
        self._since_s: Optional[float] = None  # when the current identical, held run began
        self.stale = False

    def frozen_s(self, now_s: float) -> float:
        """How long the readings have been identical with a stick held (0 when they are not)."""
        return 0.0 if self._since_s is None else max(0.0, float(now_s) - self._since_s)

    def reset(self) -> None:
        self._last, self._since_s, self.stale = None, None, False

    def update(self, state: Optional[PadState], now_s: float) -> bool:
        """Feed one reading (None or disconnected: forgotten, other rules stop the arm); True while stale."""
        if state is None or not state.connected or self.timeout_s == 0.0:
            self.reset()
            return False
        reading = tuple(state.axis(a) for a in AXES)
        held = any(abs(state.axis(a)) > self.deadzone for a in self.watched if math.isfinite(state.axis(a)))
        if not held or reading != self._last:
            self._since_s = float(now_s) if held else None
        self._last = reading
        self.stale = self.frozen_s(now_s) > self.timeout_s
        return self.stale
