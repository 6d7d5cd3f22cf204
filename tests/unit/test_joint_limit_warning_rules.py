"""The teleoperation node's joint-limit warning and recover gesture, as core rules.

Joint states by name (/franka_state_controller/joint_states or the merged /joint_states), a
warning that ends when the states go stale, the pad's rumble as the larger of force and
warning, and a recover button that is pressed once per press and is none of the handout's.
"""

from __future__ import annotations

import math

import pytest

from hri_teleop.core.gamepad import PadState
from hri_teleop.core.joints import (
    JOINT_NAMES,
    READY_POSE_RAD,
    ROBOT_JOINT_LIMITS,
    JointLimitWatch,
    JointsError,
    JointStateWarning,
    positions_by_name,
)
from hri_teleop.core.teleop import ButtonPress, TeleopError, TeleopParams, check_extra_button, combined_rumble

FINGERS = ["panda_finger_joint1", "panda_finger_joint2"]
NEAR = tuple(READY_POSE_RAD[:6]) + (ROBOT_JOINT_LIMITS.position_max_rad[6] - 0.05,)  # joint 7 inside 0.1 rad


# --- joint states by name -------------------------------------------------------------------


def test_the_arm_joints_are_picked_by_name_whatever_the_order_and_the_fingers_are_ignored():
    names = FINGERS[:1] + list(reversed(JOINT_NAMES)) + FINGERS[1:]
    positions = [0.04] + list(reversed(READY_POSE_RAD)) + [0.04]
    assert positions_by_name(names, positions) == pytest.approx(READY_POSE_RAD)


@pytest.mark.parametrize("names, positions", [
    (list(JOINT_NAMES[:6]), list(READY_POSE_RAD[:6])),                 # joint 7 missing
    (list(JOINT_NAMES), list(READY_POSE_RAD[:6])),                     # lists of different length
    (list(JOINT_NAMES), list(READY_POSE_RAD[:6]) + [math.nan]),        # not a number
    (FINGERS, [0.04, 0.04]),                                           # the hand's own joint_states
])
def test_an_incomplete_or_broken_joint_state_gives_nothing(names, positions):
    assert positions_by_name(names, positions) is None


# --- the warning ends when the states go stale ------------------------------------------------


def _warning(timeout_s: float = 0.5, pulse_period_s: float = 0.4) -> JointStateWarning:
    return JointStateWarning(JointLimitWatch(rumble_level=0.6, pulse_period_s=pulse_period_s), timeout_s)


def test_a_state_near_a_limit_starts_the_warning_once_with_the_joint_named():
    warning = _warning()
    started = warning.update(NEAR, 10.0)
    assert started is not None and started.joint == 7 and started.side == "max"
    assert "joint 7" in started.describe()
    assert warning.update(NEAR, 10.02) is None  # the same warning goes on
    assert warning.warning is not None


@pytest.mark.parametrize("age_s, warned", [(0.499, True), (0.5, True), (0.501, False)])
def test_the_warning_lasts_while_the_states_are_at_most_the_timeout_old(age_s, warned):
    warning = _warning(0.5, pulse_period_s=10.0)  # the pulse is on from 10 s to 15 s
    warning.update(NEAR, 10.0)
    now = 10.0 + age_s
    assert warning.rumble(now) == (0.6 if warned else 0.0)
    assert warning.expire(now) is False  # rumble() has expired it already, once
    assert (warning.warning is not None) is warned


@pytest.mark.parametrize("age_s, ended", [(0.499, False), (0.5, False), (0.501, True)])
def test_expire_says_once_that_stale_states_ended_the_warning(age_s, ended):
    warning = _warning(0.5)
    warning.update(NEAR, 10.0)
    assert warning.expire(10.0 + age_s) is ended
    assert (warning.warning is None) is ended
    if ended:
        assert warning.expire(11.0) is False  # said once


def test_states_that_come_again_after_going_stale_start_a_new_warning():
    warning = _warning(0.5)
    assert warning.update(NEAR, 10.0) is not None
    assert warning.expire(11.0)
    assert warning.update(NEAR, 11.1) is not None


@pytest.mark.parametrize("start_s", [0.0, 10.3])  # 10.3: in the off half of a pulse counted from 0
def test_the_warning_pulses_at_the_watchs_level_starting_on(start_s):
    warning = _warning()
    warning.update(NEAR, start_s)
    pulse = [warning.rumble(start_s + dt) for dt in (0.0, 0.1, 0.199, 0.201, 0.3, 0.401)]
    assert pulse == [0.6, 0.6, 0.6, 0.0, 0.0, 0.6]


@pytest.mark.parametrize("timeout", [0.0, -1.0, math.inf, "0.5"])
def test_an_unusable_timeout_names_itself(timeout):
    with pytest.raises(JointsError, match="timeout_s must be a positive time"):
        JointStateWarning(JointLimitWatch(), timeout)


# --- the pad's rumble: force and warning ----------------------------------------------------


@pytest.mark.parametrize("force, warning, expected", [
    (0.59, 0.6, 0.6),   # the warning just above the force
    (0.6, 0.6, 0.6),    # equal
    (0.61, 0.6, 0.61),  # the force just above: force feedback still shows
    (0.3, 0.0, 0.3),    # the pulse's off half: the force alone
    (0.0, 0.0, 0.0),
    (1.5, 0.6, 1.0),    # never past 1
    (math.nan, 0.6, 0.6),
])
def test_the_pad_feels_the_larger_of_force_and_warning(force, warning, expected):
    assert combined_rumble(force, warning, stopping=False) == pytest.approx(expected)


def test_a_stopping_controller_makes_the_pad_silent_even_when_warned():
    assert combined_rumble(0.5, 0.6, stopping=True) == 0.0


def test_without_force_feedback_the_pad_stays_silent_even_when_warned():
    """Ex. 14's control condition: feedback false means the pad never rumbles."""
    assert combined_rumble(0.0, 0.6, stopping=False, feedback=False) == 0.0
    assert combined_rumble(0.0, 0.6, stopping=False, feedback=True) == 0.6


# --- the recover button -------------------------------------------------------------------------


def test_the_recover_button_is_options_by_default_and_must_be_free():
    params = TeleopParams()
    assert check_extra_button(params, "start", "recover_button") == "start"
    for taken, role in (("south", "close"), ("east", "open"), ("north", "toggle"), ("west", "quit")):
        with pytest.raises(TeleopError, match=f"recover_button '{taken}' is already the {role} button"):
            check_extra_button(params, taken, "recover_button")
    with pytest.raises(TeleopError, match="already the deadman button"):
        check_extra_button(TeleopParams(deadman_button="l1"), "l1", "recover_button")
    with pytest.raises(TeleopError, match="positional button name, got 'options'"):
        check_extra_button(params, "options", "recover_button")


def test_a_press_counts_once_while_held_and_a_lost_pad_releases_it():
    press = ButtonPress("start")
    down = PadState({}, {"start": True}, True)
    up = PadState({}, {}, True)
    assert [press.update(s) for s in (up, down, down, up, down)] == [False, True, False, False, True]
    assert press.update(None) is False
    assert press.update(down) is True  # pressed again after the pad came back
    assert press.update(PadState({}, {"start": True}, False)) is False


def test_recovery_waits_until_the_nodes_twist_is_exactly_zero():
    from hri_teleop.core.teleop import recovery_refusal

    assert recovery_refusal((0.0,) * 6) is None
    assert recovery_refusal((-0.0, 0.0, 0.0, 0.0, 0.0, 0.0)) is None
    tiny = recovery_refusal((0.0, 0.0, 1e-12, 0.0, 0.0, 0.0))
    assert tiny is not None and "let go of the sticks" in tiny
    turning = recovery_refusal((0.0, 0.0, 0.0, 0.0, 0.0, 0.3))
    assert turning is not None and "0.300 rad/s" in turning and "0.000 m/s" in turning
