"""A pad read by a web browser: the W3C standard mapping as positional names, the link's clock, the heartbeat."""

from __future__ import annotations

import math

import pytest

from hri_teleop.core.gamepad import BUTTONS, GamepadError, PadState, available_layouts, load_layout
from hri_teleop.core.gamepad.browser import (
    HEARTBEAT_TIMEOUT_S,
    MAX_AGE_S,
    STANDARD_BUTTONS,
    BrowserClock,
    BrowserInput,
    read_browser_pad,
    state_from_standard,
)
from hri_teleop.core.teleop import TeleopParams

PAD_ID = "Wireless Controller (STANDARD GAMEPAD Vendor: 054c Product: 09cc)"


def _buttons(pressed=(), values=None):
    """17 standard buttons as the page sends them: [pressed, value]."""
    values = values or {}
    return [[i in pressed, values.get(i, 1.0 if i in pressed else 0.0)] for i in range(17)]


def _pad(axes=(0.0, 0.0, 0.0, 0.0), pressed=(), values=None, **extra):
    pad = {"id": PAD_ID, "mapping": "standard", "connected": True, "axes": list(axes),
           "buttons": _buttons(pressed, values), "haptics": True}
    pad.update(extra)
    return pad


def test_standard_face_and_centre_buttons_become_positional_names():
    for index, name in [(0, "south"), (1, "east"), (2, "west"), (3, "north"), (4, "l1"), (5, "r1"),
                        (8, "select"), (9, "start"), (10, "l3"), (11, "r3"), (16, "mode")]:
        state = state_from_standard([0.0] * 4, _buttons({index}))
        assert [b for b in BUTTONS if state.pressed(b)] == [name], index
    assert set(n for n in STANDARD_BUTTONS if n) == set(BUTTONS)


def test_the_d_pad_and_extra_buttons_press_nothing():
    buttons = _buttons({12, 13, 14, 15}) + [[True, 1.0]]  # + a touchpad click (index 17)
    state = state_from_standard([0.0] * 4, buttons)
    assert not any(state.pressed(b) for b in BUTTONS)


def test_sticks_read_up_and_right_as_plus_one_though_the_browser_reads_up_as_minus_one():
    state = state_from_standard([0.5, -1.0, -0.25, 0.75], _buttons())
    assert state.axis("left_x") == 0.5 and state.axis("left_y") == 1.0
    assert state.axis("right_x") == -0.25 and state.axis("right_y") == -0.75
    centred = state_from_standard([0.0, 0.0, 0.0, 0.0], _buttons())
    assert math.copysign(1.0, centred.axis("left_y")) == 1.0  # no -0.0 from the inversion


def test_triggers_are_the_values_of_buttons_6_and_7():
    state = state_from_standard([0.0] * 4, _buttons({7}, {6: 0.3, 7: 0.9}))
    assert state.axis("l2") == pytest.approx(0.3) and state.axis("r2") == pytest.approx(0.9)
    assert state.pressed("r2") and not state.pressed("l2")  # pressed as the browser says


def test_out_of_range_and_garbled_values_are_clipped_or_read_at_rest():
    state = state_from_standard([3.0, float("nan"), "x", None], [[True, 7.0], True, 0.8, "y"])
    assert state.axis("left_x") == 1.0 and state.axis("left_y") == 0.0 and state.axis("right_x") == 0.0
    assert state.pressed("south") and state.pressed("east") and state.pressed("west") and not state.pressed("north")


def test_short_lists_read_as_released():
    state = state_from_standard([0.2], [[True, 1.0]])
    assert state.axis("left_x") == 0.2 and state.axis("right_y") == 0.0 and state.pressed("south")


@pytest.mark.parametrize("layout", available_layouts())
def test_a_browser_state_survives_the_nodes_joy_in_every_layout(layout):
    """The widget publishes the state as raw Joy in the node's layout; the node reads back the same state."""
    pad = load_layout(layout)
    state = state_from_standard([0.5, -0.75, -0.25, 1.0], _buttons({0, 3, 5, 9}, {6: 0.5}))
    axes, buttons = pad.raw_from_state(state)
    back = pad.state_from_raw(axes, buttons)
    for name in ("left_x", "left_y", "right_x", "right_y"):
        assert back.axis(name) == pytest.approx(state.axis(name)), name
    for name in ("south", "north", "r1", "start"):
        assert back.pressed(name) == state.pressed(name) or name not in pad.buttons, name


def test_only_a_standard_mapped_connected_pad_is_usable():
    ok = read_browser_pad(_pad(axes=(0.0, -1.0, 0.0, 0.0)))
    assert ok.usable and ok.state.axis("left_y") == 1.0 and ok.haptics and ok.pad_id == PAD_ID
    unknown = read_browser_pad(_pad(axes=(0.0, -1.0, 0.0, 0.0), mapping=""))
    assert not unknown.usable and unknown.state == PadState.neutral(connected=False)
    assert PAD_ID in unknown.problem and "Chrome or Edge" in unknown.problem
    gone = read_browser_pad(_pad(axes=(0.0, -1.0, 0.0, 0.0), connected=False))
    assert not gone.usable and "disconnected" in gone.problem and gone.state.axis("left_y") == 0.0
    none = read_browser_pad(None)
    assert not none.usable and "press a button" in none.problem
    short = read_browser_pad(_pad(axes=(0.0,)))
    assert not short.usable and "reload the page" in short.problem


def _steady(clock, start_s=10.0, offset_s=1000.0, period_s=0.04, count=6):
    """Readings sent every period and received offset later (the clocks' offset; no delay)."""
    ages = [clock.age_s(start_s + i * period_s, start_s + i * period_s + offset_s) for i in range(count)]
    return ages, start_s + count * period_s


def test_a_link_counts_once_readings_arrive_as_far_apart_as_they_were_sent():
    clock = BrowserClock(steady=5)
    ages, _ = _steady(clock)
    assert ages[:5] == [None] * 5 and ages[5] == pytest.approx(0.0)


def test_a_queue_replayed_at_once_is_old_and_an_earlier_reading_is_never_used():
    clock = BrowserClock()
    _ages, t = _steady(clock)
    # a cell kept the kernel busy for 2 s: 50 readings arrive at once
    ages = [clock.age_s(t + i * 0.04, t + 2.0 + 1000.0) for i in range(50)]
    assert all(a is None or a > MAX_AGE_S for a in ages[:40])
    assert clock.age_s(t, t + 1000.0 + 3.0) is None  # older than one already seen


def test_the_last_reading_before_the_age_limit_counts_and_the_next_does_not():
    clock = BrowserClock(drift_per_s=0.0)
    _ages, t = _steady(clock)
    assert clock.age_s(t, t + 1000.0 + MAX_AGE_S - 1e-3) == pytest.approx(MAX_AGE_S - 1e-3)
    assert clock.age_s(t + 0.04, t + 0.04 + 1000.0 + MAX_AGE_S + 1e-3) == pytest.approx(MAX_AGE_S + 1e-3)


def _input_driving(timeout_s=HEARTBEAT_TIMEOUT_S):
    """A BrowserInput whose link is measured, the stick pushed forward; returns it and the last time."""
    link = BrowserInput(timeout_s)
    t = 8.0  # times in binary fractions: the comparisons at the threshold are exact
    for _ in range(6):
        link.receive({"sent_s": t, "visible": True, "pad": _pad(axes=(0.0, -1.0, 0.0, 0.0))}, t + 512.0)
        t += 0.0625
    return link, t - 0.0625 + 512.0


def test_the_heartbeat_keeps_the_state_up_to_its_timeout_and_releases_the_pad_after():
    timeout_s = 0.25
    link, received = _input_driving(timeout_s)
    assert link.state(received).axis("left_y") == 1.0 and link.problem(received) == ""
    assert link.state(received + timeout_s).axis("left_y") == 1.0
    late = link.state(received + timeout_s + 1e-3)
    assert late == PadState.neutral(connected=False)
    assert "no reading from the browser" in link.problem(received + timeout_s + 1e-3)
    assert 0.0 < HEARTBEAT_TIMEOUT_S < TeleopParams().input_timeout_s  # the page, not the node, stops the robot


def test_messages_before_the_link_is_measured_and_old_ones_are_dropped():
    link = BrowserInput()
    reading = link.receive({"sent_s": 1.0, "visible": True, "pad": _pad(axes=(0.0, -1.0, 0.0, 0.0))}, 50.0)
    assert reading is None and link.state(50.0).axis("left_y") == 0.0 and link.dropped == 1
    assert link.receive({"visible": True}, 50.1) is None and link.receive("garbage", 50.2) is None


def test_a_hidden_tab_a_disconnected_pad_and_an_unknown_mapping_release_at_once():
    for message, words in [({"visible": False, "pad": _pad(axes=(0.0, -1.0, 0.0, 0.0))}, "hidden"),
                           ({"visible": True, "pad": _pad(connected=False)}, "disconnected"),
                           ({"visible": True, "pad": _pad(mapping="")}, "Chrome or Edge"),
                           ({"visible": True, "pad": None}, "no gamepad")]:
        link, received = _input_driving()
        reading = link.receive(dict(message, sent_s=received - 512.0 + 0.0625), received + 0.0625)
        assert reading is not None and not reading.usable
        assert link.state(received + 0.0625) == PadState.neutral(connected=False)
        assert words in link.problem(received + 0.0625)


def test_the_heartbeat_timeout_must_be_a_positive_number():
    for bad in (0.0, -1.0, float("nan"), float("inf"), "0.3"):
        with pytest.raises(GamepadError, match="positive number of seconds"):
            BrowserInput(bad)
