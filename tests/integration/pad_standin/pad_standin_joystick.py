"""A PS4-like pad for pygame that follows a pad script: the person at a real pad, played in a node's process.

There is no pad and no /dev/uinput on a test machine, so a node started with ``pad:=pygame`` would
only find no gamepad. With this folder first on its PYTHONPATH and ``HRI_PAD_STANDIN_SCRIPT`` naming
a pad script (the virtual pad's step format: ``{t: 0.5, axis: left_y, value: 1.0}``, ``press``,
``release``, ``tap``, ``when: rumble``; time from the first read), ``sitecustomize`` calls
:func:`install`: ``pygame.joystick`` reports one DualShock 4 (its SDL GUID, name, 6 axes, 13 buttons,
rumble) whose readings follow the script. Everything else is the node's real pygame code path.
A held stick trembles by one float step every other read, as a hand on a real pad does (the node's
stale-input watch would otherwise take a stick held perfectly still for a frozen link).
``HRI_PAD_STANDIN_LOG`` (optional) names a file that gets one line per read and per rumble.
"""

from __future__ import annotations

import os
import time
from typing import Optional, TextIO

import numpy

SCRIPT_ENV = "HRI_PAD_STANDIN_SCRIPT"
LOG_ENV = "HRI_PAD_STANDIN_LOG"
#: What SDL reports for a wired DualShock 4 (second model) under the kernel's hid-sony/hid-playstation driver.
NAME = "Sony Interactive Entertainment Wireless Controller"
GUID = "030000004c050000cc09000011810000"
LAYOUT = "dualshock4"
STICKS = ("left_x", "left_y", "right_x", "right_y")


class StandinJoystick:
    """pygame.joystick.Joystick's methods, reading a ScriptedPad through the DualShock 4 layout."""

    def __init__(self, script: str, log_path: Optional[str] = None) -> None:
        from hri_teleop.core.gamepad.layout import as_layout
        from hri_teleop.core.gamepad.state import PadState
        from hri_teleop.sim.virtual_pad import ScriptedPad

        self._layout = as_layout(LAYOUT)
        self._pad = ScriptedPad(script, self._layout, name=NAME, clock=time.monotonic)
        self._sticks = [self._layout.axes[name][0] for name in STICKS]
        self._axes, self._buttons = self._layout.raw_from_state(PadState.neutral())  # the script starts at the first read
        self._reads = 0
        self._log: Optional[TextIO] = open(log_path, "a", buffering=1) if log_path else None

    def _refresh(self) -> None:
        state = self._pad.poll()
        axes, buttons = self._layout.raw_from_state(state)
        self._reads += 1
        if self._reads % 2 == 0:
            for index in self._sticks:
                if axes[index] != 0.0:
                    axes[index] = float(numpy.nextafter(axes[index], 0.0))
        self._axes, self._buttons = axes, buttons
        if self._log is not None:
            self._log.write(f"{time.monotonic():.6f} read {' '.join(f'{a:.6f}' for a in axes)} "
                            f"{''.join(str(b) for b in buttons)}\n")

    # -- pygame.joystick.Joystick ------------------------------------------------------------
    def init(self) -> None:
        pass

    def quit(self) -> None:
        pass

    def get_init(self) -> bool:
        return True

    def get_id(self) -> int:
        return 0

    def get_instance_id(self) -> int:
        return 0

    def get_guid(self) -> str:
        return GUID

    def get_name(self) -> str:
        return NAME

    def get_power_level(self) -> str:
        return "wired"

    def get_numaxes(self) -> int:
        return len(self._axes)

    def get_axis(self, index: int) -> float:
        if index == 0:  # PygamePad reads every axis in order, then the buttons: one read begins here
            self._refresh()
        return self._axes[index]

    def get_numbuttons(self) -> int:
        return len(self._buttons)

    def get_button(self, index: int) -> int:
        return self._buttons[index]

    def get_numhats(self) -> int:
        return 1

    def get_hat(self, _index: int) -> tuple:
        return (0, 0)

    def get_numballs(self) -> int:
        return 0

    def rumble(self, low: float, high: float, duration_ms: int) -> bool:
        self._pad.rumble_motors(low, high, duration_ms / 1000.0)
        if self._log is not None:
            self._log.write(f"{time.monotonic():.6f} rumble {low:.6f} {high:.6f} {duration_ms}\n")
        return True

    def stop_rumble(self) -> None:
        self._pad.rumble_motors(0.0, 0.0, 0.0)


def install() -> None:
    """Make pygame.joystick report the one stand-in pad (called by sitecustomize at interpreter start)."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame
    import pygame.joystick

    device = StandinJoystick(os.environ[SCRIPT_ENV], os.environ.get(LOG_ENV) or None)

    def joystick(index: int) -> StandinJoystick:
        if index != 0:
            raise pygame.error("Invalid joystick device number")
        return device

    pygame.joystick.get_count = lambda: 1
    pygame.joystick.Joystick = joystick
