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


# ------------------------------------------------------------------ the ranges, edge by edge, and the lines

def _refusal(axes):
    with pytest.raises(GamepadError) as info:
        PadState(axes)
    return str(info.value)


def test_a_stick_reads_from_minus_1_to_1_inclusive():
    assert PadState({"left_x": -1.0, "right_y": 1.0}).axes == {"left_x": -1.0, "right_y": 1.0}
    assert _refusal({"left_x": -1.000001}) == "axis 'left_x' got -1.000001: give a finite number in -1..1"
    assert _refusal({"right_y": 1.000001}) == "axis 'right_y' got 1.000001: give a finite number in -1..1"


def test_a_trigger_reads_from_0_to_1_inclusive():
    assert PadState({"l2": 0.0, "r2": 1.0}).axes == {"l2": 0.0, "r2": 1.0}
    assert _refusal({"r2": -0.000001}) == "axis 'r2' got -1e-06: give a finite number in 0..1"
    assert _refusal({"l2": 1.000001}) == "axis 'l2' got 1.000001: give a finite number in 0..1"


def test_an_axis_value_that_is_no_number_names_the_range():
    assert _refusal({"left_x": "0.5"}) == "axis 'left_x' got '0.5': give a number in -1..1"
    assert _refusal({"l2": True}) == "axis 'l2' got True: give a number in 0..1"
    assert _refusal({"left_y": float("nan")}) == "axis 'left_y' got nan: give a finite number in -1..1"


def test_a_numpy_number_is_an_axis_value_and_reads_as_a_float():
    np = pytest.importorskip("numpy")
    state = PadState({"left_x": np.float32(0.5), "l2": np.int64(1)})
    assert state.axes == {"left_x": 0.5, "l2": 1.0} and type(state.axis("l2")) is float


def test_buttons_and_connected_read_as_bools():
    state = PadState({}, {"south": 1, "east": 0}, connected=0)
    assert state.buttons == {"south": True, "east": False} and state.connected is False
    assert PadState().connected is True and PadState.neutral().connected is True


def test_unknown_names_are_refused_with_the_names_to_use():
    with pytest.raises(GamepadError) as info:
        PadState().pressed("cross")
    assert str(info.value) == ("unknown button 'cross': use a positional name, one of south, east, west, north, l1, "
                               "r1, l2, r2, select, start, mode, l3, r3 (south = cross/A, east = circle/B, "
                               "west = square/X, north = triangle/Y)")
    with pytest.raises(GamepadError) as info:
        PadState().axis("lx")
    assert str(info.value) == "unknown axis 'lx': use one of left_x, left_y, right_x, right_y, l2, r2"
    with pytest.raises(GamepadError, match="unknown axis 'lx'"):
        PadState({"lx": 0.0})
    with pytest.raises(GamepadError, match="unknown button 'X'"):
        PadState(buttons={"X": True})


def test_the_repr_shows_the_moved_axes_to_3_decimals_and_the_held_buttons():
    state = PadState({"left_x": 0.5, "left_y": 0.0, "r2": 0.12345}, {"south": True, "east": False, "r1": True})
    assert repr(state) == "PadState(connected=True, axes={left_x=0.500, r2=0.123}, pressed=[south, r1])"
    assert repr(PadState.neutral(connected=False)) == "PadState(connected=False, axes={}, pressed=[])"


def test_a_rumble_intensity_is_clipped_to_0_to_1_and_nan_is_0():
    from hri_teleop.core.gamepad.state import clean_intensity

    for given, clean in [(-0.5, 0.0), (0.0, 0.0), (0.25, 0.25), (1.0, 1.0), (1.5, 1.0), (float("nan"), 0.0),
                         (float("inf"), 1.0), (float("-inf"), 0.0), (1, 1.0)]:
        value = clean_intensity(given)
        assert value == clean and type(value) is float, given
    np = pytest.importorskip("numpy")
    assert clean_intensity(np.float32(0.5)) == 0.5


@pytest.mark.parametrize("bad", ["0.5", None, True])
def test_a_rumble_intensity_that_is_no_number_is_refused(bad):
    from hri_teleop.core.gamepad.state import clean_intensity

    with pytest.raises(GamepadError) as info:
        clean_intensity(bad)
    assert str(info.value) == "rumble intensity %r is not a number: pass 0..1 (0 stops)" % (bad,)


def test_a_rumble_duration_is_a_finite_number_of_seconds_from_0():
    from hri_teleop.core.gamepad.state import clean_duration

    assert clean_duration(0.0) == 0.0 and clean_duration(0.5) == 0.5 and type(clean_duration(2)) is float
    np = pytest.importorskip("numpy")
    assert clean_duration(np.float32(0.25)) == 0.25
    for bad in (-0.000001, float("inf"), float("nan"), "1", None, True):
        with pytest.raises(GamepadError) as info:
            clean_duration(bad)
        assert str(info.value) == ("rumble duration %r s is not a finite number >= 0: pass the effect length in "
                                   "seconds (0 means until the next rumble call)" % (bad,)), bad
