"""A real gamepad through pygame 2 / SDL2, with hot-plugging and rumble.

pygame is imported only when a PygamePad is created, so everything else runs without it.
``SDL_JOYSTICK_HIDAPI=0`` (unless set) makes SDL read PlayStation pads through the kernel driver,
whose raw order ``layouts/`` describe. No window is opened (``dummy`` video driver without a
display). ``poll`` never raises for a pad that went away: it reports ``connected=False`` (the
controller ramps to a stop) and reopens the pad when it is plugged in again. A pad that cannot
rumble logs one warning and keeps working.
"""

from __future__ import annotations

import logging
import os
from typing import Any, Callable, List, Optional, Sequence, Tuple, Union

from hri_teleop.core.checks import is_int
from hri_teleop.core.gamepad.identify import identify_layout
from hri_teleop.core.gamepad.layout import AUTO_LAYOUT, DEFAULT_LAYOUT, Layout, as_layout, available_layouts
from hri_teleop.core.gamepad.state import GamepadError, PadState, clean_duration, clean_intensity

__all__ = ["PygamePad", "NO_GAMEPAD_MESSAGE", "SDL_DEFAULTS", "import_pygame"]

_log = logging.getLogger("hri_teleop.hardware.real.pygame_pad")

NO_GAMEPAD_MESSAGE = ("no gamepad found: plug in a gamepad (check `ls /dev/input/js*`) "
                      "or start with the virtual pad (pad:=virtual in roslaunch, _pad:=virtual in rosrun)")

#: Environment defaults set (only where unset) before pygame/SDL initialises.
SDL_DEFAULTS = (
    ("SDL_JOYSTICK_HIDAPI", "0"),                   # kernel-driver button order, see layouts/
    ("SDL_JOYSTICK_ALLOW_BACKGROUND_EVENTS", "1"),  # read the pad even if a window lacks focus
    ("PYGAME_HIDE_SUPPORT_PROMPT", "1"),            # no banner in the ROS log
)

Raw = Tuple[List[float], List[int]]


def import_pygame() -> Any:
    """Import and initialise pygame's display (event queue) and joystick modules, headless-safe."""
    for key, value in SDL_DEFAULTS:
        os.environ.setdefault(key, value)
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        # No screen at all (ssh, CI): go straight to the dummy driver; trying X11/Wayland
        # first only makes SDL print a stray "XDG_RUNTIME_DIR is invalid" line.
        os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    try:
        import pygame  # noqa: PLC0415 - deliberately lazy: only real pads need pygame
    except ImportError:
        raise GamepadError("pygame is not installed: run `make setup` (or `pip install 'pygame>=2.1'`), "
                           "or start with the virtual pad (pad:=virtual in roslaunch, _pad:=virtual in rosrun)") from None
    try:
        if not pygame.display.get_init():
            try:
                pygame.display.init()
            except pygame.error:
                # No display (ssh, CI): the event queue needs *a* video driver, not a screen.
                os.environ["SDL_VIDEODRIVER"] = "dummy"
                pygame.display.init()
        pygame.joystick.init()
    except pygame.error as exc:
        raise GamepadError("SDL could not start its event queue (%s): unset SDL_VIDEODRIVER or set "
                           "it to dummy, or start with the virtual pad (pad:=virtual in roslaunch, _pad:=virtual in rosrun)" % exc) from None
    return pygame


def _quietly(joystick: Any, method: str) -> None:
    """Call a cleanup method that may fail on a device that is already gone."""
    try:
        getattr(joystick, method)()
    except (RuntimeError, AttributeError):
        pass


def _instance_id(joystick: Any) -> Any:
    getter = getattr(joystick, "get_instance_id", None) or getattr(joystick, "get_id", None)
    return getter() if getter is not None else id(joystick)


class PygamePad:
    """A physical pad read with pygame; implements the Gamepad protocol.

    ``joystick`` and ``pygame_module`` exist for tests: any object with pygame's Joystick
    methods (get_numaxes, get_axis, get_numbuttons, get_button, rumble, stop_rumble,
    get_name) can stand in for the device, and a stand-in module for pygame's event queue
    and joystick module. Raw values become a PadState through the layout only.
    ``check_layout=False`` accepts a pad with fewer axes/buttons than the layout maps
    (the missing ones read as at rest): for inspecting an unknown pad. Layout ``auto``
    identifies the pad (core.gamepad.identify; again when another pad is plugged in) and
    falls back to the default layout with one log line; ``layout_reason`` says which it was.
    """

    #: A hand on a real pad always trembles: identical held readings mean a frozen link (core.gamepad.stale).
    stale_input_watch = True

    def __init__(self, layout: Union[Layout, str, None] = None, index: int = 0, *,
                 pygame_module: Any = None, joystick: Any = None,
                 log: Optional[Callable[[str], None]] = None, check_layout: bool = True) -> None:
        self._auto = isinstance(layout, str) and layout.strip() == AUTO_LAYOUT
        self._layout = as_layout(layout)
        self.layout_reason = "set by the configuration"
        self._log = log if log is not None else _log.warning
        self._rumble_warned = False
        self._closed = False
        if joystick is None:
            self._pg = pygame_module if pygame_module is not None else import_pygame()
            joystick = self._open(index)
        else:
            self._pg = pygame_module  # may be None: an injected device, nothing to pump
        self._check_layout = check_layout
        self._identify(joystick)
        problem = self._mismatch(joystick)
        if problem:
            if self._pg is not None:  # we opened it: release it again
                _quietly(joystick, "quit")
            raise GamepadError(problem)
        self._js: Optional[Any] = joystick
        self._instance = _instance_id(joystick)
        self.name: str = str(getattr(joystick, "get_name", lambda: "gamepad")())
        self.index = index

    # -- opening -------------------------------------------------------------------------
    def _open(self, index: int) -> Any:
        pg = self._pg
        count = pg.joystick.get_count()
        if count == 0:
            raise GamepadError(NO_GAMEPAD_MESSAGE)
        if not is_int(index) or not 0 <= index < count:
            raise GamepadError("gamepad index %r not found: %d gamepad%s connected; set the pad "
                               "index to a number from 0 to %d" % (index, count, "" if count == 1 else "s",
                                                                   count - 1))
        try:
            joystick = pg.joystick.Joystick(index)
            joystick.init()
        except RuntimeError as exc:  # pygame.error
            raise GamepadError("cannot open gamepad %d (%s): check read/write access to "
                               "/dev/input/event* (`ls -l /dev/input/`) or start with the virtual pad (pad:=virtual in roslaunch, _pad:=virtual in rosrun)"
                               % (index, exc)) from None
        return joystick

    def _identify(self, joystick: Any) -> None:
        """With layout auto: the layout this device's GUID/name says, or the default and one log line."""
        if not self._auto:
            return
        name = str(getattr(joystick, "get_name", lambda: "gamepad")())
        guid = str(joystick.get_guid()) if hasattr(joystick, "get_guid") else ""
        guess = identify_layout(guid, name, joystick.get_numaxes(), joystick.get_numbuttons())
        if guess.layout is not None:
            self._layout, self.layout_reason = as_layout(guess.layout), "auto: " + guess.reason
            return
        self._layout = as_layout(DEFAULT_LAYOUT)
        self.layout_reason = "auto: not identified, the default"
        self._log("gamepad %r (GUID %s) has no known layout: %s; using layout %s. If its buttons or sticks do "
                  "the wrong thing, set layout:= one of %s (check it with `python -m hri_teleop.apps."
                  "pad_check --layout NAME`)" % (name, guid or "?", guess.reason, DEFAULT_LAYOUT,
                                                 ", ".join(available_layouts())))

    def _mismatch(self, joystick: Any) -> str:
        """Why this device cannot be read with the layout, or '' if it can."""
        axes, buttons = joystick.get_numaxes(), joystick.get_numbuttons()
        if not self._check_layout or axes >= self._layout.num_axes and buttons >= self._layout.num_buttons:
            return ""
        name = getattr(joystick, "get_name", lambda: "gamepad")()
        return ("gamepad %r has %d axes and %d buttons but layout %r needs at least %d and %d: "
                "set layout to the one for this pad (%s; `python -m hri_teleop.apps.pad_check` shows "
                "raw input)" % (name, axes, buttons, self._layout.name, self._layout.num_axes,
                                self._layout.num_buttons, ", ".join(available_layouts())))

    # -- Gamepad protocol ------------------------------------------------------------
    @property
    def layout(self) -> Layout:
        return self._layout

    @property
    def connected(self) -> bool:
        return self._js is not None and not self._closed

    def read_raw(self) -> Optional[Raw]:
        """Pump events and read every raw axis and button in SDL's order; None if disconnected."""
        if self._closed:
            return None
        if self._pg is not None:
            self._handle_events(self._pg.event.get())
        joystick = self._js
        if joystick is None:
            return None
        try:
            axes = [float(joystick.get_axis(i)) for i in range(joystick.get_numaxes())]
            buttons = [int(bool(joystick.get_button(i))) for i in range(joystick.get_numbuttons())]
        except RuntimeError as exc:  # pygame.error: the device vanished between two events
            self._lost("read failed: %s" % exc)
            return None
        return axes, buttons

    def poll(self) -> PadState:
        raw = self.read_raw()
        if raw is None:
            return PadState.neutral(connected=False)
        return self._layout.state_from_raw(raw[0], raw[1], connected=True)

    def rumble(self, intensity: float, duration_s: float) -> None:
        """Both motors at ``intensity`` (0..1) for ``duration_s`` (0: until the next call); 0 stops."""
        self.rumble_motors(intensity, intensity, duration_s)

    def rumble_motors(self, low: float, high: float, duration_s: float) -> None:
        """The low-frequency (strong, left) and high-frequency (weak, right) motors apart; both 0 stops."""
        played, _why = self._play(clean_intensity(low), clean_intensity(high), clean_duration(duration_s))
        if not played and not self._rumble_warned:
            self._rumble_warned = True
            self._log("gamepad %r does not accept rumble; force feedback is off: check that the kernel "
                      "driver supports force feedback and that /dev/input/event* is writable"
                      % self.name)

    def check_rumble(self, level: float, duration_s: float) -> Tuple[bool, str]:
        """Rumble both motors briefly now: (accepted, why not). A refusal is then not warned again."""
        played, why = self._play(clean_intensity(level), clean_intensity(level), clean_duration(duration_s))
        self._rumble_warned = self._rumble_warned or not played
        return played, why

    def _play(self, low: float, high: float, duration: float) -> Tuple[bool, str]:
        joystick = self._js
        if joystick is None or self._closed:
            return True, ""  # nothing to play on: not a refusal
        try:
            if low == 0.0 and high == 0.0:
                joystick.stop_rumble()
                return True, ""
            duration_ms = 0 if duration == 0.0 else max(1, int(round(duration * 1000.0)))
            if bool(joystick.rumble(low, high, duration_ms)):
                return True, ""
            return False, "SDL reports no rumble for this pad and driver"
        except AttributeError:
            return False, "this pygame has no rumble (pygame >= 2.0.2 with SDL >= 2.0.9 has)"
        except RuntimeError as exc:  # pygame.error
            return False, "SDL: %s" % exc

    def close(self) -> None:
        if self._closed:
            return
        joystick, self._js = self._js, None
        self._closed = True
        if joystick is not None:
            _quietly(joystick, "stop_rumble")
            _quietly(joystick, "quit")

    def __enter__(self) -> "PygamePad":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- hot-plugging --------------------------------------------------------------------
    def _handle_events(self, events: Sequence[Any]) -> None:
        pg = self._pg
        removed = getattr(pg, "JOYDEVICEREMOVED", None)
        added = getattr(pg, "JOYDEVICEADDED", None)
        for event in events:
            kind = getattr(event, "type", None)
            if kind is None:
                continue
            if kind == removed and self._js is not None and getattr(event, "instance_id", None) == self._instance:
                self._lost("unplugged")
            elif kind == added and self._js is None:
                self._reopen(getattr(event, "device_index", 0))

    def _lost(self, why: str) -> None:
        joystick, self._js = self._js, None
        if joystick is not None:
            _quietly(joystick, "quit")
        self._log("gamepad %r disconnected (%s): the robot is brought to a stop; plug the pad in "
                  "again to continue" % (self.name, why))

    def _reopen(self, device_index: int) -> None:
        pg = self._pg
        try:
            joystick = pg.joystick.Joystick(device_index)
            joystick.init()
        except RuntimeError as exc:
            self._log("a gamepad was plugged in but cannot be opened (%s)" % exc)
            return
        self._identify(joystick)
        problem = self._mismatch(joystick)
        if problem:
            self._log("ignoring the gamepad just plugged in: " + problem)
            _quietly(joystick, "quit")
            return
        self._js = joystick
        self._instance = _instance_id(joystick)
        self.name = str(getattr(joystick, "get_name", lambda: self.name)())
        self._log("gamepad %r connected again" % self.name)
