"""GoalThrottle: the rule that keeps gripper_manager.py from flooding the Franka Hand."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core.gripper import GoalThrottle, GripperError

RATE_HZ = 50.0  # teleoperation's loop rate: one /gripper_width per tick
DT = 1.0 / RATE_HZ


def drive(throttle: GoalThrottle, targets, dt: float = DT, t0: float = 0.0):
    """Feed one target per tick like /gripper_width does; return the (time, width) goals sent."""
    sent = []
    for i, target in enumerate(targets):
        now = t0 + i * dt
        if throttle.should_send(target, now):
            throttle.sent(target, now)
            sent.append((now, target))
    return sent


def test_first_target_is_sent_at_once():
    throttle = GoalThrottle()
    assert throttle.should_send(0.08, 0.0)


def test_unchanged_target_at_loop_rate_sends_one_goal_only():
    throttle = GoalThrottle()
    sent = drive(throttle, [0.08] * 500)  # 10 s of the same width at 50 Hz
    assert sent == [(0.0, 0.08)]


def test_holding_close_does_not_flood_and_reaches_the_final_width():
    # cross held for 2 s: width falls by k_gripper / rate = 0.04 / 50 = 0.8 mm per tick.
    throttle = GoalThrottle(min_step_m=0.002, max_goal_rate_hz=5.0, settle_s=0.2)
    ramp = [max(0.0, 0.08 - 0.0008 * i) for i in range(100)]
    hold = [ramp[-1]] * 50  # button released, target stays for 1 s
    sent = drive(throttle, ramp + hold)
    assert len(sent) <= 1 + 2.0 * 5.0 + 2, f"{len(sent)} goals for 150 targets: flooding"
    assert len(sent) < len(ramp) / 5
    assert sent[-1][1] == pytest.approx(ramp[-1]), "the final width must be sent"
    gaps = [b[0] - a[0] for a, b in zip(sent, sent[1:])]
    assert min(gaps) >= 1.0 / 5.0 - 1e-9


def test_small_final_correction_is_sent_after_settling_not_before():
    throttle = GoalThrottle(min_step_m=0.002, max_goal_rate_hz=5.0, settle_s=0.2)
    throttle.sent(0.040, 0.0)
    assert not throttle.should_send(0.0395, 1.0)        # 0.5 mm: below min_step, just arrived
    assert not throttle.should_send(0.0395, 1.1)        # still settling
    assert throttle.should_send(0.0395, 1.25)           # unchanged for >= 0.2 s


def test_big_step_is_sent_once_the_rate_limit_allows():
    throttle = GoalThrottle(min_step_m=0.002, max_goal_rate_hz=5.0)
    throttle.sent(0.08, 0.0)
    assert not throttle.should_send(0.0, 0.1)           # 0.2 s between goals at 5 Hz
    assert throttle.should_send(0.0, 0.2)


def test_step_exactly_min_step_counts_as_meaningful():
    throttle = GoalThrottle(min_step_m=0.002, max_goal_rate_hz=100.0)
    throttle.sent(0.010, 0.0)
    assert throttle.should_send(0.012, 1.0)
    throttle.sent(0.012, 1.0)
    assert not throttle.should_send(0.0139, 1.5)  # 1.9 mm: waits for the settle rule


def test_noise_below_tolerance_never_sends():
    throttle = GoalThrottle(min_step_m=0.002, tolerance_m=1e-4)
    throttle.sent(0.05, 0.0)
    for i in range(1, 200):
        assert not throttle.should_send(0.05 + (5e-5 if i % 2 else -5e-5), i * DT)


def test_pending_tells_whether_the_latest_target_is_still_unsent():
    throttle = GoalThrottle()
    assert not throttle.pending()
    throttle.should_send(0.03, 0.0)
    assert throttle.pending()
    throttle.sent(0.03, 0.0)
    assert not throttle.pending()
    assert throttle.latest_target_m == 0.03


def test_clock_is_used_when_no_time_is_given():
    now = [0.0]
    throttle = GoalThrottle(max_goal_rate_hz=5.0, clock=lambda: now[0])
    throttle.sent(0.08)
    now[0] = 0.1
    assert not throttle.should_send(0.0)
    now[0] = 0.3
    assert throttle.should_send(0.0)


@pytest.mark.parametrize("kwargs, word", [
    ({"min_step_m": 0}, "min_step_m"),
    ({"min_step_m": -0.001}, "min_step_m"),
    ({"max_goal_rate_hz": 0}, "max_goal_rate_hz"),
    ({"max_goal_rate_hz": float("nan")}, "max_goal_rate_hz"),
    ({"settle_s": True}, "settle_s"),
    ({"min_step_m": "2mm"}, "min_step_m"),
    ({"tolerance_m": 0.01}, "tolerance_m"),
])
def test_bad_settings_raise_one_line_naming_the_setting(kwargs, word):
    with pytest.raises(GripperError) as info:
        GoalThrottle(**kwargs)
    assert word in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("target", [float("nan"), float("inf"), "0.04", None, True])
def test_bad_target_raises(target):
    with pytest.raises(GripperError, match="/gripper_width"):
        GoalThrottle().should_send(target, 0.0)


@settings(max_examples=200, deadline=None)
@given(
    targets=st.lists(st.floats(min_value=0.0, max_value=0.08), min_size=1, max_size=300),
    max_rate=st.floats(min_value=0.5, max_value=20.0),
    min_step=st.floats(min_value=0.0005, max_value=0.01),
)
def test_property_goal_rate_is_bounded_and_the_last_target_is_reached(targets, max_rate, min_step):
    throttle = GoalThrottle(min_step_m=min_step, max_goal_rate_hz=max_rate, settle_s=0.2)
    tail = [targets[-1]] * int(RATE_HZ * (0.2 + 2.0 / max_rate + 0.1))  # the target then stays put
    sent = drive(throttle, list(targets) + tail)
    times = [t for t, _ in sent]
    gaps = [b - a for a, b in zip(times, times[1:])]
    assert all(g >= 1.0 / max_rate - 1e-9 for g in gaps)
    duration = (len(targets) + len(tail)) * DT
    assert len(sent) <= 1 + math.floor(duration * max_rate + 1e-9)
    assert abs(sent[-1][1] - targets[-1]) <= throttle.tolerance_m


@pytest.mark.parametrize("raw, expected", [
    (0.04, 0.04), (0.0, 0.0), (0.08, 0.08), (-0.01, 0.0), (0.2, 0.08),
    (float("nan"), None), (float("inf"), None), (float("-inf"), None), ("x", None),
])
def test_usable_width_clamps_to_the_hand_and_drops_non_numbers(raw, expected):
    from hri_teleop.core.gripper import usable_width_m

    width, problem = usable_width_m(raw)
    assert width == expected
    assert (problem == "") == (raw == expected)


def test_the_hand_width_is_the_sum_of_the_two_finger_joints_or_none_for_a_malformed_message():
    from hri_teleop.core.gripper import width_from_joint_positions_m

    assert width_from_joint_positions_m([0.02, 0.02]) == pytest.approx(0.04)
    assert width_from_joint_positions_m((0.013, 0.013, 9.0)) == pytest.approx(0.026)
    assert width_from_joint_positions_m([0.04]) is None
    assert width_from_joint_positions_m([float("nan"), 0.01]) is None


# -- the edges (make mutants) ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("now_s, sends", [(0.19, False), (0.199, False), (0.2, True), (0.21, True)])
def test_by_default_a_big_step_waits_0_2_s_after_the_last_goal(now_s, sends):
    throttle = GoalThrottle()
    throttle.sent(0.08, 0.0)
    assert throttle.should_send(0.0, now_s) is sends


@pytest.mark.parametrize("now_s, sends", [(1.19, False), (1.21, True)])
def test_by_default_a_small_correction_goes_out_once_unchanged_for_0_2_s(now_s, sends):
    throttle = GoalThrottle()
    throttle.sent(0.040, 0.0)
    assert not throttle.should_send(0.0395, 1.0)  # 0.5 mm: below the default 2 mm step, above the 0.1 mm tolerance
    assert throttle.should_send(0.0395, now_s) is sends


@pytest.mark.parametrize("now_s, sends", [(1.125, False), (1.25, True), (1.375, True)])
def test_a_correction_goes_out_once_unchanged_for_exactly_the_settle_time(now_s, sends):
    throttle = GoalThrottle(min_step_m=1.0, max_goal_rate_hz=100.0, settle_s=0.25, tolerance_m=0.25)
    throttle.sent(2.0, 0.0)
    assert not throttle.should_send(2.5, 1.0)
    assert throttle.should_send(2.5, now_s) is sends


@pytest.mark.parametrize("target, sends", [(2.24, False), (2.25, False), (2.26, True)])
def test_a_target_at_most_the_tolerance_from_the_last_goal_is_never_sent(target, sends):
    throttle = GoalThrottle(min_step_m=1.0, max_goal_rate_hz=100.0, settle_s=0.5, tolerance_m=0.25)
    throttle.sent(2.0, 0.0)
    assert throttle.should_send(target, 1.0) is False  # a new target (or none) has not settled yet
    assert throttle.should_send(target, 2.0) is sends


def test_a_target_moving_by_exactly_the_tolerance_does_not_restart_the_settle_time():
    throttle = GoalThrottle(min_step_m=1.0, max_goal_rate_hz=100.0, settle_s=0.5, tolerance_m=0.25)
    throttle.sent(2.0, 0.0)
    assert not throttle.should_send(2.5, 1.0)    # settles from 1.0
    assert not throttle.should_send(2.75, 1.25)  # 0.25 from 2.5: the same target
    assert throttle.should_send(2.75, 1.5)       # unchanged since 1.0 for 0.5 s


def test_a_goal_within_the_tolerance_of_the_latest_target_leaves_nothing_pending():
    throttle = GoalThrottle(min_step_m=1.0, tolerance_m=0.25)
    throttle.should_send(2.5, 0.0)
    throttle.sent(2.25, 0.0)  # 0.25 from the latest target
    assert not throttle.pending()
    throttle.should_send(2.76, 1.0)  # a new target, 0.51 from the goal
    assert throttle.pending()


def test_goals_sent_counts_every_goal_recorded():
    throttle = GoalThrottle()
    assert throttle.goals_sent == 0
    throttle.sent(0.04, 0.0)
    assert throttle.goals_sent == 1
    throttle.sent(0.04, 1.0)
    throttle.sent(0.02, 2.0)
    assert throttle.goals_sent == 3


@pytest.mark.parametrize("kwargs, message", [
    ({"min_step_m": 0}, "gripper throttle min_step_m must be a positive number, got 0; set it to e.g. 0.002 (2 mm)"),
    ({"max_goal_rate_hz": -5.0}, "gripper throttle max_goal_rate_hz must be a positive number, got -5.0; set it to e.g. 5.0"),
    ({"settle_s": float("inf")}, "gripper throttle settle_s must be a positive number, got inf; set it to e.g. 0.2"),
    ({"min_step_m": 0.002, "tolerance_m": 0.002}, "gripper throttle tolerance_m must be >= 0 and below min_step_m "
                                                  "(0.002), got 0.002; leave it at its default 1e-4"),
    ({"tolerance_m": -1e-9}, "gripper throttle tolerance_m must be >= 0 and below min_step_m (0.002), got -1e-09; "
                             "leave it at its default 1e-4"),
])
def test_a_bad_setting_is_refused_naming_it_and_the_fix(kwargs, message):
    with pytest.raises(GripperError) as info:
        GoalThrottle(**kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize("tolerance_m", [0, 0.0, 0.0019])
def test_a_tolerance_from_0_to_just_below_the_step_is_accepted(tolerance_m):
    assert GoalThrottle(min_step_m=0.002, tolerance_m=tolerance_m).tolerance_m == tolerance_m


def test_the_hand_width_adds_the_first_two_finger_joints_whatever_follows():
    from hri_teleop.core.gripper import width_from_joint_positions_m

    assert width_from_joint_positions_m([0.01, 0.03]) == 0.04
    assert width_from_joint_positions_m([0.01, 0.03, float("nan")]) == 0.04
    assert width_from_joint_positions_m((0.01, 0.03, "x")) == 0.04
