"""What a pad is to the teleoperation node: the :class:`Gamepad` protocol every backend follows.

Apart from :mod:`.state` because it names a :class:`~.layout.Layout`, and layouts are built
from the state's axis and button names.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from hri_teleop.core.gamepad.layout import Layout
from hri_teleop.core.gamepad.state import PadState

__all__ = ["Gamepad", "PAD_KINDS"]

#: The pad kinds a configuration may name: a real pad through pygame, or the virtual one.
PAD_KINDS = ("pygame", "virtual")


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
