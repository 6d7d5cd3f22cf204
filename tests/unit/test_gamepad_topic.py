"""The browser pad as a node reads it: the latest sensor_msgs/Joy, released once the messages stop."""

from __future__ import annotations

import pytest

from hri_teleop.core.gamepad import GamepadError, PadState
from hri_teleop.core.gamepad.layout import load_layout
from hri_teleop.core.gamepad.topic import TOPIC_PAD_TIMEOUT_S, TopicPadInput
from hri_teleop.hardware.gamepad import open_gamepad

LAYOUT = load_layout("dualshock4")


def _raw(state: PadState):
    return LAYOUT.raw_from_state(state)


def test_the_latest_message_is_the_pad_in_its_layout():
    pad = TopicPadInput(LAYOUT)
    pad.receive(*_raw(PadState({"left_y": 1.0}, {"south": True})), now=10.0)
    state = pad.state(10.1)
    assert state.connected and state.axis("left_y") == pytest.approx(1.0) and state.pressed("south")
    pad.receive(*_raw(PadState({"right_y": -0.5}, {})), now=10.2)
    state = pad.state(10.2)
    assert state.axis("left_y") == 0.0 and state.axis("right_y") == pytest.approx(-0.5) and not state.pressed("south")


def test_messages_that_stop_are_input_lost_a_released_unplugged_pad():
    pad = TopicPadInput(LAYOUT)
    pad.receive(*_raw(PadState({"left_y": 1.0}, {"south": True})), now=10.0)
    assert pad.state(10.0 + TOPIC_PAD_TIMEOUT_S).pressed("south")
    lost = pad.state(10.0 + TOPIC_PAD_TIMEOUT_S + 0.01)
    assert lost == PadState.neutral(connected=False)


def test_before_the_first_message_the_pad_reads_released_and_unplugged():
    assert TopicPadInput(LAYOUT).state(0.0) == PadState.neutral(connected=False)


def test_a_message_from_the_future_of_the_clock_is_not_fresh():
    pad = TopicPadInput(LAYOUT)
    pad.receive(*_raw(PadState({"left_y": 1.0}, {})), now=10.0)
    assert not pad.state(9.0).connected


def test_the_browser_pad_takes_no_script():
    with pytest.raises(GamepadError, match="only drives the virtual pad"):
        open_gamepad("browser", script="/tmp/drive.yaml")


def test_the_browser_pad_refuses_to_open_beside_the_real_robot():
    from hri_teleop.hardware.joy_pad import BrowserJoyPad

    with pytest.raises(GamepadError, match=r"does not drive the real robot.*\(/franka_control\).*'pygame'"):
        BrowserJoyPad(hardware=lambda: ["/franka_control"])


class _Joy:
    def __init__(self, state: PadState) -> None:
        self.axes, self.buttons = _raw(state)


def test_the_browser_pad_reads_unplugged_from_the_moment_the_real_robot_appears(monkeypatch):
    import time

    from hri_teleop.hardware import joy_pad

    monkeypatch.setattr(joy_pad, "HARDWARE_CHECK_S", 0.01)
    found = []
    clock = [10.0]
    pad = joy_pad.BrowserJoyPad(topic="/teleoperation/virtual_joy", hardware=lambda: list(found), clock=lambda: clock[0],
                                log=lambda _line: None)
    try:
        pad.on_joy(_Joy(PadState({"left_y": 1.0}, {})))
        assert pad.poll().axis("left_y") == pytest.approx(1.0)
        found.append("/franka_control")
        deadline = time.monotonic() + 10.0
        while not pad.refused and time.monotonic() < deadline:
            time.sleep(0.01)
        pad.on_joy(_Joy(PadState({"left_y": 1.0}, {})))
        assert "(/franka_control)" in pad.refused and pad.poll() == PadState.neutral(connected=False)
    finally:
        pad.close()


def test_a_timeout_that_is_not_positive_is_one_line_with_an_example():
    with pytest.raises(GamepadError, match=r"timeout_s is 0: give a positive number of seconds, e\.g\. 0\.5"):
        TopicPadInput(LAYOUT, 0)


def test_a_message_is_fresh_from_the_moment_it_arrives_until_exactly_the_timeout_after():
    pad = TopicPadInput(LAYOUT, timeout_s=0.25)
    pad.receive(*_raw(PadState({"left_y": 1.0}, {})), now=10.0)
    for now, fresh in [(9.999, False), (10.0, True), (10.25, True), (10.251, False)]:
        assert pad.fresh(now) is fresh, now
        assert pad.state(now).connected is fresh, now


def test_any_positive_timeout_is_taken_as_seconds():
    assert TopicPadInput(LAYOUT, 1).timeout_s == 1.0 and type(TopicPadInput(LAYOUT, 1).timeout_s) is float
    tiny = TopicPadInput(LAYOUT, 0.001)
    tiny.receive(*_raw(PadState({"left_y": 1.0}, {})), now=10.0)
    assert tiny.fresh(10.001) and not tiny.fresh(10.002)
    with pytest.raises(GamepadError, match=r"timeout_s is -0\.5: give a positive number of seconds, e\.g\. 0\.5"):
        TopicPadInput(LAYOUT, -0.5)


def test_every_message_is_counted():
    pad = TopicPadInput(LAYOUT)
    assert pad.messages == 0
    for i in range(3):
        pad.receive([0.0] * 6, [0] * 13, now=10.0 + i)
    assert pad.messages == 3


def test_a_message_is_read_in_the_layout_the_input_was_given():
    xbox = load_layout("xbox")
    pad = TopicPadInput(xbox)
    assert pad.layout is xbox
    axes, buttons = xbox.raw_from_state(PadState({"right_x": 0.5}, {"north": True}))
    pad.receive(tuple(axes), tuple(buttons), now=1.0)
    assert pad.state(1.0) == xbox.state_from_raw(axes, buttons)
    assert pad.state(1.0).axis("right_x") == pytest.approx(0.5) and pad.state(1.0).pressed("north")
