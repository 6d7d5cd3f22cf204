"""Pad snapshots -> the handout's pygame-style events (hri_teleop.core.gamepad.events)."""

from __future__ import annotations

import pytest

from hri_teleop.core.gamepad import GamepadError, PadState
from hri_teleop.core.gamepad.events import JOYAXISMOTION, JOYBUTTONDOWN, JOYBUTTONUP, PadEvent, pad_events


def test_a_press_and_a_release_are_one_event_each():
    rest = PadState.neutral()
    held = PadState({}, {"north": True})
    assert pad_events(rest, held) == [PadEvent(JOYBUTTONDOWN, button="north")]
    assert pad_events(held, held) == []  # held: no repeated event (the toggle fires once per press)
    assert pad_events(held, rest) == [PadEvent(JOYBUTTONUP, button="north")]


def test_axis_motion_carries_the_new_value_and_comes_before_buttons():
    before = PadState({"left_y": 0.2}, {})
    after = PadState({"left_y": -0.5, "right_x": 1.0}, {"south": True})
    assert pad_events(before, after) == [PadEvent(JOYAXISMOTION, axis="left_y", value=-0.5),
                                         PadEvent(JOYAXISMOTION, axis="right_x", value=1.0),
                                         PadEvent(JOYBUTTONDOWN, button="south")]


def test_no_previous_state_means_a_pad_at_rest():
    assert pad_events(None, PadState({"left_x": 0.3}, {})) == [PadEvent(JOYAXISMOTION, axis="left_x", value=0.3)]


def test_a_lost_pad_lets_go_of_everything():
    held = PadState({"left_y": 1.0}, {"east": True})
    events = pad_events(held, PadState({"left_y": 1.0}, {"east": True}, connected=False))
    assert PadEvent(JOYBUTTONUP, button="east") in events
    assert PadEvent(JOYAXISMOTION, axis="left_y", value=0.0) in events


@pytest.mark.parametrize("kwargs", [{"type": "KEYDOWN", "button": "south"},
                                    {"type": JOYBUTTONDOWN, "button": "cross"},
                                    {"type": JOYAXISMOTION, "axis": "wheel"}])
def test_malformed_events_are_refused_with_the_valid_names(kwargs):
    with pytest.raises(GamepadError, match="use one of|one of"):
        PadEvent(**kwargs)
