"""When to send the pad a rumble request: the rule the teleoperation node follows.

Why: the controller computes a rumble intensity every tick (50 Hz), but each request is
a USB/Bluetooth transfer to the pad. Sending every tick floods the link; sending only on
change leaves the pad buzzing forever if the node dies. So a request goes out when the
intensity changes noticeably or switches on/off, and is refreshed while it stays on;
each request lasts a little longer than the refresh period, so the pad falls silent by
itself soon after the requests stop.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Tuple

from hri_teleop.core.checks import is_finite_number
from hri_teleop.core.gamepad.state import GamepadError


def unit_intensity(value: object) -> float:
    """A rumble strength clipped to 0..1; anything but a finite number is 0 (a bad value never shakes the pad)."""
    return min(1.0, max(0.0, float(value))) if is_finite_number(value, numpy=True) else 0.0


@dataclass(frozen=True)
class RumblePolicy:
    change: float = 0.02     # intensity change (0..1) that is worth a new request
    refresh_s: float = 0.25  # while on, repeat the request this often (s) ...
    hold_s: float = 0.5      # ... each lasting this long (s), so the pad stops by itself

    def __post_init__(self) -> None:
        if not (0 < self.change <= 1 and 0 < self.refresh_s < self.hold_s < math.inf):
            raise GamepadError(f"rumble policy needs 0 < change <= 1 and 0 < refresh_s < hold_s, got {self}; "
                               "use the defaults (0.02, 0.25 s, 0.5 s)")


class RumbleRequests:
    """Turns a per-tick intensity into the few requests the pad needs (see the module doc)."""

    def __init__(self, policy: RumblePolicy = RumblePolicy()) -> None:
        self.policy = policy
        self._sent: Tuple[float, ...] = (0.0, 0.0)
        self._sent_at = -math.inf

    def update(self, intensity: float, now_s: float) -> Optional[Tuple[float, float]]:
        """(intensity, duration_s) to send now, or None to send nothing."""
        request = self.update_motors(intensity, intensity, now_s)
        return None if request is None else (request[0], request[2])

    def update_motors(self, low: float, high: float, now_s: float) -> Optional[Tuple[float, float, float]]:
        """(low, high, duration_s) for a pad's two motors to send now, or None: the same rule per motor."""
        values = (unit_intensity(low), unit_intensity(high))
        on = max(values) > 0.0
        switched = on != (max(self._sent) > 0.0)
        changed = any(abs(v - s) >= self.policy.change for v, s in zip(values, self._sent))
        refresh = on and now_s - self._sent_at >= self.policy.refresh_s
        if not (switched or changed or refresh):
            return None
        self._sent, self._sent_at = values, now_s
        return values[0], values[1], (self.policy.hold_s if on else 0.0)


#: The start check (teleoperation's ~rumble_check_level, ~rumble_check_s): a short rumble of both motors,
#: strength 0..1 and length s, that an operator notices as "the pad works" and a refusal shows at once.
RUMBLE_CHECK_LEVEL = 0.5
RUMBLE_CHECK_S = 0.2


def rumble_refused(pad_name: str, why: str) -> str:
    """One line for a pad that refused the start check: which pad, why, and what to do."""
    return (f"gamepad {pad_name!r} refuses rumble ({why}): no force feedback with it; connect the pad with a USB "
            "cable (some Bluetooth links carry no rumble), check that its kernel driver supports force feedback "
            "and that /dev/input/event* is writable (`ls -l /dev/input/`), or use another pad")
