"""Layout files: raw SDL indices <-> positional names, and the errors a bad file gives."""

from __future__ import annotations

import textwrap

import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

from hri_teleop.core.gamepad import (
    AXES,
    BUTTONS,
    LAYOUT_DIR,
    GamepadError,
    Layout,
    PadState,
    available_layouts,
    load_layout,
)

#: Raw (SDL2, Linux, kernel driver) indices each shipped layout must keep; sources in the YAML.
EXPECTED = {
    "dualshock4": dict(buttons=dict(south=0, east=1, north=2, west=3, l1=4, r1=5, select=8,
                                    start=9, mode=10, l3=11, r3=12),
                       axes=dict(left_x=0, left_y=1, l2=2, right_x=3, right_y=4, r2=5)),
    "dualsense": dict(buttons=dict(south=0, east=1, north=2, west=3, l1=4, r1=5, select=8,
                                   start=9, mode=10, l3=11, r3=12),
                      axes=dict(left_x=0, left_y=1, l2=2, right_x=3, right_y=4, r2=5)),
    "dualsense_hid_generic": dict(buttons=dict(west=0, south=1, east=2, north=3, l1=4, r1=5,
                                               select=8, start=9, l3=10, r3=11, mode=12),
                                  axes=dict(left_x=0, left_y=1, right_x=2, l2=3, r2=4, right_y=5)),
    "xbox": dict(buttons=dict(south=0, east=1, west=2, north=3, l1=4, r1=5, select=6, start=7,
                              mode=8, l3=9, r3=10),
                 axes=dict(left_x=0, left_y=1, l2=2, right_x=3, right_y=4, r2=5)),
}


def test_shipped_layouts():
    assert set(available_layouts()) >= {"dualshock4", "dualsense", "xbox"}
    assert set(available_layouts()) == set(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_shipped_layout_indices(name):
    layout = load_layout(name)
    assert layout.name == name
    assert layout.description and "\n" not in layout.description
    assert "SDL" in layout.verified  # every file says where its indices come from
    assert dict(layout.buttons) == {**EXPECTED[name]["buttons"], **{
        k: v for k, v in layout.buttons.items() if k in ("l2", "r2")}}
    assert {k: v.raw_index for k, v in layout.axes.items()} == EXPECTED[name]["axes"]
    # SDL reports stick up as -1 and triggers resting at -1 on all of them.
    assert layout.axes["left_y"].invert and layout.axes["right_y"].invert
    assert not layout.axes["left_x"].invert and not layout.axes["right_x"].invert
    assert layout.axes["l2"].rest == -1.0 and layout.axes["r2"].rest == -1.0
    assert layout.label("south") in ("cross", "A")


def test_stick_up_and_right_read_plus_one():
    layout = load_layout("dualshock4")
    raw_axes = [1.0, -1.0, -1.0, 1.0, -1.0, -1.0]  # right, up, L2 released, right, up, R2 released
    state = layout.state_from_raw(raw_axes, [0] * 13)
    assert state.axis("left_x") == 1.0 and state.axis("left_y") == 1.0
    assert state.axis("right_x") == 1.0 and state.axis("right_y") == 1.0
    assert state.axis("l2") == 0.0 and state.axis("r2") == 0.0
    pulled = layout.state_from_raw([0, 0, 1.0, 0, 0, 0.0], [0] * 13)
    assert pulled.axis("l2") == 1.0 and pulled.axis("r2") == 0.5


def test_cross_is_south_on_a_dualshock_and_a_is_south_on_an_xbox_pad():
    ds4 = load_layout("dualshock4").state_from_raw([0.0] * 6, [1] + [0] * 12)
    xbox = load_layout("xbox").state_from_raw([0.0] * 6, [1] + [0] * 10)
    assert ds4.pressed("south") and xbox.pressed("south")
    square = load_layout("dualshock4").state_from_raw([0.0] * 6, [0, 0, 0, 1] + [0] * 9)
    x_button = load_layout("xbox").state_from_raw([0.0] * 6, [0, 0, 1] + [0] * 8)
    assert square.pressed("west") and x_button.pressed("west")


def test_short_or_broken_raw_input_reads_as_rest():
    layout = load_layout("dualshock4")
    state = layout.state_from_raw([0.5, float("nan")], [1])
    assert state.axis("left_x") == 0.5
    assert state.axis("left_y") == 0.0 and state.axis("l2") == 0.0
    assert state.pressed("south") and not state.pressed("r3")
    assert layout.state_from_raw([], [], connected=False).connected is False


def test_raw_from_state_has_the_pads_raw_shape():
    layout = load_layout("xbox")
    axes, buttons = layout.raw_from_state(PadState())
    assert axes == [0.0, 0.0, -1.0, 0.0, 0.0, -1.0]   # triggers rest at -1 in raw units
    assert buttons == [0] * 11
    axes, buttons = layout.raw_from_state(PadState({"left_y": 1.0, "r2": 1.0}, {"north": True}))
    assert axes[1] == -1.0 and axes[5] == 1.0 and buttons[3] == 1


raw_axis = st.floats(min_value=-1.0, max_value=1.0)


@pytest.mark.parametrize("name", sorted(EXPECTED))
@given(data=st.data())
def test_raw_round_trip(name, data):
    layout = load_layout(name)
    raw_axes = data.draw(st.lists(raw_axis, min_size=layout.num_axes, max_size=layout.num_axes))
    raw_buttons = data.draw(st.lists(st.integers(0, 1), min_size=layout.num_buttons,
                                     max_size=layout.num_buttons))
    axes, buttons = layout.raw_from_state(layout.state_from_raw(raw_axes, raw_buttons))
    mapped_axes = {a.raw_index for a in layout.axes.values()}
    mapped_buttons = set(layout.buttons.values())
    for i, value in enumerate(raw_axes):
        if i in mapped_axes:
            assert axes[i] == pytest.approx(value, abs=1e-12)
    for i, value in enumerate(raw_buttons):
        if i in mapped_buttons:
            assert buttons[i] == value


@given(st.dictionaries(st.sampled_from(AXES), raw_axis), st.sets(st.sampled_from(BUTTONS)))
def test_state_round_trip(axes, pressed):
    axes = {k: abs(v) if k in ("l2", "r2") else v for k, v in axes.items()}
    layout = load_layout("dualshock4")
    state = PadState(axes, {b: True for b in pressed})
    again = layout.state_from_raw(*layout.raw_from_state(state))
    for name in AXES:
        assert again.axis(name) == pytest.approx(state.axis(name), abs=1e-12)
    assert {b for b in BUTTONS if again.pressed(b)} == pressed


# ------------------------------------------------------------------ errors

def _one_line(exc: pytest.ExceptionInfo) -> str:
    message = str(exc.value)
    assert "\n" not in message, message
    return message


def test_unknown_name_lists_the_layouts():
    with pytest.raises(GamepadError) as info:
        load_layout("ps4")
    message = _one_line(info)
    assert "'ps4'" in message
    for name in ("dualshock4", "dualsense", "xbox"):
        assert name in message


def test_missing_file():
    with pytest.raises(GamepadError) as info:
        load_layout("/nonexistent/pad.yaml")
    assert "/nonexistent/pad.yaml" in _one_line(info)


def _write(tmp_path, text: str):
    path = tmp_path / "mypad.yaml"
    path.write_text(textwrap.dedent(text))
    return path


def _good() -> dict:
    return yaml.safe_load((LAYOUT_DIR / "dualshock4.yaml").read_text())


def test_own_layout_file_by_path(tmp_path):
    data = _good()
    data["name"] = "mypad"
    data["buttons"] = {"south": 1, "east": 2, "west": 0, "north": 3}
    path = tmp_path / "mypad.yaml"
    path.write_text(yaml.safe_dump(data))
    layout = load_layout(str(path))
    assert isinstance(layout, Layout) and layout.name == "mypad"
    assert layout.source == str(path)
    assert layout.state_from_raw([0.0] * 6, [1, 0, 0, 0]).pressed("west")
    assert load_layout(layout) is layout


def test_yaml_syntax_error_names_file_and_line(tmp_path):
    path = _write(tmp_path, """\
        name: broken
        axes: {left_x: {index: 0}
        buttons: {south: 0}
        """)
    with pytest.raises(GamepadError) as info:
        load_layout(str(path))
    message = _one_line(info)
    assert str(path) + ":" in message and "fix the YAML syntax" in message


@pytest.mark.parametrize("change, expected", [
    (lambda d: d.pop("buttons"), "missing key 'buttons'"),
    (lambda d: d.pop("verified"), "missing key 'verified'"),
    (lambda d: d.update(colour="blue"), "unknown key 'colour'"),
    (lambda d: d["buttons"].update(cross=0), "unknown button 'cross'"),
    (lambda d: d["buttons"].pop("north"), "button 'north' is not mapped"),
    (lambda d: d["buttons"].update(east=0), "both use raw index 0"),
    (lambda d: d["buttons"].update(south=-1), "give a raw index"),
    (lambda d: d["buttons"].update(south="0"), "give a raw index"),
    (lambda d: d["axes"].pop("right_y"), "axis 'right_y' is not mapped"),
    (lambda d: d["axes"].update(left_z={"index": 7}), "unknown axis 'left_z'"),
    (lambda d: d["axes"]["left_y"].update(invert="yes"), "write true or false"),
    (lambda d: d["axes"]["l2"].update(rest=1.0), "raw resting value"),
    (lambda d: d["axes"]["l2"].update(scale=2), "unknown key 'scale'"),
    (lambda d: d["axes"].update(right_x={"index": 0}), "both use raw index 0"),
    (lambda d: d.update(axes=[0, 1]), "'axes' must be a mapping"),
])
def test_bad_layout_is_one_line_naming_file_and_fix(tmp_path, change, expected):
    data = _good()
    change(data)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(GamepadError) as info:
        load_layout(str(path))
    message = _one_line(info)
    assert message.startswith(str(path) + ": ")
    assert expected in message
    assert ";" in message  # cause; fix


def test_not_a_mapping(tmp_path):
    path = _write(tmp_path, "- just\n- a list\n")
    with pytest.raises(GamepadError) as info:
        load_layout(str(path))
    assert "expected a mapping" in _one_line(info)


@pytest.mark.parametrize("bad", ["", "   ", None, 3])
def test_layout_argument_must_be_a_name_or_path(bad):
    with pytest.raises(GamepadError) as info:
        load_layout(bad)  # type: ignore[arg-type]
    assert "dualshock4" in _one_line(info)
