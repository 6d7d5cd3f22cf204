"""What a pad is to the teleoperation node: the :class:`Gamepad` protocol every backend follows.

Apart from :mod:`.state` because it names a :class:`~.layout.Layout`, and layouts are built
from the state's axis and button names.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from .layout import Layout
from .state import PadState

__all__ = ["Gamepad"]


@runtime_checkable
class Gamepad(Protocol):
    """What the teleoperation node needs from a pad, real or virtual."""

    name: str

    @property
    def layout(self) -> Layout:
        ...

    def poll(self) -> PadState:
        """Read the pad now; never blocks, never raises for an unplugged pad (connected=False)."""
        ...

    def rumble(self, intensity: float, duration_s: float) -> None:
        """Vibrate at intensity 0..1 for duration_s seconds (0 s: until the next call); 0 stops."""
        ...

    def close(self) -> None:
        """Release the device; safe to call twice."""
        ...
