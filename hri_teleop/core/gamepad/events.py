"""Pad snapshots -> the handout's pygame-style events (JOYAXISMOTION, JOYBUTTONDOWN, JOYBUTTONUP).

Handout Ex. 8 explains the teleoperation script through pygame's events, while the toolkit's pads
deliver snapshots (:class:`~hri_teleop.core.gamepad.PadState`). The student's template, the
grader's pad traces and the tests turn two consecutive snapshots into the events between them
here, with positional names instead of raw pygame indices.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional

from hri_teleop.core.gamepad.state import AXES, BUTTONS, GamepadError, PadState

__all__ = ["JOYAXISMOTION", "JOYBUTTONDOWN", "JOYBUTTONUP", "EVENT_TYPES", "PadEvent", "pad_events"]

JOYAXISMOTION = "JOYAXISMOTION"
JOYBUTTONDOWN = "JOYBUTTONDOWN"
JOYBUTTONUP = "JOYBUTTONUP"
EVENT_TYPES = (JOYAXISMOTION, JOYBUTTONDOWN, JOYBUTTONUP)


@dataclass(frozen=True)
class PadEvent:
    """One event: ``type`` is one of :data:`EVENT_TYPES`; ``button`` or ``axis`` names what moved.

    ``value`` is the axis' new value (sticks -1..1, +1 right/up; triggers 0..1) for
    JOYAXISMOTION and 0.0 for button events.
    """

    type: str
    button: str = ""
    axis: str = ""
    value: float = 0.0

    def __post_init__(self) -> None:
        if self.type not in EVENT_TYPES:
            raise GamepadError("unknown event type %r: use one of %s" % (self.type, ", ".join(EVENT_TYPES)))
        if self.type == JOYAXISMOTION and self.axis not in AXES:
            raise GamepadError("JOYAXISMOTION needs an axis, one of %s, got %r" % (", ".join(AXES), self.axis))
        if self.type != JOYAXISMOTION and self.button not in BUTTONS:
            raise GamepadError("%s needs a button, one of %s, got %r" % (self.type, ", ".join(BUTTONS), self.button))


def pad_events(before: Optional[PadState], after: PadState) -> List[PadEvent]:
    """The events that turn ``before`` into ``after``: axes first (in AXES order), then buttons.

    ``before`` None means a pad at rest (sticks centred, nothing pressed). A disconnected
    ``after`` reads as a pad at rest: every held button is released and every stick
    returns to 0, so code that reacts to events lets go of everything when the pad is lost.
    """
    old = before if before is not None and before.connected else PadState.neutral()
    new = after if after.connected else PadState.neutral()
    events: List[PadEvent] = []
    for axis in AXES:
        if new.axis(axis) != old.axis(axis):
            events.append(PadEvent(JOYAXISMOTION, axis=axis, value=new.axis(axis)))
    for button in BUTTONS:
        was, now = old.pressed(button), new.pressed(button)
        if now and not was:
            events.append(PadEvent(JOYBUTTONDOWN, button=button))
        elif was and not now:
            events.append(PadEvent(JOYBUTTONUP, button=button))
    return events
