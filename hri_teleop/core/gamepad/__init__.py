"""Gamepads as the lab's rules see them: positional names, layouts, the dead zone, rumble.

Everything downstream sees a :class:`PadState` with positional button names
(south/east/west/north = cross/circle/square/triangle on PlayStation, A/B/X/Y on Xbox)
and sticks that read +1 right/up. Raw indices live in ``layouts/*.yaml`` only. The pads
themselves: pygame and browser in :mod:`hri_teleop.hardware`, virtual and scripted in :mod:`hri_teleop.sim`.
"""

from __future__ import annotations

from hri_teleop.core.gamepad.deadzone import check_deadzone, normalize_analog_input
from hri_teleop.core.gamepad.interface import PAD_KINDS, Gamepad
from hri_teleop.core.gamepad.layout import (
    AUTO_LAYOUT,
    DEFAULT_LAYOUT,
    LAYOUT_DIR,
    AxisMap,
    Layout,
    available_layouts,
    layout_from_dict,
    load_layout,
)
from hri_teleop.core.gamepad.rumble import RumblePolicy, RumbleRequests
from hri_teleop.core.gamepad.state import (
    AXES,
    BUTTON_LABELS,
    BUTTONS,
    STICK_AXES,
    TRIGGER_AXES,
    GamepadError,
    PadState,
)

__all__ = [
    "AXES", "BUTTONS", "STICK_AXES", "TRIGGER_AXES", "BUTTON_LABELS",
    "GamepadError", "PadState", "Gamepad", "PAD_KINDS",
    "AxisMap", "Layout", "load_layout", "layout_from_dict", "available_layouts",
    "DEFAULT_LAYOUT", "AUTO_LAYOUT", "LAYOUT_DIR",
    "normalize_analog_input", "check_deadzone",
    "RumblePolicy", "RumbleRequests",
]
