"""The virtual pads: driven by code, by raw Joy values, or by a timed YAML script."""

from __future__ import annotations

import textwrap

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hri_teleop.core.gamepad import AXES, BUTTONS, Gamepad, GamepadError, PadState, load_layout
from hri_teleop.hardware.gamepad import open_gamepad
from hri_teleop.sim.virtual_pad import (
    RumbleRecord,
    ScriptedPad,
    ScriptStep,
    VirtualPad,
    load_script,
    parse_script,
)


class FakeClock:
    def __init__(self, now: float = 100.0) -> None:
        self.now = now

    def __call__(self) -> float:
        return self.now


def test_starts_neutral_and_connected():
    pad = VirtualPad()
    assert isinstance(pad, Gamepad)
    assert pad.name == "virtual" and pad.layout.name == "dualshock4"
    assert pad.poll() == PadState.neutral()


def test_driven_by_code():
    pad = VirtualPad("xbox")
    pad.set_axis("left_y", 0.8)
    pad.set_axis("l2", 1.0)
    pad.press("south")
    pad.press("north")
    pad.release("north")
    state = pad.poll()
    assert state.axis("left_y") == 0.8 and state.axis("l2") == 1.0
    assert state.pressed("south") and not state.pressed("north")
    pad.reset()
    assert pad.poll() == PadState.neutral()


@pytest.mark.parametrize("call", [
    lambda p: p.set_axis("left_z", 0.1),
    lambda p: p.set_axis("left_x", 1.2),
    lambda p: p.set_axis("l2", -0.5),
    lambda p: p.set_axis("left_x", float("nan")),
    lambda p: p.press("cross"),
    lambda p: p.release("A"),
])
def test_mistakes_are_one_line_errors(call):
    with pytest.raises(GamepadError) as info:
        call(VirtualPad())
    assert "\n" not in str(info.value)


def test_disconnect_reads_neutral_and_reconnect_restores():
    pad = VirtualPad()
    pad.set_axis("right_x", -0.5)
    pad.disconnect()
    state = pad.poll()
    assert not state.connected and state.axis("right_x") == 0.0
    pad.reconnect()
    assert pad.poll().connected and pad.poll().axis("right_x") == -0.5


def test_set_raw_from_a_joy_message():
    pad = VirtualPad("dualshock4")
    pad.set_raw([0.0, -1.0, -1.0, 0.5, 0.0, 1.0], [0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0])
    state = pad.poll()
    assert state.axis("left_y") == 1.0 and state.axis("right_x") == 0.5
    assert state.axis("r2") == 1.0 and state.axis("l2") == 0.0
    assert state.pressed("east") and not state.pressed("south")


@given(st.dictionaries(st.sampled_from(AXES), st.floats(0.0, 1.0)), st.sets(st.sampled_from(BUTTONS)))
def test_raw_round_trip_through_a_virtual_pad(axes, pressed):
    layout = load_layout("dualsense")
    source = PadState(axes, {b: True for b in pressed})
    pad = VirtualPad(layout)
    pad.set_raw(*layout.raw_from_state(source))
    state = pad.poll()
    assert {b for b in BUTTONS if state.pressed(b)} == pressed
    for name in AXES:
        assert state.axis(name) == pytest.approx(source.axis(name), abs=1e-12)


def test_records_every_rumble_with_the_injected_clock():
    clock = FakeClock(5.0)
    pad = VirtualPad(clock=clock)
    pad.rumble(0.5, 0.1)
    clock.now = 5.02
    pad.rumble(1.7, 0.0)            # clipped
    pad.rumble(float("nan"), 0.1)   # a broken force value never shakes the pad
    pad.disconnect()
    pad.rumble(0.0, 0.1)            # recorded even while unplugged: what the node asked for
    assert pad.rumbles == [RumbleRecord(5.0, 0.5, 0.1), RumbleRecord(5.02, 1.0, 0.0),
                           RumbleRecord(5.02, 0.0, 0.1), RumbleRecord(5.02, 0.0, 0.1)]


@pytest.mark.parametrize("intensity, duration", [("x", 0.1), (None, 0.1), (0.5, -1.0),
                                                 (0.5, float("inf")), (0.5, "1")])
def test_bad_rumble_arguments(intensity, duration):
    with pytest.raises(GamepadError):
        VirtualPad().rumble(intensity, duration)


def test_close_is_idempotent_and_reads_disconnected():
    with VirtualPad() as pad:
        pad.press("south")
    pad.close()
    assert pad.poll() == PadState.neutral(connected=False)


# ------------------------------------------------------------------ scripts

SCRIPT = """\
description: push, grip, unplug, replug
steps:
  - {t: 0.5, axis: left_y, value: 0.8}
  - {t: 1.0, press: south}
  - {t: 2.0, release: south}
  - {t: 2.0, press: [north, l1]}
  - {t: 3.0, disconnect: true}
  - {t: 4.0, reconnect: true}
  - {t: 4.0, axis: left_y, value: 0}
"""


def _script(tmp_path, text: str = SCRIPT):
    path = tmp_path / "pad_script.yaml"
    path.write_text(textwrap.dedent(text))
    return path


def test_load_script(tmp_path):
    steps = load_script(_script(tmp_path))
    assert steps[0] == ScriptStep(0.5, "axis", ("left_y",), 0.8)
    assert steps[3] == ScriptStep(2.0, "press", ("north", "l1"))
    assert steps[4] == ScriptStep(3.0, "disconnect")
    assert len(steps) == 7


def test_a_plain_list_is_a_script_too():
    steps = parse_script([{"t": 0, "press": "east"}])
    assert steps == [ScriptStep(0.0, "press", ("east",))]


def test_scripted_pad_replays_on_its_clock(tmp_path):
    clock = FakeClock(50.0)
    pad = ScriptedPad(_script(tmp_path), clock=clock)
    assert pad.poll() == PadState.neutral()          # time zero = first poll
    clock.now = 50.49
    assert pad.poll().axis("left_y") == 0.0
    clock.now = 50.5
    assert pad.poll().axis("left_y") == 0.8
    clock.now = 51.5
    assert pad.poll().pressed("south")
    clock.now = 52.0
    state = pad.poll()
    assert not state.pressed("south") and state.pressed("north") and state.pressed("l1")
    clock.now = 53.0
    assert not pad.poll().connected
    assert not pad.finished
    clock.now = 54.0
    state = pad.poll()
    assert state.connected and state.axis("left_y") == 0.0 and state.pressed("north")
    assert pad.finished
    pad.rumble(0.3, 0.02)
    assert pad.rumbles == [RumbleRecord(54.0, 0.3, 0.02)]


def test_on_ros_time_the_script_starts_when_time_begins_not_at_zero(tmp_path):
    """Under /use_sim_time rospy reads 0 until the first /clock (the grader's starts at 1 s): before this, a
    script started at 0 had its first second gone when the clock began, and Ex. 10's drive moved the hand half
    as far under the grader's clock as in real time."""
    clock = FakeClock(0.0)
    pad = ScriptedPad(_script(tmp_path), clock=clock, time_begins_after_zero=True)
    assert pad.poll() == PadState.neutral()          # time has not begun
    clock.now = 1.0
    assert pad.poll().axis("left_y") == 0.0          # time zero = first poll that reads a time
    clock.now = 1.49
    assert pad.poll().axis("left_y") == 0.0
    clock.now = 1.5
    assert pad.poll().axis("left_y") == 0.8
    plain = ScriptedPad(_script(tmp_path), clock=FakeClock(0.0))
    plain.poll()                                     # a clock that starts at 0 starts the script at 0
    plain._clock.now = 0.5
    assert plain.poll().axis("left_y") == 0.8


def test_a_pad_opened_on_ros_time_waits_for_time_to_begin(tmp_path, monkeypatch):
    import sys
    import types

    monkeypatch.setitem(sys.modules, "rospy", types.SimpleNamespace(get_time=lambda: 0.0))  # ROS time not begun
    monkeypatch.setenv("HRI_PAD_CLOCK", "ros")
    assert open_gamepad("virtual", script=_script(tmp_path)).time_begins_after_zero
    assert not open_gamepad("virtual", script=_script(tmp_path), clock=FakeClock(0.0)).time_begins_after_zero
    monkeypatch.delenv("HRI_PAD_CLOCK")
    assert not open_gamepad("virtual", script=_script(tmp_path)).time_begins_after_zero


def test_advance_by_hand():
    pad = ScriptedPad(parse_script([{"t": 1, "press": "west"}, {"t": 2, "release": "west"}]))
    assert pad.advance(0.5) == 0
    assert pad.advance(1.0) == 1
    assert pad.poll().pressed("west")     # poll's own clock (elapsed ~0) applies nothing more
    assert pad.advance(10.0) == 1 and pad.finished
    assert not pad.poll().pressed("west")


def test_open_gamepad_virtual_and_scripted(tmp_path):
    assert type(open_gamepad("virtual", "xbox")) is VirtualPad
    pad = open_gamepad("virtual", "xbox", script=_script(tmp_path))
    assert isinstance(pad, ScriptedPad) and pad.layout.name == "xbox"
    with pytest.raises(GamepadError, match="needs a script"):
        open_gamepad("scripted")
    with pytest.raises(GamepadError, match="unknown pad kind 'joystick'.*'pygame'.*'virtual'"):
        open_gamepad("joystick")
    with pytest.raises(GamepadError, match="only drives the virtual pad"):
        open_gamepad("pygame", script=_script(tmp_path))


@pytest.mark.parametrize("text, expected", [
    ("- {t: 1, press: cross}\n", "step 1: unknown button 'cross'"),
    ("- {t: 1, press: south}\n- {t: 0.5, release: south}\n", "step 2: t=0.5 comes before"),
    ("- {t: -1, press: south}\n", "step 1: t is -1"),
    ("- {press: south}\n", "step 1: t is None"),
    ("- {t: 1}\n", "step 1: found no action"),
    ("- {t: 1, press: south, release: east}\n", "step 1: found press and release"),
    ("- {t: 1, axis: left_y}\n", "step 1: axis left_y value is None"),
    ("- {t: 1, axis: left_y, value: 2}\n", "step 1: axis left_y value is 2"),
    ("- {t: 1, axis: r2, value: -0.5}\n", "give a number in 0..1"),
    ("- {t: 1, axis: stick, value: 0.5}\n", "step 1: unknown axis 'stick'"),
    ("- {t: 1, press: south, value: 1}\n", "'value' belongs to an axis step"),
    ("- {t: 1, disconnect: yes please}\n", "write 'disconnect: true'"),
    ("- {t: 1, presss: south}\n", "step 1: unknown key 'presss'"),
    ("- {t: 1, press: []}\n", "give a button name or a list"),
    ("- just text\n", "step 1: expected a mapping"),
    ("{}\n", "expected a non-empty list of steps"),
    ("steps: []\nloop: true\n", "unknown key 'loop'"),
    ("- {t: 1, press: south\n", "fix the YAML syntax"),
])
def test_script_errors_name_file_step_and_fix(tmp_path, text, expected):
    path = _script(tmp_path, text)
    with pytest.raises(GamepadError) as info:
        load_script(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(str(path))
    assert expected in message
    assert ";" in message


def test_missing_script_file(tmp_path):
    with pytest.raises(GamepadError, match="pad script not found: .*nope.yaml"):
        ScriptedPad(tmp_path / "nope.yaml")


def test_a_scripted_read_failure_makes_poll_raise_until_it_recovers():
    now = [0.0]
    pad = ScriptedPad(parse_script([{"t": 1.0, "fail": True}, {"t": 2.0, "recover": True}]), clock=lambda: now[0])
    assert pad.poll().connected
    now[0] = 1.5
    with pytest.raises(GamepadError, match="reading failed"):
        pad.poll()
    now[0] = 2.5
    assert pad.poll().connected


# --------------------------------------------------------------------------- the simulated operator


class TickClock:
    """The teleoperation node's clock for a scripted pad: ticks of 20 ms."""

    def __init__(self) -> None:
        self.ticks = 0

    def __call__(self) -> float:
        return self.ticks * 0.02


def _run_ticks(pad, clock, ticks, rumble_after=None, level=1.0):
    """Poll once per tick; from tick ``rumble_after`` on the node makes the pad rumble."""
    held = []
    for _ in range(ticks):
        state = pad.poll()
        held.append(state.pressed("south"))
        if rumble_after is not None and clock.ticks >= rumble_after:
            pad.rumble(level, 0.5)
        clock.ticks += 1
    return held


def test_a_tap_holds_the_button_for_exactly_its_hold_time_in_ticks():
    clock = TickClock()
    pad = ScriptedPad(parse_script([{"t": 0.1, "tap": "south", "hold": 0.04}]), clock=clock)
    held = _run_ticks(pad, clock, 12)
    assert held == [False] * 5 + [True, True] + [False] * 5
    assert pad.finished and pad.taps == 1


def test_repeated_taps_stop_when_the_pad_rumbles_above_the_level_and_later_steps_shift():
    clock = TickClock()
    steps = parse_script([
        {"t": 0.0, "tap": "south", "hold": 0.04, "every": 0.2, "until": "rumble", "above": 0.5},
        {"t": 0.1, "press": "west"},   # 0.1 s of script time after the taps end
    ])
    pad = ScriptedPad(steps, clock=clock)
    held, west_at = [], None
    for _ in range(80):
        state = pad.poll()
        held.append(state.pressed("south"))
        if west_at is None and state.pressed("west"):
            west_at = clock.ticks
        if clock.ticks >= 45:  # the node starts rumbling at tick 45 (0.9 s)
            pad.rumble(0.8, 0.5)
        clock.ticks += 1
    presses = [i for i in range(1, len(held)) if held[i] and not held[i - 1]] + ([0] if held[0] else [])
    assert sorted(presses) == [0, 10, 20, 30, 40]  # every 0.2 s until the rumble is felt
    assert sum(held) == 5 * 2  # two ticks each
    # The tap decision at tick 50 feels the rumble: the wait ends after 1.0 s, and the
    # press written 0.1 s after the taps' start happens 1.0 s + 0.1 s after it.
    assert pad.waited == [(1, pytest.approx(1.0))]
    assert west_at == 55
    assert pad.timed_out == []


def test_a_rumble_below_the_level_does_not_end_the_taps():
    clock = TickClock()
    pad = ScriptedPad(parse_script([
        {"t": 0.0, "tap": "south", "hold": 0.02, "every": 0.1, "until": "rumble", "above": 0.9, "max_wait": 1.0},
    ]), clock=clock)
    held = _run_ticks(pad, clock, 70, rumble_after=0, level=0.5)
    assert sum(held) == 10  # taps at 0, 0.1, ... 0.9 s: ten, then max_wait gives up
    assert pad.timed_out == [(1, pytest.approx(1.0))] and pad.waited == []
    assert pad.finished


def test_when_waits_for_the_rumble_then_acts():
    clock = TickClock()
    pad = ScriptedPad(parse_script([
        {"t": 0.0, "press": "south"},
        {"t": 0.2, "release": "south", "when": "rumble"},
    ]), clock=clock)
    held = _run_ticks(pad, clock, 40, rumble_after=25)
    assert held.index(False) == 26  # released at the first poll after the rumble began
    assert pad.waited == [(2, pytest.approx(0.32))]


def test_when_gives_up_after_max_wait_and_goes_on():
    clock = TickClock()
    pad = ScriptedPad(parse_script([
        {"t": 0.0, "press": "south"},
        {"t": 0.2, "release": "south", "when": "rumble", "max_wait": 0.5},
    ]), clock=clock)
    held = _run_ticks(pad, clock, 60)
    assert held.index(False) == 35  # 0.2 s + 0.5 s
    assert pad.timed_out == [(2, pytest.approx(0.5))]


def test_rumble_level_follows_the_requests_and_their_duration():
    clock = FakeClock(10.0)
    pad = ScriptedPad(parse_script([{"t": 0.0, "press": "south"}]), clock=clock)
    assert pad.rumble_level() == 0.0
    pad.rumble(0.7, 0.5)
    assert pad.rumble_level(10.2) == pytest.approx(0.7)
    assert pad.rumble_level(10.6) == 0.0  # expired
    pad.rumble(0.0, 0.0)
    assert pad.rumble_level(10.1) == 0.0


def test_a_rumble_of_duration_zero_lasts_until_the_next_request():
    """The Gamepad protocol: duration 0 s means until the next call (the students' node asks so)."""
    clock = FakeClock(10.0)
    pad = ScriptedPad(parse_script([{"t": 0.0, "press": "south"}]), clock=clock)
    pad.rumble(0.9, 0.0)
    assert pad.rumble_level(10.0) == pytest.approx(0.9)
    assert pad.rumble_level(15.0) == pytest.approx(0.9)
    clock.now = 16.0
    pad.rumble(0.0, 0.0)
    assert pad.rumble_level(16.5) == 0.0


@pytest.mark.parametrize("step, expected", [
    ({"t": 0, "press": "south", "hold": 0.1}, "'hold' belongs to a tap step"),
    ({"t": 0, "tap": "south", "until": "rumble"}, "'until' belongs to a repeated tap"),
    ({"t": 0, "tap": "south", "every": 0.5}, "a repeated tap needs 'until'"),
    ({"t": 0, "tap": "south", "hold": 0.5, "every": 0.4, "until": "rumble"}, "longer than hold"),
    ({"t": 0, "release": "south", "when": "force"}, "the condition is 'rumble'"),
    ({"t": 0, "release": "south", "when": "rumble", "above": 1.0}, "above is 1.0"),
    ({"t": 0, "release": "south", "above": 0.5}, "'above' without a condition"),
    ({"t": 0, "release": "south", "when": "rumble", "max_wait": 0}, "max_wait is 0"),
])
def test_operator_step_mistakes_are_one_line_errors(step, expected):
    with pytest.raises(GamepadError) as info:
        parse_script([step], "op.yaml")
    message = str(info.value)
    assert expected in message and message.startswith("op.yaml: step 1:") and "\n" not in message


def test_a_scenario_mapping_may_carry_a_world_section_for_the_simulation():
    steps = parse_script({"description": "d", "world": {"object": "egg"}, "steps": [{"t": 0, "press": "south"}]})
    assert steps[0].action == "press"
