"""Gamepads for the teleoperation lab: positional names, layouts, dead zone, two backends.

Everything downstream sees a :class:`PadState` with positional button names
(south/east/west/north = cross/circle/square/triangle on PlayStation, A/B/X/Y on Xbox)
and sticks that read +1 right/up. Raw indices live in ``layouts/*.yaml`` only.

Backends (one interface, :class:`Gamepad`): :class:`PygamePad` for a real pad (pygame is
imported only when one is opened) and :class:`VirtualPad` / :class:`ScriptedPad` for
home, tests and the grader. Check a real pad with ``python -m hri_teleop.gamepad``.
"""

from __future__ import annotations

from .deadzone import check_deadzone, normalize_analog_input
from .factory import PAD_KINDS, open_gamepad
from .interface import Gamepad
from .layout import DEFAULT_LAYOUT, LAYOUT_DIR, AxisMap, Layout, available_layouts, layout_from_dict, load_layout
from .pygame_pad import NO_GAMEPAD_MESSAGE, PygamePad
from .rumble import RumblePolicy, RumbleRequests
from .state import AXES, BUTTON_LABELS, BUTTONS, STICK_AXES, TRIGGER_AXES, GamepadError, PadState
from .virtual import (
                     RUMBLE_LOG_HEADER,
                     RumbleRecord,
                     ScriptedPad,
                     ScriptStep,
                     VirtualPad,
                     load_script,
                     parse_script,
                     read_rumble_log,
                     rumble_log_line,
)

__all__ = [
    "AXES", "BUTTONS", "STICK_AXES", "TRIGGER_AXES", "BUTTON_LABELS",
    "GamepadError", "PadState", "Gamepad",
    "AxisMap", "Layout", "load_layout", "layout_from_dict", "available_layouts",
    "DEFAULT_LAYOUT", "LAYOUT_DIR",
    "normalize_analog_input", "check_deadzone",
    "VirtualPad", "ScriptedPad", "ScriptStep", "RumbleRecord", "load_script", "parse_script",
    "RUMBLE_LOG_HEADER", "rumble_log_line", "read_rumble_log",
    "PygamePad", "NO_GAMEPAD_MESSAGE",
    "open_gamepad", "PAD_KINDS",
    "RumblePolicy", "RumbleRequests",
]
