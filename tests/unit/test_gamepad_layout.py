"""Layout files: raw SDL indices <-> positional names, and the errors a bad file gives."""

from __future__ import annotations

import importlib.resources
import math
import textwrap
from pathlib import Path

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
from hri_teleop.core.gamepad import layout as layout_module
from hri_teleop.core.gamepad.layout import AxisMap, as_layout, layout_from_dict

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


# ------------------------------------------------------------------ a layout built from a dict, edge by edge

SHIPPED = "dualsense, dualsense_hid_generic, dualshock4, xbox"


def _minimal(**changes) -> dict:
    data = {"name": "mine", "description": "a pad", "verified": "by hand",
            "axes": {"left_x": {"index": 0}, "left_y": {"index": 1}, "right_x": {"index": 2}, "right_y": {"index": 3}},
            "buttons": {"south": 0, "east": 1, "west": 2, "north": 3}}
    data.update(changes)
    return data


def _refusal(data) -> str:
    with pytest.raises(GamepadError) as info:
        layout_from_dict(data)
    return _one_line(info)


def test_a_layout_from_a_dict_has_no_source_and_its_errors_name_the_dict():
    assert layout_from_dict(_minimal()).source is None
    assert layout_from_dict(_minimal(), "pads/mine.yaml").source == "pads/mine.yaml"
    assert _refusal(_minimal(description="")) == \
        "<dict>: missing key 'description'; add it (see hri_teleop/core/gamepad/layouts/dualshock4.yaml)"
    assert _refusal(_minimal(name=None)) == \
        "<dict>: missing key 'name'; add it (see hri_teleop/core/gamepad/layouts/dualshock4.yaml)"


def test_an_axis_may_be_written_as_its_bare_index():
    layout = layout_from_dict(_minimal(axes={"left_x": 0, "left_y": {"index": 1, "invert": True}, "right_x": 2,
                                             "right_y": 3}))
    assert layout.axes["left_x"] == AxisMap(0, False, 0.0) and layout.axes["right_x"].raw_index == 2
    assert layout.axes["left_y"] == AxisMap(1, True, 0.0)


def test_an_axis_without_an_index_is_refused_with_the_form_to_write():
    axes = dict(_minimal()["axes"], left_x={"invert": True})
    assert _refusal(_minimal(axes=axes)) == "<dict>: axis 'left_x' is {'invert': True}; write it as {index: N, invert: false}"


def test_a_negative_index_is_refused_naming_the_axis_or_button():
    axes = dict(_minimal()["axes"], left_y={"index": -1})
    assert _refusal(_minimal(axes=axes)) == "<dict>: axis 'left_y' index is -1; give a raw index, an integer >= 0"
    buttons = dict(_minimal()["buttons"], east=-1)
    assert _refusal(_minimal(buttons=buttons)) == "<dict>: button 'east' is -1; give a raw index, an integer >= 0"


def test_a_rest_from_minus_1_up_to_below_1_is_accepted():
    for rest in (-1.0, 0.999999):
        axes = dict(_minimal()["axes"], l2={"index": 4, "rest": rest})
        assert layout_from_dict(_minimal(axes=axes)).axes["l2"].rest == rest
    for rest in (-1.000001, 1.0):
        axes = dict(_minimal()["axes"], l2={"index": 4, "rest": rest})
        assert _refusal(_minimal(axes=axes)) == ("<dict>: axis 'l2' rest is %r; give the raw resting value, -1.0 for "
                                                 "a trigger that rests at -1, else 0" % rest)


def test_two_axes_or_two_buttons_on_one_raw_index_are_named_with_the_fix():
    axes = dict(_minimal()["axes"], right_x={"index": 0})
    assert _refusal(_minimal(axes=axes)) == \
        "<dict>: axes 'left_x' and 'right_x' both use raw index 0; give each axis its own index"
    buttons = dict(_minimal()["buttons"], north=1)
    assert _refusal(_minimal(buttons=buttons)) == \
        "<dict>: buttons 'east' and 'north' both use raw index 1; give each button its own index"


@pytest.mark.parametrize("labels", [["cross"], {"south": 1}, {"cross": "x"}])
def test_labels_must_map_positional_names_to_text(labels):
    assert _refusal(_minimal(labels=labels)) == \
        "<dict>: 'labels' must map positional button names to text; write e.g. 'labels: {south: cross}'"


def test_a_button_without_a_label_is_called_by_its_positional_name():
    layout = layout_from_dict(_minimal(labels={"south": "cross"}))
    assert layout.label("south") == "cross" and layout.label("north") == "north"


@pytest.mark.parametrize("text", ["pads/mine", "pads\\mine", "mine.yaml", "mine.yml"])
def test_a_name_with_a_slash_or_a_yaml_suffix_is_a_path(text):
    with pytest.raises(GamepadError) as info:
        load_layout(text)
    assert _one_line(info) == ("layout file not found: %s; check the path or use one of the shipped layouts: %s"
                               % (text, SHIPPED))


def test_a_name_without_is_a_shipped_layouts_name():
    with pytest.raises(GamepadError) as info:
        load_layout("mine")
    assert _one_line(info) == ("unknown gamepad layout 'mine': set layout to one of %s, or to the path of your own "
                               "layout YAML file" % SHIPPED)


@pytest.mark.parametrize("bad, shown", [(3, "3"), ("   ", "'   '"), (None, "None")])
def test_a_layout_that_is_neither_a_name_nor_a_path_is_refused_with_the_choices(bad, shown):
    with pytest.raises(GamepadError) as info:
        load_layout(bad)  # type: ignore[arg-type]
    assert _one_line(info) == ("layout %s is not a name or a path: set layout to one of %s or to a layout YAML file"
                               % (shown, SHIPPED))


def test_a_layout_file_gone_between_the_check_and_the_read_is_named_as_a_layout_file(monkeypatch):
    monkeypatch.setattr(Path, "is_file", lambda _self: True)
    with pytest.raises(GamepadError) as info:
        load_layout("/nonexistent/gone.yaml")
    assert _one_line(info) == "layout file not found: /nonexistent/gone.yaml; check the path"


def test_none_and_auto_are_the_default_layout_anything_else_is_loaded():
    assert as_layout(None).name == "dualshock4" and as_layout(" auto ").name == "dualshock4"
    assert as_layout("xbox").name == "xbox" and as_layout(" xbox ").name == "xbox"


def test_the_shipped_layouts_are_found_beside_the_module_with_or_without_importlib_resources_files(monkeypatch):
    here = (Path(layout_module.__file__).resolve().parent / "layouts").resolve()
    assert layout_module.shipped_layouts_folder().resolve() == here and (here / "dualshock4.yaml").is_file()
    monkeypatch.delattr(importlib.resources, "files", raising=False)  # as on Python 3.8
    assert layout_module.shipped_layouts_folder().resolve() == here


def test_a_layout_converts_and_copies_what_it_is_given_and_cannot_be_changed():
    axes = {"left_x": (0,), "left_y": (1, True), "right_x": AxisMap(2), "right_y": (3, False, 0.5)}
    buttons, labels = {"south": 0, "east": 1, "west": 2, "north": 3}, {"south": "cross"}
    layout = Layout("mine", "a pad", axes, buttons, labels=labels)
    assert layout.axes["left_x"].rest == 0.0 and layout.axes["left_y"].invert is True
    assert layout.axes["right_y"].rest == 0.5 and layout.axes["right_x"] == AxisMap(2, False, 0.0)
    axes["left_x"], buttons["south"], labels["south"] = (5,), 5, "A"
    assert layout.axes["left_x"].raw_index == 0 and layout.buttons["south"] == 0 and layout.labels["south"] == "cross"
    for mapping in (layout.axes, layout.buttons, layout.labels):
        with pytest.raises(TypeError):
            mapping["south"] = 1  # type: ignore[index]


def test_raw_slots_no_axis_or_button_uses_read_0():
    layout = Layout("gaps", "a pad", {"left_x": AxisMap(0), "left_y": AxisMap(1), "right_x": AxisMap(3),
                                      "right_y": AxisMap(4)}, {"south": 0, "east": 1, "west": 2, "north": 5})
    axes, buttons = layout.raw_from_state(PadState({"left_x": 1.0, "left_y": 1.0, "right_x": 1.0, "right_y": 1.0},
                                                   {b: True for b in ("south", "east", "west", "north")}))
    assert axes == [1.0, 1.0, 0.0, 1.0, 1.0] and buttons == [1, 1, 1, 0, 0, 1]


def test_a_state_is_connected_unless_the_caller_says_otherwise():
    layout = load_layout("dualshock4")
    assert layout.state_from_raw([0.0] * 6, [0] * 13).connected is True


ODD = Layout("odd", "axes at odd rests", {
    "left_x": AxisMap(0, True, 0.0),        # inverted: raw 0 must read 0.0, not -0.0
    "left_y": AxisMap(1, False, 0.5),       # rests at 0.5: raw -1 is 3 times a full push below
    "right_x": AxisMap(2, True, 0.5),       # the same, inverted
    "right_y": AxisMap(3, True, -0.0),      # a rest written -0.0
    "l2": AxisMap(4, True, -1.0),           # an inverted trigger resting at -1
    "r2": AxisMap(5, False, 0.0),           # a trigger resting at 0
}, {"south": 0, "east": 1, "west": 2, "north": 3})


def test_axes_read_within_their_range_and_never_minus_zero_whatever_the_rest():
    state = ODD.state_from_raw([0.0, -1.0, -1.0, 0.0, -1.5, -0.5], [0] * 4)
    assert (state.axis("left_x"), state.axis("left_y"), state.axis("right_x")) == (0.0, -1.0, 1.0)
    assert math.copysign(1.0, state.axis("left_x")) == 1.0
    assert state.axis("l2") == 0.0 and state.axis("r2") == 0.0  # below their rest: released


def test_raw_axes_are_clipped_to_minus_1_to_1_and_never_minus_zero():
    axes, _buttons = ODD.raw_from_state(PadState({"l2": 1.0}))
    assert axes[4] == -1.0  # -(1.0) * 2 - 1 = -3: clipped
    assert axes[3] == 0.0 and math.copysign(1.0, axes[3]) == 1.0
