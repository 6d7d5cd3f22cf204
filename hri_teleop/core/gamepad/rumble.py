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

from hri_teleop.core.gamepad.state import GamepadError


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
        self._sent = 0.0
        self._sent_at = -math.inf

    def update(self, intensity: float, now_s: float) -> Optional[Tuple[float, float]]:
        """(intensity, duration_s) to send now, or None to send nothing."""
        value = min(1.0, max(0.0, float(intensity))) if math.isfinite(intensity) else 0.0
        switched = (value == 0.0) != (self._sent == 0.0)
        changed = abs(value - self._sent) >= self.policy.change
        refresh = value > 0.0 and now_s - self._sent_at >= self.policy.refresh_s
        if not (switched or changed or refresh):
            return None
        self._sent, self._sent_at = value, now_s
        return value, (self.policy.hold_s if value > 0.0 else 0.0)
