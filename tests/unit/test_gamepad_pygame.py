"""PygamePad: the real-pad backend, tested headless (SDL dummy drivers) and with stand-in devices.

There is no pad on the test machine, so real pygame only shows the no-gamepad error; the
reading, rumble and hot-plug logic is driven through an injected joystick / pygame module.
"""

from __future__ import annotations

import os
import subprocess
import sys
from types import SimpleNamespace
from typing import List

import pytest

from hri_teleop.core.gamepad import Gamepad, GamepadError, PadState
from hri_teleop.hardware.gamepad import open_gamepad
from hri_teleop.hardware.real.pygame_pad import NO_GAMEPAD_MESSAGE, PygamePad

HEADLESS = dict(os.environ, SDL_VIDEODRIVER="dummy", SDL_AUDIODRIVER="dummy",
                PYGAME_HIDE_SUPPORT_PROMPT="1")


class PygameError(RuntimeError):
    """Stands in for pygame.error (a RuntimeError subclass)."""


class FakeJoystick:
    """Just the pygame.joystick.Joystick methods PygamePad uses."""

    def __init__(self, name: str = "Sony Interactive Entertainment Wireless Controller",
                 axes: int = 6, buttons: int = 13, instance_id: int = 0, rumble_ok: bool = True):
        self.name = name
        self.axes = [0.0] * axes
        self.buttons = [0] * buttons
        if axes >= 6:
            self.axes[2] = self.axes[5] = -1.0  # triggers at rest
        self.instance_id = instance_id
        self.rumble_ok = rumble_ok
        self.rumble_calls: List[tuple] = []
        self.stops = 0
        self.quits = 0
        self.broken = False

    def init(self) -> None:
        pass

    def quit(self) -> None:
        self.quits += 1

    def get_name(self) -> str:
        return self.name

    def get_instance_id(self) -> int:
        return self.instance_id

    def get_numaxes(self) -> int:
        return len(self.axes)

    def get_numbuttons(self) -> int:
        return len(self.buttons)

    def get_axis(self, i: int) -> float:
        if self.broken:
            raise PygameError("Joystick not initialized")
        return self.axes[i]

    def get_button(self, i: int) -> int:
        return self.buttons[i]

    def rumble(self, low: float, high: float, duration_ms: int) -> bool:
        self.rumble_calls.append((low, high, duration_ms))
        return self.rumble_ok

    def stop_rumble(self) -> None:
        self.stops += 1


class FakePygame:
    """The slice of the pygame module PygamePad touches: event queue and joystick module."""

    JOYDEVICEADDED = 1541
    JOYDEVICEREMOVED = 1542
    error = PygameError

    def __init__(self, *devices: FakeJoystick):
        self.devices = list(devices)
        self.queue: list = [SimpleNamespace(type=self.JOYDEVICEADDED, device_index=i)
                            for i in range(len(devices))]  # SDL announces present pads first
        self.event = SimpleNamespace(get=self._get)
        self.joystick = SimpleNamespace(get_count=lambda: len(self.devices), Joystick=self._open)

    def _get(self) -> list:
        events, self.queue = self.queue, []
        return events

    def _open(self, index: int) -> FakeJoystick:
        if not 0 <= index < len(self.devices):
            raise PygameError("Invalid joystick device number")
        return self.devices[index]

    def unplug(self, device: FakeJoystick) -> None:
        self.devices.remove(device)
        self.queue.append(SimpleNamespace(type=self.JOYDEVICEREMOVED, instance_id=device.instance_id))

    def plug(self, device: FakeJoystick) -> None:
        self.devices.append(device)
        self.queue.append(SimpleNamespace(type=self.JOYDEVICEADDED, device_index=len(self.devices) - 1))


# ------------------------------------------------------------------ real pygame, no pad

def test_no_gamepad_is_one_line_with_the_fix():
    with pytest.raises(GamepadError) as info:
        PygamePad("dualshock4")
    assert str(info.value) == NO_GAMEPAD_MESSAGE
    assert "\n" not in NO_GAMEPAD_MESSAGE
    assert "ls /dev/input/js*" in NO_GAMEPAD_MESSAGE and "pad:=virtual" in NO_GAMEPAD_MESSAGE
    assert os.environ.get("SDL_JOYSTICK_HIDAPI") == "0"  # kernel-driver order, see layouts/


def test_open_gamepad_pygame_without_a_pad():
    with pytest.raises(GamepadError, match="^no gamepad found"):
        open_gamepad("pygame", "xbox")


def test_opening_a_virtual_pad_does_not_import_pygame():
    code = ("import sys, hri_teleop.hardware.gamepad as g; g.open_gamepad('virtual').poll(); "
            "print('pygame' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=HEADLESS,
                         check=True)
    assert out.stdout.strip() == "False"


def test_checker_cli_lists_layouts_and_reports_no_pad():
    listed = subprocess.run([sys.executable, "-m", "hri_teleop.apps.pad_check", "--list"],
                            capture_output=True, text=True, env=HEADLESS)
    assert listed.returncode == 0 and "dualshock4" in listed.stdout and "xbox" in listed.stdout
    run = subprocess.run([sys.executable, "-m", "hri_teleop.apps.pad_check", "--seconds", "0.1"],
                         capture_output=True, text=True, env=HEADLESS)
    assert run.returncode == 1
    assert run.stderr.strip().splitlines()[-1] == "error: " + NO_GAMEPAD_MESSAGE


# ------------------------------------------------------------------ injected device

def test_reads_the_device_through_the_layout():
    js = FakeJoystick()
    pad = PygamePad("dualshock4", joystick=js)
    assert isinstance(pad, Gamepad)
    assert pad.name == js.name and pad.layout.name == "dualshock4" and pad.connected
    assert pad.poll() == PadState.neutral()
    js.axes[:6] = [0.5, -0.8, 1.0, -0.25, 0.4, -1.0]   # raw SDL: stick up is negative
    js.buttons[2] = 1                                   # triangle on a DS4
    state = pad.poll()
    assert state.axis("left_x") == 0.5 and state.axis("left_y") == 0.8
    assert state.axis("right_x") == -0.25 and state.axis("right_y") == -0.4
    assert state.axis("l2") == 1.0 and state.axis("r2") == 0.0
    assert state.pressed("north") and not state.pressed("west")
    assert pad.read_raw() == (js.axes, js.buttons)


def test_same_position_on_an_xbox_pad():
    js = FakeJoystick("Microsoft X-Box 360 pad", buttons=11)
    js.buttons[2] = 1  # X, the west button on Xbox
    assert PygamePad("xbox", joystick=js).poll().pressed("west")


def test_pad_with_too_few_inputs_for_the_layout():
    js = FakeJoystick("Generic USB Joystick", axes=4, buttons=12)
    with pytest.raises(GamepadError) as info:
        PygamePad("dualshock4", joystick=js)
    message = str(info.value)
    assert "\n" not in message
    assert "4 axes and 12 buttons" in message and "'dualshock4' needs at least 6 and 13" in message
    assert "xbox" in message  # lists the layouts to choose from
    assert PygamePad("dualshock4", joystick=js, check_layout=False).poll().connected
    opened = FakeJoystick("Generic USB Joystick", axes=4, buttons=12)
    with pytest.raises(GamepadError):
        PygamePad("dualshock4", pygame_module=FakePygame(opened))
    assert opened.quits == 1  # a device we opened is released again


def test_rumble_goes_to_both_motors_in_milliseconds():
    js = FakeJoystick()
    pad = PygamePad(joystick=js)
    pad.rumble(0.5, 0.25)
    pad.rumble(2.0, 0.0)       # clipped; 0 s = until the next call (pygame: 0 ms)
    pad.rumble(0.3, 0.0001)    # never rounds down to pygame's "forever"
    assert js.rumble_calls == [(0.5, 0.5, 250), (1.0, 1.0, 0), (0.3, 0.3, 1)]
    pad.rumble(0.0, 0.1)
    assert js.stops == 1 and len(js.rumble_calls) == 3


def test_rumble_unsupported_warns_once_and_keeps_going():
    messages: List[str] = []
    js = FakeJoystick(rumble_ok=False)
    pad = PygamePad(joystick=js, log=messages.append)
    for _ in range(5):
        pad.rumble(0.8, 0.1)
    assert len(messages) == 1 and "does not accept rumble" in messages[0]
    assert "\n" not in messages[0]
    assert pad.poll().connected


def test_rumble_raising_is_caught():
    messages: List[str] = []
    js = FakeJoystick()
    js.rumble = lambda *a: (_ for _ in ()).throw(PygameError("Joystick not initialized"))  # type: ignore
    pad = PygamePad(joystick=js, log=messages.append)
    pad.rumble(0.5, 0.1)
    pad.rumble(0.5, 0.1)
    assert len(messages) == 1


def test_unplug_and_replug():
    messages: List[str] = []
    first = FakeJoystick(instance_id=0)
    pg = FakePygame(first)
    pad = PygamePad("dualshock4", pygame_module=pg, log=messages.append)
    first.buttons[0] = 1
    assert pad.poll().pressed("south") and pad.connected

    pg.unplug(first)
    lost = pad.poll()
    assert lost == PadState.neutral(connected=False) and not pad.connected
    assert first.quits == 1 and "disconnected" in messages[-1]
    pad.rumble(0.5, 0.1)                      # nothing to rumble: no error
    assert pad.poll().connected is False      # stays lost until a pad comes back

    again = FakeJoystick(instance_id=1)       # SDL gives a replugged pad a new instance id
    again.axes[1] = -1.0
    pg.plug(again)
    state = pad.poll()
    assert state.connected and state.axis("left_y") == 1.0
    assert "connected again" in messages[-1]
    pg.unplug(again)
    assert not pad.poll().connected


def test_other_devices_coming_and_going_do_not_matter():
    pad_js, other = FakeJoystick(instance_id=0), FakeJoystick("Other", instance_id=7)
    pg = FakePygame(pad_js, other)
    pad = PygamePad(pygame_module=pg)
    pg.unplug(other)
    pg.plug(FakeJoystick("Third", instance_id=8))
    assert pad.poll().connected and pad.name == pad_js.name


def test_replugged_pad_that_does_not_fit_the_layout_is_ignored():
    messages: List[str] = []
    first = FakeJoystick(instance_id=0)
    pg = FakePygame(first)
    pad = PygamePad(pygame_module=pg, log=messages.append)
    pg.unplug(first)
    pad.poll()
    wrong = FakeJoystick("Tiny pad", axes=2, buttons=4, instance_id=3)
    pg.plug(wrong)
    assert not pad.poll().connected
    assert "ignoring the gamepad" in messages[-1] and wrong.quits == 1


def test_read_failure_counts_as_unplugged():
    js = FakeJoystick()
    pad = PygamePad(pygame_module=FakePygame(js), log=lambda m: None)
    js.broken = True
    assert pad.poll().connected is False


@pytest.mark.parametrize("index", [1, -1, "0"])
def test_index_out_of_range(index):
    pg = FakePygame(FakeJoystick())
    with pytest.raises(GamepadError) as info:
        PygamePad(index=index, pygame_module=pg)
    assert "1 gamepad connected" in str(info.value) and "from 0 to 0" in str(info.value)


def test_device_that_cannot_be_opened():
    pg = FakePygame(FakeJoystick())
    pg.joystick.Joystick = lambda i: (_ for _ in ()).throw(PygameError("Permission denied"))
    with pytest.raises(GamepadError, match="cannot open gamepad 0 .Permission denied.: check"):
        PygamePad(pygame_module=pg)


def test_close_is_idempotent():
    js = FakeJoystick()
    with PygamePad(joystick=js) as pad:
        pass
    pad.close()
    assert js.stops == 1 and js.quits == 1
    assert pad.poll() == PadState.neutral(connected=False)
    pad.rumble(1.0, 0.1)
    assert js.rumble_calls == []
