"""A pad read by a web browser: the W3C standard gamepad as positional names, and how old a reading is.

The browser's Gamepad API numbers buttons and axes by the W3C "standard" mapping, which is not any
layout of ``layouts/`` (those are pygame's raw indices); :func:`state_from_standard` is the one
place that turns it into a :class:`~.state.PadState`. A browser's clock is not the kernel's, and a
kernel busy with a cell receives a queue of old readings at once: :class:`BrowserClock` tells a
fresh reading from a replayed one; :class:`BrowserInput` gives the state to send at each moment,
neutral once the page falls silent. The widget is ``hri_teleop.course.widgets.BrowserPad``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional, Sequence, Tuple

from hri_teleop.core.checks import is_finite_number, is_number
from hri_teleop.core.gamepad.state import GamepadError, PadState
from hri_teleop.core.limits import Watchdog

__all__ = ["STANDARD_BUTTONS", "STANDARD_AXES", "STANDARD_TRIGGERS", "BrowserReading", "state_from_standard",
           "read_browser_pad", "BrowserClock", "MAX_AGE_S", "HEARTBEAT_TIMEOUT_S", "BrowserInput"]

#: The W3C standard gamepad's buttons by index (https://w3c.github.io/gamepad/#remapping) as
#: positional names; None: not used by the lab (12-15 the d-pad, which PadState has no names for).
STANDARD_BUTTONS: Tuple[Optional[str], ...] = (
    "south", "east", "west", "north",   # 0-3 bottom, right, left, top face button
    "l1", "r1", "l2", "r2",             # 4-7 front left/right top, front left/right bottom (triggers)
    "select", "start",                  # 8-9 left, right button of the centre cluster
    "l3", "r3",                         # 10-11 left, right stick pressed
    None, None, None, None,             # 12-15 d-pad up, down, left, right
    "mode",                             # 16 centre button (PS, Xbox guide)
)
#: The standard axes by index: (name, inverted). The browser reads up as -1; the lab reads up as +1.
STANDARD_AXES: Tuple[Tuple[str, bool], ...] = (("left_x", False), ("left_y", True), ("right_x", False),
                                              ("right_y", True))
#: The analog triggers are buttons 6 and 7 in the standard mapping: their value (0..1) is the axis.
STANDARD_TRIGGERS: Tuple[Tuple[str, int], ...] = (("l2", 6), ("r2", 7))
#: A reading whose delay exceeds the link's usual delay by more than this is old, s (the node's
#: input timeout is 0.5 s; a LAN or Wi-Fi link delays readings by a few to some tens of ms).
MAX_AGE_S = 0.25
#: No usable reading for longer than this and the pad reads released, s: the page sends 25 a
#: second, so this is several lost messages in a row (a busy kernel, a closed tab, a dead link),
#: and it is below the node's input_timeout (0.5 s), so the robot stops because of the page, not later.
HEARTBEAT_TIMEOUT_S = 0.3

_HIDDEN = ("the browser tab with the gamepad is hidden (the browser gives a pad only to the visible tab): bring "
           "the notebook's tab to the front")
_NO_PAD = ("no gamepad in this browser: plug one in and press a button on it (a browser shows a pad only after "
           "a button press, with its tab visible)")


def _finite(value: Any, low: float, high: float) -> float:
    """value as a float clipped to [low, high]; anything not a finite number counts as at rest (0)."""
    number = float(value) if is_number(value) else 0.0
    return min(high, max(low, number)) if math.isfinite(number) else 0.0


def _button(raw: Any) -> Tuple[bool, float]:
    """(pressed, value) of one button as the page sends it: [pressed, value], a number or a bool."""
    if isinstance(raw, (list, tuple)) and len(raw) == 2:
        pressed, value = raw
        return pressed is True, _finite(value, 0.0, 1.0)
    if isinstance(raw, bool):
        return raw, 1.0 if raw else 0.0
    value = _finite(raw, 0.0, 1.0)
    return value > 0.5, value


def state_from_standard(axes: Sequence[Any], buttons: Sequence[Any], connected: bool = True) -> PadState:
    """The lab's PadState of a W3C standard gamepad's ``axes`` and ``buttons`` (as ``navigator.getGamepads()``).

    Sticks read +1 right and up (standard: up is -1); the triggers l2/r2 are the values of
    buttons 6/7 (0..1) and also buttons, pressed as the browser says. Values outside the range
    are clipped, non-numbers read as at rest, missing entries as released; the d-pad and any
    button after 16 (e.g. a touchpad click) are left out.
    """
    values = {}
    for index, (name, inverted) in enumerate(STANDARD_AXES):
        value = _finite(axes[index], -1.0, 1.0) if index < len(axes) else 0.0
        values[name] = (-value if inverted else value) + 0.0  # + 0.0: no -0.0
    read = [_button(raw) for raw in buttons[:len(STANDARD_BUTTONS)]]
    pressed = {name: read[index][0] for index, name in enumerate(STANDARD_BUTTONS)
               if name is not None and index < len(read)}
    for name, index in STANDARD_TRIGGERS:
        values[name] = read[index][1] if index < len(read) else 0.0
    return PadState(values, pressed, connected)


@dataclass(frozen=True)
class BrowserReading:
    """One reading from the page: the state to act on, or a neutral one and why it cannot be used."""

    state: PadState
    problem: str = ""      # one line (cause, then fix); "" when the state may drive the robot
    pad_id: str = ""       # what the browser calls the pad, e.g. "Wireless Controller (STANDARD GAMEPAD ...)"
    haptics: bool = False  # the browser offers "dual-rumble" on this pad

    @property
    def usable(self) -> bool:
        return not self.problem


def read_browser_pad(pad: Optional[Mapping[str, Any]]) -> BrowserReading:
    """The page's description of its pad (None: no pad) as a reading; only a standard-mapped pad is usable.

    A pad the browser does not map ("mapping": "") has device-specific indices, in which the
    quit button could sit where close is: it gives a neutral state and a line saying what to do.
    """
    if not isinstance(pad, Mapping):
        return BrowserReading(PadState.neutral(connected=False), _NO_PAD)
    pad_id = str(pad.get("id", ""))[:120]
    haptics = pad.get("haptics") is True
    neutral = PadState.neutral(connected=False)
    if pad.get("connected") is False:
        return BrowserReading(neutral, f"the gamepad {pad_id!r} was disconnected: plug it in again or wake it "
                                       "(press its PS / Xbox button)", pad_id, haptics)
    if pad.get("mapping") != "standard":
        return BrowserReading(neutral, (
            f"the browser does not know the layout of {pad_id!r} (mapping {pad.get('mapping', '')!r}), so its "
            "buttons could mean anything and nothing is sent: use Chrome or Edge, connect the pad by USB, or use "
            "a DualShock 4, DualSense or Xbox pad"), pad_id, haptics)
    axes, buttons = pad.get("axes"), pad.get("buttons")
    if not isinstance(axes, (list, tuple)) or not isinstance(buttons, (list, tuple)) or len(axes) < 4 \
            or len(buttons) < 4:
        return BrowserReading(neutral, (f"the page sent no standard axes and buttons for {pad_id!r}: reload the "
                                        "page (the widget's JavaScript is older than the kernel's)"), pad_id, haptics)
    return BrowserReading(state_from_standard(axes, buttons), "", pad_id, haptics)


class BrowserClock:
    """How old a reading from the page is, though the page's clock is not the kernel's.

    The page stamps each reading with its monotonic clock (``sent_s``); the kernel notes when
    it handled it (``received_s``). Their difference is the clocks' offset plus the delay; the
    smallest difference seen is taken as no delay (it may rise by ``drift_per_s`` of the time
    passed, far more than two quartz clocks drift, so it follows them). A link counts only once
    ``steady`` readings in a row arrived as far apart as they were sent (not a queue replayed
    at once, as after a busy cell); until then, and for a reading older than the one before,
    :meth:`age_s` is None: not to be used. When readings keep arriving in real time but all
    look old (the page's clock jumped: a laptop that slept), the link is measured anew.
    """

    def __init__(self, steady: int = 5, drift_per_s: float = 1e-3, max_age_s: float = MAX_AGE_S) -> None:
        self.steady = int(steady)
        self.drift_per_s = float(drift_per_s)
        self.max_age_s = float(max_age_s)
        self.reset()

    def reset(self) -> None:
        """Forget the link: the next readings measure it again (a new page, a reload)."""
        self.base_s: Optional[float] = None
        self._last: Optional[Tuple[float, float]] = None
        self._in_time = 0
        self._old_in_time = 0
        self.resyncs = 0

    def age_s(self, sent_s: float, received_s: float) -> Optional[float]:
        """The reading's extra delay over the link's usual one (s), or None if it is not to be used."""
        last = self._last
        if last is not None and sent_s <= last[0]:
            return None  # out of order or repeated: never act on an older reading after a newer one
        delay = received_s - sent_s
        if last is not None and received_s - last[1] >= 0.5 * (sent_s - last[0]):
            self._in_time += 1
        else:
            self._in_time = 0
        if self.base_s is not None and last is not None:
            self.base_s = min(self.base_s + self.drift_per_s * max(0.0, received_s - last[1]), delay)
        self._last = (sent_s, received_s)
        if self.base_s is None:
            if self._in_time < self.steady:
                return None
            self.base_s, self._old_in_time = delay, 0  # the link measured: this reading has the usual delay
            return 0.0
        age = delay - self.base_s
        if age <= self.max_age_s:
            self._old_in_time = 0
            return age
        self._old_in_time = self._old_in_time + 1 if self._in_time else 0
        if self._old_in_time >= 5 * self.steady:
            self.base_s, self._old_in_time = delay, 0
            self.resyncs += 1
            return 0.0
        return age


class BrowserInput:
    """The pad's state to send at each moment: the page's last usable reading while it keeps coming, else neutral.

    :meth:`receive` takes one message of the page, ``{"sent_s": page clock, "visible": bool,
    "pad": {...} or None}``, at the kernel's monotonic ``received_s``; a message that
    :class:`BrowserClock` calls old or replayed is counted and dropped. :meth:`state` is neutral
    (connected False) when the last message was not usable (no pad, unknown mapping, hidden tab)
    or no usable one came for more than ``timeout_s`` (the heartbeat).
    """

    def __init__(self, timeout_s: float = HEARTBEAT_TIMEOUT_S, clock: Optional[BrowserClock] = None) -> None:
        if not (is_finite_number(timeout_s) and timeout_s > 0.0):
            raise GamepadError(f"the browser pad's timeout_s is {timeout_s!r}: give a positive number of seconds, "
                               f"e.g. {HEARTBEAT_TIMEOUT_S}")
        self.clock = clock if clock is not None else BrowserClock()
        self.heartbeat = Watchdog(timeout_s)
        self.reading = BrowserReading(PadState.neutral(connected=False), "waiting for the browser page to send the pad")
        self.age_s: Optional[float] = None  # the last used message's extra delay, s
        self.received = 0
        self.dropped = 0

    def receive(self, message: Any, received_s: float) -> Optional[BrowserReading]:
        """Handle one message of the page; the reading it gave, or None if it was dropped (old, replayed, garbled)."""
        self.received += 1
        sent_s = message.get("sent_s") if isinstance(message, Mapping) else None
        age = self.clock.age_s(float(sent_s), float(received_s)) if is_finite_number(sent_s) else None
        if age is None or age > self.clock.max_age_s:
            self.dropped += 1
            return None
        assert isinstance(message, Mapping)  # sent_s was read from it
        if message.get("visible") is False:
            reading = BrowserReading(PadState.neutral(connected=False), _HIDDEN)
        else:
            reading = read_browser_pad(message.get("pad"))
        self.reading, self.age_s = reading, age
        if reading.usable:
            self.heartbeat.feed(received_s)
        else:
            self.heartbeat.reset()
        return reading

    def fresh(self, now_s: float) -> bool:
        """Whether the last reading may drive the robot at ``now_s`` (usable, and not older than the timeout)."""
        return self.reading.usable and not self.heartbeat.is_stale(now_s)

    def state(self, now_s: float) -> PadState:
        """The state to send at ``now_s``: the last usable reading while fresh, else neutral (connected False)."""
        return self.reading.state if self.fresh(now_s) else PadState.neutral(connected=False)

    def problem(self, now_s: float) -> str:
        """One line on why the pad reads neutral at ``now_s`` ("" while it drives)."""
        if not self.reading.usable:
            return self.reading.problem
        if self.heartbeat.is_stale(now_s):
            return (f"no reading from the browser for {self.heartbeat.age_s(now_s):.1f} s (a cell is running, the "
                    "tab was closed or the link dropped): the robot gets a released pad until readings come again")
        return ""
