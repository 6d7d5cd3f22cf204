"""PadState and the positional names: the vocabulary every other module relies on."""

from __future__ import annotations

import pytest

from hri_teleop.core.gamepad import AXES, BUTTONS, GamepadError, PadState


def test_positional_names_are_the_contract():
    assert BUTTONS[:4] == ("south", "east", "west", "north")
    assert set(BUTTONS) >= {"l1", "r1", "l2", "r2", "select", "start", "mode", "l3", "r3"}
    assert AXES == ("left_x", "left_y", "right_x", "right_y", "l2", "r2")


def test_absent_axes_and_buttons_read_as_rest():
    state = PadState({"left_x": 0.5}, {"south": True})
    assert state.axis("left_x") == 0.5
    assert state.axis("right_y") == 0.0
    assert state.pressed("south") is True
    assert state.pressed("east") is False
    assert state.connected is True


def test_typos_are_refused_not_read_as_released():
    state = PadState()
    with pytest.raises(GamepadError, match="unknown button 'cross'.*south"):
        state.pressed("cross")
    with pytest.raises(GamepadError, match="unknown axis 'lx'"):
        state.axis("lx")
    with pytest.raises(GamepadError):
        PadState(buttons={"X": True})


@pytest.mark.parametrize("value", [1.5, -1.01, float("nan"), float("inf"), "0.5", True, None])
def test_axis_values_outside_their_range_are_refused(value):
    with pytest.raises(GamepadError) as info:
        PadState({"left_x": value})
    assert "\n" not in str(info.value)


def test_triggers_read_zero_to_one():
    assert PadState({"l2": 1.0}).axis("l2") == 1.0
    with pytest.raises(GamepadError, match="0..1"):
        PadState({"l2": -0.5})


def test_state_is_a_read_only_value():
    source = {"left_y": 0.25}
    state = PadState(source, {"north": 1})
    source["left_y"] = 0.9  # the caller's dict is copied
    assert state.axis("left_y") == 0.25
    assert state.buttons["north"] is True
    with pytest.raises(TypeError):
        state.axes["left_y"] = 1.0  # type: ignore[index]
    with pytest.raises(AttributeError):
        state.connected = False  # type: ignore[misc]
    assert state == PadState({"left_y": 0.25}, {"north": True})


def test_neutral_state():
    lost = PadState.neutral(connected=False)
    assert not lost.connected
    assert all(lost.axis(a) == 0.0 for a in AXES)
    assert not any(lost.pressed(b) for b in BUTTONS)
    assert "connected=False" in repr(lost)
