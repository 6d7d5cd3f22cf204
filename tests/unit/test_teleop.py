"""TeleopController: handout Ex. 8 rules, pad loss, quitting, rumble, and limits for any input."""

from __future__ import annotations

import math
from typing import Dict, List, Optional

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from hri_teleop.core.gamepad import AXES, BUTTONS, PadState
from hri_teleop.core.limits import (
    DEFAULT_LIMITS,
    ROBOT_LIMITS,
    ROBOT_PERIOD_S,
    AxisLimits,
    CartesianLimits,
    LimitsError,
    check_command_rate,
    hold_at_robot_rate,
    limit_violations,
)
from hri_teleop.core.teleop import (
    DEFAULT_AXIS_ASSIGNMENT,
    GRIPPER_MAX_WIDTH_M,
    AxisAssignment,
    Mode,
    TeleopCommand,
    TeleopController,
    TeleopError,
    TeleopParams,
)


def assert_within_limits(limits, twists, dts):
    # limit_violations is checked against an independent implementation in test_limits.py.
    assert limit_violations(limits, twists, dts) == []

DT = 0.02


def pad(axes: Optional[Dict[str, float]] = None, pressed=(), connected: bool = True) -> PadState:
    return PadState(dict(axes or {}), {name: True for name in pressed}, connected)


def run(controller: TeleopController, pads, force=None, age=0.0, dt=DT) -> List[TeleopCommand]:
    return [controller.step(p, force, age, dt) for p in pads]


# --- parameters ------------------------------------------------------------------------


def test_default_params_are_the_handout_lab_values():
    p = TeleopParams()
    assert (p.rate_hz, p.k_trans, p.k_rot, p.k_gripper, p.deadzone) == (50.0, 0.1, 0.3, 0.04, 0.1)
    assert (p.width_min_m, p.width_max_m, p.initial_width_m) == (0.0, 0.08, 0.08)
    assert (p.close_button, p.open_button, p.toggle_button, p.quit_button) == ("south", "east", "north", "west")
    assert p.gripper_step_m == pytest.approx(0.04 / 50)
    assert p.assignment == DEFAULT_AXIS_ASSIGNMENT
    assert GRIPPER_MAX_WIDTH_M == 0.08


def test_default_axis_assignment():
    assert DEFAULT_AXIS_ASSIGNMENT.translation == ("left_y", "-left_x", "right_y")
    assert DEFAULT_AXIS_ASSIGNMENT.rotation == ("left_y", "-left_x", "right_y")
    assert DEFAULT_AXIS_ASSIGNMENT.sources(Mode.TRANSLATION) == (("left_y", 1.0), ("left_x", -1.0), ("right_y", 1.0))


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(rate_hz=0),
        dict(rate_hz=float("nan")),
        dict(k_trans=-0.1),
        dict(k_rot="0.3"),
        dict(k_gripper=True),
        dict(deadzone=1.0),
        dict(deadzone=-0.1),
        dict(width_max_m=0.1),
        dict(width_min_m=0.05, width_max_m=0.04, initial_width_m=0.04),
        dict(initial_width_m=0.09),
        dict(input_timeout_s=0),
        dict(force_timeout_s=-1),
        dict(rumble_threshold=1.5),
        dict(close_button="cross"),
        dict(quit_button="north"),
        dict(assignment=("left_y", "left_x", "right_y")),
    ],
)
def test_bad_params_raise_one_line_errors(kwargs):
    with pytest.raises(TeleopError) as info:
        TeleopParams(**kwargs)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(translation=("left_y", "left_x")),
        dict(translation="left_y"),
        dict(rotation=("left_y", "-stick", "right_y")),
        dict(rotation=("left_y", 3, "right_y")),
    ],
)
def test_bad_axis_assignments_raise(kwargs):
    with pytest.raises(TeleopError) as info:
        AxisAssignment(**kwargs)
    assert "\n" not in str(info.value)


def test_limits_above_the_robot_are_refused():
    with pytest.raises(TeleopError, match="exceed"):
        TeleopController(TeleopParams(), CartesianLimits(AxisLimits(5.0, 1.0, 1.0), DEFAULT_LIMITS.rotation))


@pytest.mark.parametrize("dt", [0.0, -0.02, float("nan"), True])
def test_bad_time_step(dt):
    with pytest.raises(TeleopError):
        TeleopController().step(pad(), None, 0.0, dt)


# --- sticks -> twist ---------------------------------------------------------------------


def test_target_twist_in_translation_uses_gain_dead_zone_and_assignment():
    c = TeleopController(TeleopParams())
    assert c.target_twist(pad({"left_y": 1.0})) == pytest.approx((0.1, 0, 0, 0, 0, 0))
    assert c.target_twist(pad({"left_x": 1.0})) == pytest.approx((0, -0.1, 0, 0, 0, 0))
    assert c.target_twist(pad({"right_y": -1.0})) == pytest.approx((0, 0, -0.1, 0, 0, 0))
    assert c.target_twist(pad({"right_x": 1.0, "l2": 1.0})) == (0.0,) * 6  # unassigned axes
    # Dead zone 0.1, continuous at its edge: 0.05 -> 0, 0.55 -> (0.55 - 0.1) / 0.9 = 0.5.
    assert c.target_twist(pad({"left_y": 0.05})) == (0.0,) * 6
    assert c.target_twist(pad({"left_y": 0.55}))[0] == pytest.approx(0.05)
    assert c.target_twist(None) == (0.0,) * 6
    assert c.target_twist(pad({"left_y": 1.0}, connected=False)) == (0.0,) * 6


def test_target_twist_in_rotation_uses_k_rot():
    c = TeleopController(TeleopParams())
    c.step(pad(pressed=["north"]), None, 0.0, DT)
    assert c.mode is Mode.ROTATION
    assert c.target_twist(pad({"left_y": 1.0, "left_x": -1.0, "right_y": 0.5})) == pytest.approx(
        (0, 0, 0, 0.3, 0.3, 0.3 * (0.4 / 0.9))
    )


def test_custom_assignment_and_gains():
    params = TeleopParams(k_trans=0.2, assignment=AxisAssignment(translation=("none", "right_x", "-left_y")))
    c = TeleopController(params)
    assert c.target_twist(pad({"left_y": 1.0, "right_x": 1.0, "left_x": 1.0})) == pytest.approx((0, 0.2, -0.2, 0, 0, 0))


def test_stick_drives_the_limited_twist_to_the_target():
    c = TeleopController(TeleopParams())
    commands = run(c, [pad({"left_y": 1.0})] * 60)
    assert commands[-1].twist == (0.1, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert commands[0].twist[0] < 0.01  # ramped, not stepped
    assert_within_limits(DEFAULT_LIMITS, [cmd.twist for cmd in commands], [DT] * 60)
    assert not commands[-1].stopping and commands[-1].mode is Mode.TRANSLATION


# --- buttons -----------------------------------------------------------------------------


def test_triangle_toggles_once_per_press():
    c = TeleopController(TeleopParams())
    held = run(c, [pad(pressed=["north"])] * 10)
    assert [cmd.mode for cmd in held] == [Mode.ROTATION] * 10
    run(c, [pad()] * 3)
    assert c.step(pad(pressed=["north"]), None, 0.0, DT).mode is Mode.TRANSLATION


def test_mode_switch_ramps_translation_down_and_rotation_up():
    c = TeleopController(TeleopParams())
    run(c, [pad({"left_y": 1.0})] * 60)
    commands = run(c, [pad({"left_y": 1.0}, pressed=["north"])] + [pad({"left_y": 1.0})] * 80)
    assert commands[-1].twist == (0.0, 0.0, 0.0, 0.3, 0.0, 0.0)
    assert commands[0].twist[0] > 0.09  # not stepped to zero


def test_cross_closes_and_circle_opens_by_k_gripper_over_rate_per_tick():
    c = TeleopController(TeleopParams())
    step = 0.04 / 50
    commands = run(c, [pad(pressed=["south"])] * 10)
    assert commands[-1].gripper_width_m == pytest.approx(0.08 - 10 * step)
    commands = run(c, [pad(pressed=["east"])] * 4)
    assert commands[-1].gripper_width_m == pytest.approx(0.08 - 6 * step)
    both = c.step(pad(pressed=["south", "east"]), None, 0.0, DT)
    assert both.gripper_width_m == pytest.approx(0.08 - 6 * step)
    released = run(c, [pad()] * 5)
    assert released[-1].gripper_width_m == pytest.approx(0.08 - 6 * step)


def test_gripper_width_is_clamped():
    c = TeleopController(TeleopParams())
    assert run(c, [pad(pressed=["east"])] * 5)[-1].gripper_width_m == 0.08
    closed = run(c, [pad(pressed=["south"])] * 200)
    assert closed[-1].gripper_width_m == 0.0
    assert min(cmd.gripper_width_m for cmd in closed) == 0.0


def test_square_quits_for_good_and_ramps_to_exact_zero():
    c = TeleopController(TeleopParams())
    run(c, [pad({"left_y": 1.0, "right_y": 1.0})] * 60)
    width = c.gripper_width_m
    pads = [pad({"left_y": 1.0}, pressed=["west"])] + [pad({"left_y": 1.0}, pressed=["south", "north"])] * 80
    commands = run(c, pads)
    assert all(cmd.quit and cmd.stopping for cmd in commands)
    assert all(cmd.mode is Mode.TRANSLATION for cmd in commands)  # input ignored after quit
    assert all(cmd.gripper_width_m == width for cmd in commands)
    assert commands[0].twist[0] > 0.09  # ramped, not stepped
    assert commands[-1].twist == (0.0,) * 6
    assert c.finished and c.quit


def test_finished_only_after_quit():
    c = TeleopController(TeleopParams())
    run(c, [pad()] * 5)
    assert not c.finished
    c.step(pad(pressed=["west"]), None, 0.0, DT)
    assert c.finished  # at rest already


# --- pad loss --------------------------------------------------------------------------


@pytest.mark.parametrize("lost", [None, pad({"left_y": 1.0}, connected=False)])
def test_lost_pad_ramps_to_zero_and_recovers(lost):
    c = TeleopController(TeleopParams())
    before = run(c, [pad({"left_y": 1.0})] * 60)
    during = run(c, [lost] * 60, force=1.0)
    assert all(cmd.stopping and not cmd.quit for cmd in during)
    assert all(cmd.rumble == 0.0 for cmd in during)
    assert during[0].twist[0] > 0.09
    assert during[-1].twist == (0.0,) * 6
    after = run(c, [pad({"left_y": 1.0})] * 60)
    assert after[-1].twist[0] == 0.1 and not after[-1].stopping
    assert_within_limits(DEFAULT_LIMITS, [cmd.twist for cmd in before + during + after], [DT] * 180)


def test_buttons_do_nothing_while_disconnected():
    c = TeleopController(TeleopParams())
    command = c.step(pad(pressed=["south", "north", "west"], connected=False), None, 0.0, DT)
    assert command.gripper_width_m == 0.08 and command.mode is Mode.TRANSLATION and not command.quit


# --- rumble -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "force, age, threshold, expected",
    [
        (0.5, 0.1, 0.0, 0.5),
        (0.0, 0.1, 0.0, 0.0),
        (1.7, 0.1, 0.0, 1.0),
        (-0.2, 0.1, 0.0, 0.0),
        (0.5, 1.0, 0.0, 0.5),  # exactly at the (1 s) timeout: still fresh
        (0.5, 1.01, 0.0, 0.0),  # stale
        (0.5, float("inf"), 0.0, 0.0),
        (0.5, float("nan"), 0.0, 0.0),
        (float("nan"), 0.1, 0.0, 0.0),
        (None, 0.0, 0.0, 0.0),
        (0.05, 0.1, 0.1, 0.0),  # below threshold
        (0.2, 0.1, 0.1, 0.2),
    ],
)
def test_rumble(force, age, threshold, expected):
    c = TeleopController(TeleopParams(rumble_threshold=threshold))
    assert c.step(pad(), force, age, DT).rumble == pytest.approx(expected)


def test_rumble_stops_when_quitting():
    c = TeleopController(TeleopParams())
    assert c.step(pad(pressed=["west"]), 0.8, 0.0, DT).rumble == 0.0


@pytest.mark.parametrize("force, expected", [(0.009, 0.0), (0.01, 0.0), (0.011, 0.011)])
def test_the_pad_rumbles_only_above_the_default_threshold_of_0_01(force, expected):
    c = TeleopController(TeleopParams())
    assert c.step(pad(), force, 0.0, DT).rumble == expected
    assert c.rumble_for(force, 0.0) == expected


@pytest.mark.parametrize("age, expected", [(0.99, 0.5), (1.0, 0.5), (1.01, 0.0)])
def test_a_force_older_than_1_s_gives_no_rumble(age, expected):
    assert TeleopController(TeleopParams()).rumble_for(0.5, age) == expected


def test_a_force_between_ticks_rumbles_like_at_a_tick_once_the_node_runs():
    c = TeleopController(TeleopParams())
    assert c.rumble_between_ticks(0.8, 0.0) == 0.0  # before the first tick: a node not yet running is silent
    c.step(pad(), None, 0.0, DT)
    assert c.rumble_between_ticks(0.8, 0.0) == 0.8
    assert c.rumble_between_ticks(0.01, 0.0) == 0.0 and c.rumble_between_ticks(0.011, 0.0) == 0.011  # threshold
    assert c.rumble_between_ticks(0.8, 1.01) == 0.0 and c.rumble_between_ticks(None, 0.0) == 0.0  # stale, none
    assert c.rumble_between_ticks(1.7, 0.0) == 1.0


@pytest.mark.parametrize("lost", [None, pad(connected=False)])
def test_no_rumble_between_ticks_while_stopping_for_a_lost_pad_until_it_is_back(lost):
    c = TeleopController(TeleopParams())
    c.step(pad(), 0.8, 0.0, DT)
    c.step(lost, 0.8, 0.0, DT)
    assert c.rumble_between_ticks(0.8, 0.0) == 0.0
    c.step(pad(), 0.8, 0.0, DT)
    assert c.rumble_between_ticks(0.8, 0.0) == 0.8


def test_no_rumble_between_ticks_after_quitting():
    c = TeleopController(TeleopParams())
    c.step(pad(), 0.8, 0.0, DT)
    c.step(pad(pressed=["west"]), 0.8, 0.0, DT)
    assert c.rumble_between_ticks(0.8, 0.0) == 0.0
    c.step(pad(), 0.8, 0.0, DT)  # quitting is for good
    assert c.rumble_between_ticks(0.8, 0.0) == 0.0


def test_with_feedback_off_nothing_rumbles_between_ticks_either():
    c = TeleopController(TeleopParams(feedback=False))
    c.step(pad(), 0.8, 0.0, DT)
    assert c.rumble_between_ticks(0.8, 0.0) == 0.0


# --- properties ---------------------------------------------------------------------------

stick = st.floats(min_value=-1.0, max_value=1.0)
trigger = st.floats(min_value=0.0, max_value=1.0)
pad_states = st.builds(
    PadState,
    st.fixed_dictionaries({name: (trigger if name in ("l2", "r2") else stick) for name in AXES}),
    st.dictionaries(st.sampled_from(BUTTONS), st.booleans()),
    st.booleans(),
)
pads = st.one_of(st.none(), pad_states, pad_states, pad_states)
forces = st.one_of(st.none(), st.floats(allow_nan=True, allow_infinity=True), st.floats(min_value=0.0, max_value=1.0))
params = st.builds(
    TeleopParams,
    rate_hz=st.floats(min_value=5.0, max_value=500.0),
    k_trans=st.floats(min_value=0.0, max_value=3.0),  # above the limits too: the limiter must cut it
    k_rot=st.floats(min_value=0.0, max_value=5.0),
    k_gripper=st.floats(min_value=0.0, max_value=1.0),
    deadzone=st.floats(min_value=0.0, max_value=0.9),
    rumble_threshold=st.floats(min_value=0.0, max_value=1.0),
    assignment=st.builds(
        AxisAssignment,
        st.tuples(*[st.sampled_from(["left_x", "-left_y", "right_x", "-right_y", "l2", "none"])] * 3),
        st.tuples(*[st.sampled_from(["-left_x", "left_y", "-right_x", "right_y", "-r2", "none"])] * 3),
    ),
)
# Limits the robot accepts at some command rate up to 500 Hz (a_max / rate <= its 1 ms budget);
# the Panda's own limits would need 2 kHz, so they are refused (tested below).
limits = st.sampled_from([DEFAULT_LIMITS, CartesianLimits(AxisLimits(0.1, 0.2, 1.0), AxisLimits(0.2, 0.4, 2.0)),
                          CartesianLimits(AxisLimits(1.0, 3.0, 50.0), AxisLimits(1.5, 5.0, 100.0))])


@settings(max_examples=120, deadline=None)
@given(
    p=params,
    lim=limits,
    ticks=st.lists(
        st.tuples(pads, forces, st.floats(min_value=0.0, max_value=2.0), st.floats(min_value=0.002, max_value=0.1)),
        min_size=1,
        max_size=60,
    ),
)
def test_random_pad_input_keeps_every_command_inside_the_limits(p, lim, ticks):
    assume(_rate_accepted(lim, p.rate_hz))
    c = TeleopController(p, lim)
    commands = [c.step(pad_state, force, age, dt) for pad_state, force, age, dt in ticks]
    assert_within_limits(lim, [cmd.twist for cmd in commands], [dt for *_, dt in ticks])
    quit_seen = False
    for (pad_state, *_), cmd in zip(ticks, commands):
        assert p.width_min_m <= cmd.gripper_width_m <= p.width_max_m
        assert 0.0 <= cmd.rumble <= 1.0 and not math.isnan(cmd.rumble)
        assert cmd.quit or not quit_seen  # quit never un-sets
        quit_seen = cmd.quit
        if pad_state is None or not pad_state.connected or cmd.quit:
            assert cmd.stopping and cmd.rumble == 0.0
        assert isinstance(cmd.mode, Mode)


def _rate_accepted(lim, rate_hz):
    try:
        check_command_rate(lim, rate_hz)
    except LimitsError:
        return False
    return True


@settings(max_examples=80, deadline=None)
@given(
    p=params,
    lim=limits,
    pads_seq=st.lists(pads, min_size=1, max_size=80),
)
def test_held_at_1_khz_the_commands_stay_inside_the_pandas_limits(p, lim, pads_seq):
    """What the robot sees: each command held for 1 ms cycles until the next one."""
    assume(_rate_accepted(lim, p.rate_hz))
    c = TeleopController(p, lim)
    twists = [c.step(pad_state, None, 0.0, 1.0 / p.rate_hz).twist for pad_state in pads_seq]
    twists += [c.step(None, None, 0.0, 1.0 / p.rate_hz).twist for _ in range(int(3 * p.rate_hz))]  # pad lost
    held = hold_at_robot_rate(twists, p.rate_hz)
    dt = 1.0 / (p.rate_hz * round(len(held) / len(twists)))  # the hold's actual cycle
    assert limit_violations(ROBOT_LIMITS, held, [max(dt, ROBOT_PERIOD_S)] * len(held), rel_tol=1e-6) == []


def test_the_pandas_own_limits_at_50_hz_are_refused_with_the_fix():
    with pytest.raises(TeleopError) as info:
        TeleopController(TeleopParams(rate_hz=50.0), ROBOT_LIMITS)
    message = str(info.value)
    assert "\n" not in message
    assert "limits.translation.acceleration" in message and "raise rate" in message


def test_default_limits_need_at_least_about_46_hz():
    TeleopController(TeleopParams(rate_hz=50.0), DEFAULT_LIMITS)
    with pytest.raises(TeleopError, match="rate"):
        TeleopController(TeleopParams(rate_hz=40.0), DEFAULT_LIMITS)


def test_with_a_deadman_button_the_sticks_move_the_arm_only_while_it_is_held():
    c = TeleopController(TeleopParams(deadman_button="l1"))
    released = PadState({"left_y": 1.0}, {}, True)
    held = PadState({"left_y": 1.0}, {"l1": True}, True)
    assert c.target_twist(released) == (0.0,) * 6
    assert c.target_twist(held)[0] == pytest.approx(TeleopParams().k_trans)


def test_the_deadman_button_must_be_a_free_positional_button():
    with pytest.raises(TeleopError, match="deadman_button"):
        TeleopParams(deadman_button="trigger")
    with pytest.raises(TeleopError, match="different buttons"):
        TeleopParams(deadman_button="south")


def test_with_feedback_off_the_pad_never_rumbles_and_everything_else_is_the_same():
    on, off = TeleopController(TeleopParams()), TeleopController(TeleopParams(feedback=False))
    pad = PadState({**PadState.neutral().axes, "left_y": 0.8}, {**PadState.neutral().buttons, "south": True}, True)
    for _ in range(20):
        a, b = on.step(pad, 0.7, 0.01, 0.02), off.step(pad, 0.7, 0.01, 0.02)
        assert a.rumble == pytest.approx(0.7) and b.rumble == 0.0
        assert (a.twist, a.gripper_width_m, a.mode) == (b.twist, b.gripper_width_m, b.mode)


def test_feedback_must_be_a_bool():
    with pytest.raises(TeleopError, match="feedback must be true or false"):
        TeleopParams(feedback="false")


# --- the small rules around the controller (issue 44: each pinned by its behaviour) --------------------------


def test_an_axes_entry_given_as_one_string_of_three_characters_is_refused_as_not_a_list():
    with pytest.raises(TeleopError, match=r"^axes\.translation must list 3 axes for x, y, z, got 'xyz'; write e\.g\."):
        AxisAssignment(translation="xyz")  # type: ignore[arg-type]


def test_an_unknown_axis_is_named_by_its_mode_and_place():
    with pytest.raises(TeleopError, match=r"^axes\.rotation\[1\] names unknown axis 'up'"):
        AxisAssignment(rotation=("left_y", "up", "right_y"))


def test_a_button_already_down_at_the_first_reading_is_one_press():
    from hri_teleop.core.teleop import ButtonPress

    press = ButtonPress("start")
    assert [press.update(pad(pressed=("start",))) for _ in range(3)] == [True, False, False]
    assert press.update(pad()) is False and press.update(pad(pressed=("start",))) is True


def test_combined_motors_both_carry_the_larger_of_force_and_warning():
    from hri_teleop.core.teleop import motor_rumble

    assert motor_rumble(0.6, 0.2, False, True, "combined") == (0.6, 0.6)
    assert motor_rumble(0.2, 0.6, False, True, "combined") == (0.6, 0.6)
    assert motor_rumble(0.6, 0.2, False, True, "split") == (0.6, 0.2)


def test_recovery_waits_and_says_how_fast_the_node_still_translates_and_turns():
    from hri_teleop.core.teleop import recovery_refusal

    assert recovery_refusal((0.03, 0.04, 0.0, 0.5, 0.0, 0.0)) == (
        "error recovery waits: the node still commands 0.050 m/s and 0.500 rad/s; let go of the sticks, then press "
        "the recover button again (a recovered robot starts from rest)")
    assert recovery_refusal((0.0, 0.0, 0.0, 0.0, 0.3, 0.4)).startswith(
        "error recovery waits: the node still commands 0.000 m/s and 0.500 rad/s;")
    assert recovery_refusal((0.0,) * 6) is None


@pytest.mark.parametrize("changed", [
    {"rate_hz": 0.5}, {"width_min_m": 0.04, "width_max_m": 0.04, "initial_width_m": 0.04}, {"rumble_threshold": 1.0},
    {"initial_width_m": 0.0}, {"gripper_max_width_m": 0.1, "width_max_m": 0.1, "initial_width_m": 0.1},
])
def test_settings_at_the_edge_of_their_range_are_taken(changed):
    params = TeleopParams(**changed)
    assert all(getattr(params, name) == value for name, value in changed.items())


@pytest.mark.parametrize("changed, words", [
    ({"rate_hz": 0.0}, "rate_hz must be > 0 Hz, got 0.0"),
    ({"gripper_max_width_m": 0.0, "width_max_m": 0.0, "initial_width_m": 0.0}, "gripper_max_width_m must be > 0 m"),
    ({"rumble_threshold": 1.01}, "rumble_threshold must be in [0, 1]"),
])
def test_settings_just_past_their_range_are_refused(changed, words):
    with pytest.raises(TeleopError, match="^" + words.replace("[", r"\[").replace("]", r"\]")):
        TeleopParams(**changed)


def test_every_number_setting_is_kept_as_a_float_also_those_after_feedback():
    params = TeleopParams(rate_hz=50, precision_scale=1, gripper_max_width_m=1)
    assert type(params.rate_hz) is float and type(params.precision_scale) is float
    assert type(params.gripper_max_width_m) is float


def test_an_axis_entry_reads_as_its_axis_and_sign_and_none_0_or_empty_as_no_axis():
    assignment = AxisAssignment(translation=("+left_y", "0", ""), rotation=("-left_x", "none", "right_y"))
    assert assignment.sources(Mode.TRANSLATION) == (("left_y", 1.0), (None, 0.0), (None, 0.0))
    assert assignment.sources(Mode.ROTATION) == (("left_x", -1.0), (None, 0.0), ("right_y", 1.0))
    with pytest.raises(TeleopError, match=r"^axes\.translation\[0\] names unknown axis 'Xleft_y'"):
        AxisAssignment(translation=("Xleft_y", "none", "none"))


def test_the_controllers_limits_are_judged_against_the_hard_limits_it_is_given():
    from hri_teleop.core.limits import LAB_LIMITS

    with pytest.raises(TeleopError, match="translation"):  # LAB_LIMITS' 0.3 m/s^2 at 50 Hz is beyond its own 1 ms budget
        TeleopController(TeleopParams(), limits=LAB_LIMITS, hard_limits=LAB_LIMITS)
    narrow = CartesianLimits(AxisLimits(0.2, 13.0, 6500.0), AxisLimits(2.5, 25.0, 12500.0))
    with pytest.raises(TeleopError):
        TeleopController(TeleopParams(), hard_limits=narrow)  # the default 0.25 m/s exceeds 0.2


def test_a_stick_at_rest_on_an_inverted_axis_asks_for_plus_zero_not_minus_zero():
    controller = TeleopController()
    assert math.copysign(1.0, controller.target_twist(pad({"left_x": 0.0}))[1]) == 1.0  # vy <- -left_x
    twist = run(controller, [pad({"left_x": 0.0})])[-1].twist
    assert math.copysign(1.0, twist[1]) == 1.0


def test_the_first_command_does_not_quit_and_says_so_with_false():
    command = run(TeleopController(), [pad()])[-1]
    assert command.quit is False


def test_a_force_that_is_not_a_number_rumbles_nothing():
    controller = TeleopController()
    run(controller, [pad()])
    assert controller.rumble_for("strong", 0.1) == 0.0  # type: ignore[arg-type]
    assert controller.rumble_for(0.5, "old") == 0.0  # type: ignore[arg-type]


def test_the_next_tick_is_one_period_on_unless_the_loop_fell_more_than_a_period_behind():
    from hri_teleop.core.teleop import next_tick_s

    assert next_tick_s(1.0, 1.1, 0.25) == 1.25  # on time
    assert next_tick_s(1.0, 1.5, 0.25) == 1.25  # exactly one period behind: still on its schedule
    assert next_tick_s(1.0, 1.75, 0.25) == 1.75  # more than a period behind: starts again from now
