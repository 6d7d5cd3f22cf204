"""The rules of hri_teleop.core.limits at their edges (issue 44: changing a rule fails a test): the command-rate
check and the lab's limits lowered to a robot's budget at their margin and at exact equality, the robot's 1 kHz
view of held commands, and the independent checker's thresholds and words. The limiter's law itself is pinned by
the property tests of tests/unit/test_limits.py."""

from __future__ import annotations

import math

import pytest

from hri_teleop.core.limits import (
    DEFAULT_LIMITS,
    LAB_LIMITS,
    ROBOT_LIMITS,
    AxisLimits,
    CartesianLimits,
    GroupLimiter,
    LimitsError,
    TwistLimiter,
    accel_for_error,
    check_command_rate,
    hold_at_robot_rate,
    lab_limits_for,
    limit_violations,
    max_step_per_command,
    sanitize_clip,
)

MARGIN = 1e-9  # limits._MARGIN: the relative slack of both budget checks
BIG = 1e9


def _both(axis: AxisLimits) -> CartesianLimits:
    return CartesianLimits(axis, axis)


# --- the largest step a robot takes: the smaller of its acceleration and jerk budgets in one cycle ----------


def test_a_step_is_bounded_by_the_jerk_budget_or_the_acceleration_budget_whichever_is_smaller():
    assert max_step_per_command(ROBOT_LIMITS.translation) == pytest.approx(6500.0 * 1e-6)  # the Panda: jerk
    assert max_step_per_command(AxisLimits(1.0, 2.0, 6500.0)) == pytest.approx(2.0 * 1e-3)  # acceleration
    assert max_step_per_command(AxisLimits(1.0, 2.0, 6500.0), robot_period_s=0.0001) == pytest.approx(6500.0 * 1e-8)


# --- the lab's limits for a robot: lowered only where they do not fit its budget ----------------------------


def _translation_budget(acceleration: float, rate_hz: float = 1000.0) -> CartesianLimits:
    """A robot whose translation budget at ``rate_hz`` is ``acceleration * 1 ms * rate_hz`` (its jerk is no bound)."""
    return CartesianLimits(AxisLimits(10.0, acceleration, BIG), ROBOT_LIMITS.rotation)


def test_a_lab_acceleration_exactly_at_the_budgets_margin_is_kept():
    hard = _translation_budget(0.29999999969999996)
    assert max_step_per_command(hard.translation) * 1000.0 * (1.0 + MARGIN) == LAB_LIMITS.translation.acceleration
    assert lab_limits_for(hard, rate_hz=1000.0).translation.acceleration == 0.3


def test_a_lab_acceleration_inside_the_budgets_margin_is_kept_and_one_beyond_it_lowered():
    inside = _translation_budget(0.3 * (1.0 - 0.5 * MARGIN))
    assert lab_limits_for(inside, rate_hz=1000.0).translation.acceleration == 0.3
    beyond = _translation_budget(0.3 * (1.0 - 2.0 * MARGIN))
    assert lab_limits_for(beyond, rate_hz=1000.0).translation.acceleration == 0.25


@pytest.mark.parametrize("jerk, lowered", [(2000.0, 0.1), (3000.0, 0.15), (4000.0, 0.2), (4500.0, 0.2)])
def test_a_lowered_acceleration_is_the_largest_step_multiple_the_budget_takes_even_when_it_divides_exactly(
        jerk, lowered):
    """0.1 / 0.05 is 2.0 and 0.15 / 0.05 is 2.9999999999999996 in floats: both are whole steps."""
    hard = CartesianLimits(AxisLimits(3.0, BIG, jerk), ROBOT_LIMITS.rotation)
    assert lab_limits_for(hard).translation.acceleration == lowered


def test_a_budget_below_one_step_is_taken_as_it_is_to_nine_places():
    hard = CartesianLimits(AxisLimits(3.0, BIG, 246.913578024), ROBOT_LIMITS.rotation)  # 0.0123456789012 at 50 Hz
    assert lab_limits_for(hard).translation.acceleration == 0.012345679


# --- the command-rate check: the change per message against the robot's one-cycle budget -------------------


def test_the_command_rate_check_takes_the_robots_period():
    check_command_rate(LAB_LIMITS, 50.0, ROBOT_LIMITS)  # 6 mm/s per message, the Panda's 6.5
    with pytest.raises(LimitsError, match="above its 0.005265 m/s"):  # 6500 m/s^3 * (0.9 ms)^2
        check_command_rate(LAB_LIMITS, 50.0, ROBOT_LIMITS, robot_period_s=0.0009)


@pytest.mark.parametrize("factor, ok", [(1.0 + MARGIN, True), (1.0 + 0.5 * MARGIN, True), (1.0 + 3.0 * MARGIN, False)])
def test_a_change_per_message_up_to_the_budgets_margin_passes_and_beyond_it_is_refused(factor, ok):
    """A robot period of 1 s and a jerk of 1 make the budget exactly 1: the margin is the only slack."""
    limits = _both(AxisLimits(10.0, 1.0 * factor, 10.0))
    hard = _both(AxisLimits(10.0, 10.0, 1.0))
    if ok:
        check_command_rate(limits, 1.0, hard, robot_period_s=1.0)
    else:
        with pytest.raises(LimitsError):
            check_command_rate(limits, 1.0, hard, robot_period_s=1.0)


@pytest.mark.parametrize("group, unit", [("translation", "m/s"), ("rotation", "rad/s")])
def test_a_refused_rate_names_the_group_its_unit_and_both_fixes(group, unit):
    fast = AxisLimits(1.0, 0.5, 10.0)
    limits = CartesianLimits(fast, LAB_LIMITS.rotation) if group == "translation" else CartesianLimits(
        LAB_LIMITS.translation, AxisLimits(1.0, 0.7, 10.0))
    acceleration = 0.5 if group == "translation" else 0.7
    budget = max_step_per_command(getattr(ROBOT_LIMITS, group))
    with pytest.raises(LimitsError) as caught:
        check_command_rate(limits, 50.0, ROBOT_LIMITS)
    assert str(caught.value) == (
        f"limits.{group}.acceleration {acceleration:g} {unit}^2 at rate 50 Hz lets the command change by "
        f"{acceleration / 50.0:.4g} {unit} per message, which the robot (1 kHz) sees as a step above its "
        f"{budget:.4g} {unit}; lower limits.{group}.acceleration to <= {budget * 50.0:.4g} or raise rate to >= "
        f"{acceleration / budget:.4g} Hz")


# --- what a controller holding each command shows the robot ----------------------------------------------


def test_held_commands_repeat_once_per_robot_cycle_as_floats():
    held = hold_at_robot_rate([(1, 2, 3, 4, 5, 6), (0, 0, 0, 0, 0, 0)], 50.0)
    assert len(held) == 40 and held[:20] == [(1.0, 2.0, 3.0, 4.0, 5.0, 6.0)] * 20 and held[20:] == [(0.0,) * 6] * 20
    assert all(type(c) is float for c in held[0])


@pytest.mark.parametrize("rate_hz, period_s, copies", [(50, 0.001, 20), (50.0, 0.002, 10), (400.0, 0.001, 2),
                                                        (2000.0, 0.001, 1), (10000.0, 0.001, 1)])
def test_each_command_is_held_for_the_robot_cycles_between_two_commands_and_at_least_one(rate_hz, period_s, copies):
    assert hold_at_robot_rate([(0.1,) * 6], rate_hz, robot_period_s=period_s) == [(0.1,) * 6] * copies


# --- the independent checker ----------------------------------------------------------------------------------


def test_a_twist_that_is_not_six_finite_numbers_ends_the_check_with_its_step():
    limits = _both(AxisLimits(1.0, 1.0, 1.0))
    assert limit_violations(limits, [(0.0,) * 6, (0.0,) * 5, (BIG,) * 6], [1.0, 1.0, 1.0]) == [
        "step 1: twist (0.0, 0.0, 0.0, 0.0, 0.0) is not 6 finite numbers"]
    assert limit_violations(limits, [(math.nan,) + (0.0,) * 5], [1.0]) == [
        "step 0: twist (nan, 0.0, 0.0, 0.0, 0.0, 0.0) is not 6 finite numbers"]


def test_a_norm_exactly_at_its_limit_passes_and_just_above_it_is_named():
    limits = _both(AxisLimits(0.5, 0.5, 0.5))
    assert limit_violations(limits, [(0.5, 0.0, 0.0, 0.0, 0.0, 0.0)], [1.0], rel_tol=0.0) == []
    assert limit_violations(limits, [(0.0, 0.0, 0.0, 0.3, 0.4, 0.0)], [1.0], rel_tol=0.0) == []  # |(0.3, 0.4)| = 0.5
    assert limit_violations(limits, [(0.0, 0.0, 0.0, 0.5000001, 0.0, 0.0)], [1.0], rel_tol=0.0) == [
        "step 0: rotation velocity 0.5000001 > 0.5", "step 0: rotation acceleration 0.5000001 > 0.5",
        "step 0: rotation jerk 0.5000001 > 0.5"]


def test_each_group_is_judged_on_its_own_three_components():
    limits = _both(AxisLimits(0.5, 10.0, 100.0))
    assert limit_violations(limits, [(0.0, 0.0, 0.0, 0.6, 0.0, 0.0)], [1.0]) == [
        "step 0: rotation velocity 0.6 > 0.5"]
    assert limit_violations(limits, [(0.0, 0.0, 0.6, 0.0, 0.0, 0.0)], [1.0]) == [
        "step 0: translation velocity 0.6 > 0.5"]


def test_the_jerk_is_the_change_of_the_acceleration():
    """A constant acceleration of 0.01 has no jerk after its start: 0.01, then 0."""
    limits = _both(AxisLimits(1.0, 1.0, 0.015))
    assert limit_violations(limits, [(0.01, 0.0, 0.0, 0.0, 0.0, 0.0), (0.02, 0.0, 0.0, 0.0, 0.0, 0.0)], [1.0, 1.0]) == []
    # a stop from 0.02 at once: acceleration -0.02, jerk -0.03 (both named)
    assert limit_violations(_both(AxisLimits(1.0, 0.015, 0.015)), [(0.01,) + (0.0,) * 5, (0.02,) + (0.0,) * 5,
                                                                    (0.0,) * 6], [1.0, 1.0, 1.0]) == [
        "step 2: translation acceleration 0.02 > 0.015", "step 2: translation jerk 0.03 > 0.015"]


# --- continuing from a known motion -----------------------------------------------------------------------


@pytest.mark.parametrize("name", ["velocity", "acceleration"])
@pytest.mark.parametrize("count", [5, 7])
def test_reset_takes_six_values_of_each(name, count):
    limiter = TwistLimiter(DEFAULT_LIMITS)
    with pytest.raises(LimitsError) as caught:
        limiter.reset(**{name: (0.01,) * count})
    assert str(caught.value) == f"reset's {name} must have 6 values (vx vy vz wx wy wz), got {count}"
    limiter.reset(**{name: (0.01, 0.02, 0.03, 0.04, 0.05, 0.06)})
    assert getattr(limiter, name) == (0.01, 0.02, 0.03, 0.04, 0.05, 0.06)


# --- the tracking law's inverse: the acceleration whose braking staircase covers an error --------------------


@pytest.mark.parametrize("q, x", [
    (0.0, 0.0), (0.5, 0.5), (1.0, 1.0), (3.0, 2.0), (6.0, 3.0), (10.0, 4.0),
    # just below a step of the staircase, where the closed form's sqrt rounds up to the next step
    (1.0 - 2.0 ** -53, 1.0 - 2.0 ** -53), (3.0 - 2.0 ** -51, (3.0 - 2.0 ** -51 + 1.0) / 2.0),
])
def test_the_acceleration_for_an_error_is_on_the_right_step_of_the_braking_staircase(q, x):
    """With dt = h = 1, D(x) = (n+1) x - n(n+1)/2 on [n, n+1) (docs/teleoperation.md): x = (q + n(n+1)/2)/(n+1)."""
    assert accel_for_error(q, 1.0, 1.0) == x
    assert accel_for_error(q * 0.02 * 0.5, 0.02, 0.5) == pytest.approx(x * 0.5, rel=1e-12)


# --- the target clip and the velocity-safety test at exactly the velocity limit -----------------------------


def test_a_target_exactly_at_the_velocity_limit_is_taken_as_it_is():
    assert sanitize_clip((0.007, 0.024, 0.0), 0.025) == (0.007, 0.024, 0.0)  # scaled: 0.007000000000000001
    assert sanitize_clip((0.6, 0.8, 0.0), 0.5) == pytest.approx((0.3, 0.4, 0.0), rel=1e-15)


def test_holding_exactly_the_velocity_limit_is_viable_and_one_step_beyond_it_is_not():
    group = GroupLimiter(AxisLimits(1.0, 1.0, 1.0))
    group.v = (group.v_max, 0.0, 0.0)
    assert group._viable((0.0, 0.0, 0.0), 0.02)
    assert not group._viable((1e-3, 0.0, 0.0), 0.02)


def test_a_target_equal_to_the_velocity_while_accelerating_eases_the_acceleration_off_by_one_jerk_step():
    """No error left but 0.16 m/s^2 of acceleration: the law takes it down by j dt = 0.04, along its own axis."""
    limiter = TwistLimiter(DEFAULT_LIMITS)
    for _ in range(4):
        limiter.step((0.1, 0.0, 0.0, 0.0, 0.0, 0.0), 0.02)
    before = limiter.acceleration[0]
    assert before == pytest.approx(0.16)
    limiter.step(limiter.velocity, 0.02)
    after = limiter.acceleration
    assert after[0] == pytest.approx(before - DEFAULT_LIMITS.translation.jerk * 0.02) and after[1:] == (0.0,) * 5


@pytest.mark.parametrize("target", [0.0006, 0.000403, 0.0008 * (1.0 - 2e-9)])
def test_an_error_one_step_can_close_is_closed_exactly_in_that_step(target):
    """At 50 Hz an error up to 0.8 mm/s needs at most one jerk step of acceleration (2 m/s^3 * 20 ms = 0.04 m/s^2):
    the step lands on the target bit for bit (0.000403 by the switching curve would be 0.00040300000000000004)."""
    assert TwistLimiter(DEFAULT_LIMITS).step((target, 0.0, 0.0, 0.0, 0.0, 0.0), 0.02) == (target,) + (0.0,) * 5


def test_full_stick_beyond_the_limit_stays_at_or_below_the_velocity_limit_without_tolerance():
    """The limiter aims a relative 1e-9 inside each limit, so its output holds them with no tolerance at all."""
    limits = _both(AxisLimits(0.25, 0.3, 2.0))
    limiter = TwistLimiter(limits)
    twists = [limiter.step((1.0, 0.0, 0.0, 0.0, 0.0, 1.0), 0.02) for _ in range(200)]
    assert twists[-1][0] == twists[-2][0] > 0.2499  # reached and held
    assert limit_violations(limits, twists, [0.02] * 200, rel_tol=0.0) == []


def test_an_error_of_exactly_one_jerk_step_lands_on_the_target_bit_for_bit():
    """At 1/0.07 Hz the jerk step of DEFAULT_LIMITS' translation is 2 m/s^3 (less its 1e-9) * 0.07 s; a target from
    rest that needs exactly that acceleration lands on it (the switching curve would give 0.0097999999902)."""
    target, dt = 0.009799999990200002, 0.07
    assert target * (1.0 / dt) == 2.0 * (1.0 - MARGIN) * dt  # the landing's edge, hit exactly
    assert TwistLimiter(DEFAULT_LIMITS).step((target, 0.0, 0.0, 0.0, 0.0, 0.0), dt)[0] == target
    assert TwistLimiter(DEFAULT_LIMITS).step((0.0, 0.0, 0.0, 2 * target, 0.0, 0.0), dt)[3] == 2 * target  # 4 rad/s^3


# --- the tracking law's staircase for any error, and its groups kept apart -----------------------------------


def _staircase_step(q: int) -> int:
    """The largest n with n (n+1) / 2 <= q, by bisection on whole numbers (independent of the limiter's formula)."""
    lo, hi = 0, 1
    while hi * (hi + 1) // 2 <= q:
        hi *= 2
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if mid * (mid + 1) // 2 <= q else (lo, mid)
    return lo


@pytest.mark.parametrize("q", [1.48401282329844e31, 2.0 ** 200, 1e300])
def test_the_acceleration_for_a_huge_error_is_found_at_once_on_its_step(q):
    """1.48e31: the float square root's guess falls one step short; 2^200: it is 1.2e14 steps too high, which a
    walk back one step at a time would take days to correct. dt = h = 1, so q is whole and x = (q + T(n))/(n+1)."""
    n = _staircase_step(int(q))
    assert accel_for_error(q, 1.0, 1.0) == pytest.approx((q + n * (n + 1) / 2) / (n + 1), rel=1e-15)


def test_the_translation_command_is_the_same_bit_for_bit_whatever_the_rotation_target():
    """Each group is clipped on its own: a huge wx does not take part in the translation's clip."""
    alone, beside = TwistLimiter(DEFAULT_LIMITS), TwistLimiter(DEFAULT_LIMITS)
    for _ in range(30):
        own = alone.step((3.0, 0.5, 0.0, 0.0, 0.0, 0.0), 0.02)
        mixed = beside.step((3.0, 0.5, 0.0, 1.79e308, 0.0, 0.0), 0.02)
        assert mixed[:3] == own[:3]


# --- the velocity safety's braking fallback: a turn at full stick ----------------------------------------------


@pytest.mark.parametrize("axis, dt, straight", [
    (AxisLimits(0.1, 4.0, 0.1), 0.1, 10),  # the jerk alone limits: the acceleration builds over a whole second
    (AxisLimits(0.1, 4.0, 1.0), 0.02, 5),
    (AxisLimits(0.1, 4.0, 1.0), 0.02, 10),
])
def test_a_turn_at_full_stick_keeps_every_limit_while_the_velocity_safety_brakes(axis, dt, straight):
    """Full stick along x, then along y: the acceleration towards y is not viable at once near the velocity limit,
    so the law brakes by one jerk step and takes the largest viable point towards the candidate."""
    group = GroupLimiter(axis)
    targets = [(1.0, 0.0, 0.0)] * straight + [(0.0, 1.0, 0.0)] * (100 - straight)
    twists = [group.step(target, dt) + (0.0, 0.0, 0.0) for target in targets]
    assert limit_violations(_both(axis), twists, [dt] * 100, rel_tol=0.0) == []
    assert twists[-1][:2] == pytest.approx((0.0, 0.1), abs=1e-9)  # and it got there


def test_a_diagonal_target_beyond_the_limit_is_scaled_onto_it_along_its_direction():
    """(0.2, 0.2) m/s has a norm of 0.283 above 0.25, though each component is below it."""
    clipped = sanitize_clip((0.2, 0.2, 0.0), 0.25)
    assert clipped == pytest.approx((0.25 / math.sqrt(2.0), 0.25 / math.sqrt(2.0), 0.0), rel=1e-15)
    assert sanitize_clip((0.1, -0.1, 0.1), 0.1) == pytest.approx((0.1 / math.sqrt(3.0), -0.1 / math.sqrt(3.0),
                                                                  0.1 / math.sqrt(3.0)), rel=1e-15)
