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
    BrowserReading,
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


# ------------------------------------------------------------------ the page's values, edge by edge

def test_a_state_is_connected_unless_the_caller_says_otherwise():
    assert state_from_standard([0.0] * 4, _buttons()).connected is True
    assert state_from_standard([0.0] * 4, _buttons(), connected=False).connected is False


def test_a_stick_beyond_either_end_reads_that_end():
    state = state_from_standard([-3.0, 3.0, -1.5, 2.0], _buttons())
    assert (state.axis("left_x"), state.axis("left_y"), state.axis("right_x"), state.axis("right_y")) == \
        (-1.0, -1.0, -1.0, -1.0)


def test_a_trigger_missing_from_a_short_button_list_reads_released():
    six = state_from_standard([0.0] * 4, [[True, 0.5]] * 6)  # buttons 0-5: no trigger
    assert six.axis("l2") == 0.0 and six.axis("r2") == 0.0
    seven = state_from_standard([0.0] * 4, [[True, 0.5]] * 7)  # button 6 (l2) only
    assert seven.axis("l2") == 0.5 and seven.axis("r2") == 0.0 and seven.pressed("l2")


def test_a_trigger_sent_as_a_bool_reads_fully_pulled_or_released():
    pulled = state_from_standard([0.0] * 4, [False] * 6 + [True, False])
    assert pulled.axis("l2") == 1.0 and pulled.pressed("l2")
    assert pulled.axis("r2") == 0.0 and not pulled.pressed("r2")


def test_a_trigger_value_above_1_reads_1_in_either_form():
    state = state_from_standard([0.0] * 4, [False] * 6 + [[True, 1.5], 1.5])
    assert state.axis("l2") == 1.0 and state.axis("r2") == 1.0


def test_a_button_sent_as_a_number_is_pressed_only_above_0_5():
    state = state_from_standard([0.0] * 4, [0.499, 0.5, 0.501])
    assert (state.pressed("south"), state.pressed("east"), state.pressed("west")) == (False, False, True)


NEUTRAL_LOST = PadState.neutral(connected=False)
NO_PAD = ("no gamepad in this browser: plug one in and press a button on it (a browser shows a pad only after "
          "a button press, with its tab visible)")
HIDDEN = ("the browser tab with the gamepad is hidden (the browser gives a pad only to the visible tab): bring "
          "the notebook's tab to the front")


def test_no_pad_reads_released_unplugged_with_a_line_saying_how_to_get_one():
    assert read_browser_pad(None) == BrowserReading(NEUTRAL_LOST, NO_PAD, "", False)


def test_a_usable_reading_has_no_problem_at_all():
    ok = read_browser_pad(_pad(id="Pad X"))
    assert ok.problem == "" and ok.usable and ok.pad_id == "Pad X" and ok.haptics is True


def test_a_disconnected_pad_keeps_its_name_and_haptics_with_the_line():
    gone = read_browser_pad(_pad(id="Pad X", connected=False))
    assert gone == BrowserReading(NEUTRAL_LOST, "the gamepad 'Pad X' was disconnected: plug it in again or wake it "
                                                "(press its PS / Xbox button)", "Pad X", True)


def test_an_unmapped_pad_names_its_mapping_in_the_line():
    unknown = ("the browser does not know the layout of 'Pad X' (mapping %s), so its buttons could mean anything "
               "and nothing is sent: use Chrome or Edge, connect the pad by USB, or use a DualShock 4, DualSense or "
               "Xbox pad")
    assert read_browser_pad(_pad(id="Pad X", mapping="xr-standard")) == \
        BrowserReading(NEUTRAL_LOST, unknown % "'xr-standard'", "Pad X", True)
    no_mapping = _pad(id="Pad X")
    del no_mapping["mapping"]
    assert read_browser_pad(no_mapping) == BrowserReading(NEUTRAL_LOST, unknown % "''", "Pad X", True)


def test_a_pad_without_an_id_is_named_by_an_empty_string():
    nameless = _pad(mapping="")
    del nameless["id"]
    reading = read_browser_pad(nameless)
    assert reading.pad_id == "" and reading.problem.startswith("the browser does not know the layout of '' (mapping")


def test_a_pad_id_is_cut_to_its_first_120_characters():
    for length, kept in [(119, 119), (120, 120), (121, 120)]:
        assert read_browser_pad(_pad(id="x" * length)).pad_id == "x" * kept, length


def test_the_page_must_send_at_least_4_axes_and_4_buttons_as_lists():
    reload = ("the page sent no standard axes and buttons for 'Pad X': reload the page (the widget's JavaScript is "
              "older than the kernel's)")
    refused = BrowserReading(NEUTRAL_LOST, reload, "Pad X", True)
    assert read_browser_pad(dict(_pad(id="Pad X"), buttons=[[True, 1.0]] * 3)) == refused
    assert read_browser_pad(dict(_pad(id="Pad X"), axes=[0.0] * 3)) == refused
    assert read_browser_pad(dict(_pad(id="Pad X"), axes=None)) == refused
    assert read_browser_pad(dict(_pad(id="Pad X"), buttons="abcd")) == refused
    four = read_browser_pad(dict(_pad(id="Pad X", axes=(0.0, -1.0, 0.0, 0.0)), buttons=[[True, 1.0]] * 4))
    assert four.usable and four.state.pressed("north") and four.state.axis("left_y") == 1.0


# ------------------------------------------------------------------ the link's clock, edge by edge
# Times are binary fractions (the page sends every 0.0625 s, the clocks are 512 s apart): exact comparisons.

def _measured(clock, count=6, sent_s=8.0, offset_s=512.0):
    """count readings in real time, all with delay offset_s; returns the last (sent, received)."""
    for i in range(count):
        clock.age_s(sent_s + i * 0.0625, sent_s + i * 0.0625 + offset_s)
    return sent_s + (count - 1) * 0.0625, sent_s + (count - 1) * 0.0625 + offset_s


def test_a_reading_counts_as_in_time_when_it_arrives_at_least_half_its_send_gap_after_the_last():
    for gap_s, measured in [(0.03125 - 0.001953125, False), (0.03125, True), (0.03125 + 0.001953125, True)]:
        clock = BrowserClock(steady=5)
        ages = [clock.age_s(8.0 + i * 0.0625, 520.0 + i * gap_s) for i in range(6)]
        assert ages[:5] == [None] * 5, gap_s
        assert (ages[5] is not None) == measured, gap_s


def test_a_reading_sent_at_the_same_page_time_as_the_last_is_not_used_again():
    clock = BrowserClock()
    sent, received = _measured(clock)
    assert clock.age_s(sent, received + 0.0625) is None
    assert clock.age_s(sent + 0.0625, received + 0.0625) == 0.0


def test_the_usual_delay_follows_a_smaller_one_at_once_and_a_larger_one_by_drift_per_s():
    clock = BrowserClock(drift_per_s=0.25)
    sent, received = _measured(clock)
    # 0.125 s later, 0.125 s faster than ever: the new usual delay
    assert clock.age_s(sent + 0.25, received + 0.125) == 0.0
    # 0.1875 s later, back at the old delay: the usual one rose by 0.25 * 0.1875 = 0.046875 s meanwhile
    assert clock.age_s(sent + 0.3125, received + 0.3125) == 0.125 - 0.046875


def _in_time(clock, sent_s, received_s, count, delay_s):
    """count readings in real time after (sent_s, received_s), each delay_s later than the link's usual delay."""
    ages = []
    for _ in range(count):
        sent_s, received_s = sent_s + 0.0625, received_s + 0.0625
        ages.append(clock.age_s(sent_s, received_s + delay_s))
    return ages, sent_s, received_s


def test_a_link_whose_readings_all_come_in_time_but_old_is_measured_anew_at_the_25th():
    clock = BrowserClock(steady=5, drift_per_s=0.0)
    sent, received = _measured(clock)
    assert clock.resyncs == 0
    ages, sent, received = _in_time(clock, sent, received, 25, 4.0)  # the page's clock jumped back 4 s
    assert ages == [4.0] * 24 + [0.0] and clock.resyncs == 1
    # at once a second jump: again 25 readings
    ages, sent, received = _in_time(clock, sent, received, 25, 8.0)
    assert ages == [4.0] * 24 + [0.0] and clock.resyncs == 2
    ages, sent, received = _in_time(clock, sent, received, 1, 8.0)
    assert ages == [0.0]


def test_a_link_measured_and_at_once_old_is_measured_anew_at_the_25th_reading_too():
    clock = BrowserClock(steady=5, drift_per_s=0.0)
    ages = [clock.age_s(8.0 + i * 0.0625, 520.0 + i * 0.0625) for i in range(6)]
    assert ages == [None] * 5 + [0.0]
    ages, _sent, _received = _in_time(clock, 8.3125, 520.3125, 25, 4.0)
    assert ages == [4.0] * 24 + [0.0] and clock.resyncs == 1


def test_a_reading_exactly_max_age_s_old_is_fresh_and_restarts_the_count_of_old_ones():
    clock = BrowserClock(steady=5, drift_per_s=0.0)
    sent, received = _measured(clock)
    ages, sent, received = _in_time(clock, sent, received, 24, 0.3125)
    assert ages == [0.3125] * 24
    sent, received = sent + 0.25, received + 0.25  # received 0.1875 s after the one before: in time
    assert clock.age_s(sent, received + 0.25) == 0.25
    ages, sent, received = _in_time(clock, sent, received, 25, 0.3125)
    assert ages == [0.3125] * 24 + [0.0] and clock.resyncs == 1


def test_the_count_of_old_readings_restarts_after_one_that_came_in_a_burst():
    clock = BrowserClock(steady=5, drift_per_s=0.0)
    sent, received = _measured(clock)
    ages, sent, received = _in_time(clock, sent, received, 10, 4.0)
    sent += 0.0625
    assert clock.age_s(sent, received + 4.0) == 3.9375  # received with the one before: not in time
    ages, sent, received = _in_time(clock, sent, received, 25, 4.0)
    assert ages == [3.9375] * 24 + [0.0] and clock.resyncs == 1


# ------------------------------------------------------------------ what the input keeps and counts

WAITING = "waiting for the browser page to send the pad"


def _message(sent_s, **pad):
    return {"sent_s": sent_s, "visible": True, "pad": _pad(**pad)}


def test_before_any_message_the_input_is_waiting_released_and_unplugged():
    link = BrowserInput()
    assert link.reading == BrowserReading(NEUTRAL_LOST, WAITING)
    assert link.problem(0.0) == WAITING and link.state(0.0) == NEUTRAL_LOST
    assert (link.received, link.dropped, link.age_s) == (0, 0, None)


def test_every_message_is_counted_and_each_dropped_one_apart():
    link = BrowserInput()
    for i in range(6):  # five before the link is measured, then one used
        link.receive(_message(8.0 + i * 0.0625), 520.0 + i * 0.0625)
    assert (link.received, link.dropped, link.age_s) == (6, 5, 0.0)
    link.receive("garbage", 521.0)
    assert (link.received, link.dropped) == (7, 6)


def test_a_message_exactly_max_age_s_late_is_used():
    link = BrowserInput(clock=BrowserClock(drift_per_s=0.0))
    for i in range(6):
        link.receive(_message(8.0 + i * 0.0625), 520.0 + i * 0.0625)
    reading = link.receive(_message(8.375, axes=(0.0, -1.0, 0.0, 0.0)), 520.375 + 0.25)
    assert reading is not None and link.age_s == 0.25 and link.state(520.625).axis("left_y") == 1.0


def test_the_input_measures_the_link_with_the_clock_it_is_given():
    clock = BrowserClock(steady=1)
    link = BrowserInput(clock=clock)
    assert link.clock is clock
    assert link.receive(_message(8.0), 520.0) is None
    assert link.receive(_message(8.0625), 520.0625) is not None  # one reading in time is enough


def test_a_hidden_tab_gives_a_released_unplugged_reading_and_the_line_to_bring_it_forward():
    link = BrowserInput()
    for i in range(6):
        link.receive(_message(8.0 + i * 0.0625), 520.0 + i * 0.0625)
    reading = link.receive({"sent_s": 8.375, "visible": False, "pad": _pad()}, 520.375)
    assert reading == BrowserReading(NEUTRAL_LOST, HIDDEN)
    assert link.problem(520.375) == HIDDEN


def test_a_silent_page_says_for_how_long_and_what_the_robot_gets():
    link, received = _input_driving(0.25)
    assert link.problem(received + 0.3125) == (
        "no reading from the browser for 0.3 s (a cell is running, the tab was closed or the link dropped): the robot "
        "gets a released pad until readings come again")
