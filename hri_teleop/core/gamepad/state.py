"""What a gamepad looks like to the rest of the toolkit: positional names and one snapshot type.

Raw button and axis numbers differ between controllers, kernel drivers and operating
systems (see ``layouts/*.yaml``), so nothing outside this package ever sees them.
Everything downstream -- the teleoperation controller, the ROS node, the grader --
talks about *positions* ("south" is cross on a PlayStation pad and A on an Xbox pad)
and about sticks that read +1 to the right and +1 up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping

from hri_teleop.core.checks import is_number
from hri_teleop.core.errors import HriTeleopError

__all__ = [
    "AXES",
    "BUTTONS",
    "STICK_AXES",
    "TRIGGER_AXES",
    "BUTTON_LABELS",
    "GamepadError",
    "PadState",
]

#: Positional button names. south/east/west/north are the four face buttons by where
#: they sit (cross/circle/square/triangle on PlayStation, A/B/X/Y on Xbox); l2/r2 are
#: the triggers' digital "pressed" buttons where the driver reports one.
BUTTONS = ("south", "east", "west", "north", "l1", "r1", "l2", "r2",
           "select", "start", "mode", "l3", "r3")

#: Logical axes. Sticks read -1..1 with right = +1 and up = +1 (the layout undoes SDL's
#: up = -1); triggers read 0 (released) .. 1 (fully pulled).
AXES = ("left_x", "left_y", "right_x", "right_y", "l2", "r2")
STICK_AXES = ("left_x", "left_y", "right_x", "right_y")
TRIGGER_AXES = ("l2", "r2")

#: What the positional names are called on the two pad families, for messages to students.
BUTTON_LABELS: Mapping[str, str] = MappingProxyType({
    "south": "cross / A", "east": "circle / B", "west": "square / X", "north": "triangle / Y",
    "l1": "L1 / LB", "r1": "R1 / RB", "l2": "L2 / LT", "r2": "R2 / RT",
    "select": "share / back", "start": "options / start", "mode": "PS / guide",
    "l3": "left stick click", "r3": "right stick click",
})


class GamepadError(HriTeleopError, RuntimeError):
    """A gamepad problem a user can fix; the message is one line: the cause, then the fix."""


def unknown_button_error(name: object) -> GamepadError:
    return GamepadError(
        "unknown button %r: use a positional name, one of %s (south = cross/A, east = circle/B, "
        "west = square/X, north = triangle/Y)" % (name, ", ".join(BUTTONS)))


def unknown_axis_error(name: object) -> GamepadError:
    return GamepadError("unknown axis %r: use one of %s" % (name, ", ".join(AXES)))


def check_axis_value(name: str, value: object) -> float:
    """value as a float, or GamepadError if it is not a finite number in the axis' range.

    Sticks read -1..1, triggers 0..1; a bool is refused because ``set_axis("l2", True)``
    is a mistake, not a trigger pull.
    """
    low = 0.0 if name in TRIGGER_AXES else -1.0
    if not is_number(value, numpy=True):
        raise GamepadError("axis %r got %r: give a number in %g..1" % (name, value, low))
    result = float(value)
    if not math.isfinite(result) or not low <= result <= 1.0:
        raise GamepadError("axis %r got %r: give a finite number in %g..1" % (name, value, low))
    return result


@dataclass(frozen=True)
class PadState:
    """One snapshot of a pad: logical axes (raw, *not* dead-zone filtered) and buttons.

    Axes and buttons that are absent read as 0.0 / not pressed, so a pad without, say,
    digital trigger buttons needs no special case downstream. Names are checked, because a
    typo such as ``pressed("cross")`` would otherwise read "not pressed" forever.
    """

    axes: Mapping[str, float] = field(default_factory=dict)
    buttons: Mapping[str, bool] = field(default_factory=dict)
    connected: bool = True

    def __post_init__(self) -> None:
        axes = {}
        for name, value in dict(self.axes).items():
            if name not in AXES:
                raise unknown_axis_error(name)
            axes[name] = check_axis_value(name, value)
        buttons = {}
        for name, value in dict(self.buttons).items():
            if name not in BUTTONS:
                raise unknown_button_error(name)
            buttons[name] = bool(value)
        # Read-only views: a PadState is a value, shared between the pad and its readers.
        object.__setattr__(self, "axes", MappingProxyType(axes))
        object.__setattr__(self, "buttons", MappingProxyType(buttons))
        object.__setattr__(self, "connected", bool(self.connected))

    def axis(self, name: str) -> float:
        """The axis value, 0.0 if this pad has no such axis."""
        if name not in AXES:
            raise unknown_axis_error(name)
        return self.axes.get(name, 0.0)

    def pressed(self, name: str) -> bool:
        """True while the button is held; False if this pad has no such button."""
        if name not in BUTTONS:
            raise unknown_button_error(name)
        return self.buttons.get(name, False)

    @classmethod
    def neutral(cls, connected: bool = True) -> "PadState":
        """Sticks centred, triggers released, nothing pressed: what a lost pad reports."""
        return cls({name: 0.0 for name in AXES}, {name: False for name in BUTTONS}, connected)

    def __repr__(self) -> str:
        axes = ", ".join("%s=%.3f" % (k, v) for k, v in self.axes.items() if v != 0.0)
        held = ", ".join(k for k, v in self.buttons.items() if v)
        return "PadState(connected=%s, axes={%s}, pressed=[%s])" % (self.connected, axes, held)


def clean_intensity(intensity: float) -> float:
    """Rumble intensity clipped to 0..1; NaN gives 0 so a bad force value never shakes the pad."""
    if not is_number(intensity, numpy=True):
        raise GamepadError("rumble intensity %r is not a number: pass 0..1 (0 stops)" % (intensity,))
    value = float(intensity)
    if math.isnan(value):
        return 0.0
    return min(1.0, max(0.0, value))


def clean_duration(duration_s: float) -> float:
    """Rumble duration in seconds, checked: a negative or infinite duration is a caller bug."""
    value = float(duration_s) if is_number(duration_s, numpy=True) else float("nan")
    if not math.isfinite(value) or value < 0.0:
        raise GamepadError("rumble duration %r s is not a finite number >= 0: pass the effect "
                           "length in seconds (0 means until the next rumble call)" % (duration_s,))
    return value
