"""The Panda's joint limits, the joint-side judge's arithmetic, the warning before a limit, and the
reflex in plain words: each rule at its thresholds."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hri_teleop.core.joints import (
    JOINT_ACCELERATION_DISCONTINUITY,
    JOINT_NAMES,
    JOINT_POSITION_LIMITS_VIOLATION,
    JOINT_VELOCITY_DISCONTINUITY,
    JOINT_VELOCITY_LIMITS_VIOLATION,
    READY_POSE_RAD,
    ROBOT_JOINT_LIMITS,
    WARNING_MARGIN_RAD,
    JointLimits,
    JointLimitWatch,
    JointsError,
    JointStateWarning,
    JointViolation,
    LimitDistance,
    joint_violations,
    nearest_limit,
    positions_by_name,
)
from hri_teleop.core.reflex import (
    CARTESIAN_ACCELERATION_DISCONTINUITY,
    CARTESIAN_VELOCITY_DISCONTINUITY,
    CARTESIAN_VELOCITY_LIMITS_VIOLATION,
    NON_FINITE_COMMAND,
    RECOVERY_HINT,
    ReflexCause,
    explain_cause,
    explain_reflex,
)

L = ROBOT_JOINT_LIMITS
ZERO7 = (0.0,) * 7


def test_the_limits_are_the_pandas_published_table():
    assert L.position_max_rad[3] == -0.0698 and L.position_min_rad[5] == -0.0175
    assert L.velocity_rad_per_s == (2.175,) * 4 + (2.61,) * 3
    assert L.acceleration_rad_per_s2[1] == 7.5 and L.jerk_rad_per_s3[1] == 3750.0
    assert JOINT_NAMES == tuple(f"panda_joint{i}" for i in range(1, 8))
    assert all(lo < q < hi for lo, q, hi in zip(L.position_min_rad, READY_POSE_RAD, L.position_max_rad))


@pytest.mark.parametrize("kwargs, words", [
    ({"velocity_rad_per_s": (1.0,) * 6}, "7 finite numbers"),
    ({"velocity_rad_per_s": (1.0,) * 6 + (0.0,)}, "positive for every joint"),
    ({"jerk_rad_per_s3": (1.0,) * 6 + (float("nan"),)}, "7 finite numbers"),
    ({"position_min_rad": (0.0,) * 7, "position_max_rad": (0.0,) * 7}, "joint 1: position_min_rad 0 must be below"),
])
def test_unusable_limits_are_refused_naming_the_field(kwargs, words):
    fields = dict(position_min_rad=L.position_min_rad, position_max_rad=L.position_max_rad,
                  velocity_rad_per_s=L.velocity_rad_per_s, acceleration_rad_per_s2=L.acceleration_rad_per_s2,
                  jerk_rad_per_s3=L.jerk_rad_per_s3)
    fields.update(kwargs)
    with pytest.raises(JointsError, match=words):
        JointLimits(**fields)


def _with(index: int, value: float, base=ZERO7):
    out = list(base)
    out[index] = value
    return tuple(out)


@pytest.mark.parametrize("quantity, error, limits", [
    ("velocity", JOINT_VELOCITY_LIMITS_VIOLATION, L.velocity_rad_per_s),
    ("acceleration", JOINT_VELOCITY_DISCONTINUITY, L.acceleration_rad_per_s2),
    ("jerk", JOINT_ACCELERATION_DISCONTINUITY, L.jerk_rad_per_s3),
])
@pytest.mark.parametrize("joint", [0, 6])
def test_a_derivative_at_its_limit_passes_and_just_above_it_breaks_it(quantity, error, limits, joint):
    def judge(value):
        args = {"velocity": ZERO7, "acceleration": ZERO7, "jerk": ZERO7}
        args[quantity] = _with(joint, value)
        return joint_violations(READY_POSE_RAD, args["velocity"], args["acceleration"], args["jerk"], rel_tol=0.0)

    limit = limits[joint]
    assert judge(limit) == [] and judge(-limit) == []
    (found,) = judge(limit * (1 + 1e-12) + 1e-9)
    assert (found.error, found.joint, found.limit) == (error, joint + 1, limit)
    assert judge(-limit - 1e-6)[0].error == error


def test_a_position_on_its_limit_passes_and_past_it_names_the_limit_it_passed():
    at_max = _with(6, L.position_max_rad[6], READY_POSE_RAD)
    assert joint_violations(at_max, ZERO7, ZERO7, ZERO7) == []
    (found,) = joint_violations(_with(6, 2.8974, READY_POSE_RAD), ZERO7, ZERO7, ZERO7)
    assert (found.error, found.joint, found.value, found.limit) == (JOINT_POSITION_LIMITS_VIOLATION, 7, 2.8974, 2.8973)
    (low,) = joint_violations(_with(3, -3.0719, READY_POSE_RAD), ZERO7, ZERO7, ZERO7)
    assert (low.joint, low.limit) == (4, -3.0718)


@pytest.mark.parametrize("velocity, broken", [(2.175, False), (2.1750000021, False),  # the limit, a billionth above
                                             (2.17500002175, True), (2.18, True)])   # a hundred-millionth above
def test_a_derivative_passes_up_to_a_billionth_above_its_limit_by_default(velocity, broken):
    found = joint_violations(READY_POSE_RAD, _with(0, velocity), ZERO7, ZERO7)
    assert bool(found) is broken
    if broken:
        assert found == [JointViolation(0.0, JOINT_VELOCITY_LIMITS_VIOLATION, 1, velocity, 2.175)]


def test_a_position_exactly_on_its_min_limit_passes_and_a_violation_carries_its_time():
    assert joint_violations(_with(3, -3.0718, READY_POSE_RAD), ZERO7, ZERO7, ZERO7) == []
    (found,) = joint_violations(_with(3, -3.0719, READY_POSE_RAD), ZERO7, ZERO7, ZERO7, time_s=1.25)
    assert found == JointViolation(1.25, JOINT_POSITION_LIMITS_VIOLATION, 4, -3.0719, -3.0718)


def test_nan_breaks_every_limit_it_meets():
    found = joint_violations(_with(0, math.nan, READY_POSE_RAD), _with(1, math.nan), ZERO7, ZERO7)
    assert {(v.error, v.joint) for v in found} == {(JOINT_POSITION_LIMITS_VIOLATION, 1),
                                                   (JOINT_VELOCITY_LIMITS_VIOLATION, 2)}


def test_the_nearest_limit_is_found_with_its_side_and_margin():
    near = nearest_limit(READY_POSE_RAD)
    assert near.joint == 4 and near.side == "min"  # -3pi/4 is 0.72 rad above -3.0718
    assert near.margin_rad == pytest.approx(-3 * math.pi / 4 - L.position_min_rad[3])
    turned = nearest_limit(_with(6, 2.85, READY_POSE_RAD))
    assert (turned.joint, turned.side, turned.limit_rad) == (7, "max", 2.8973)
    assert turned.margin_rad == pytest.approx(0.0473)
    assert "joint 7 is 0.05 rad from its max limit" in turned.describe() and "turn it back (down)" in turned.describe()
    past = nearest_limit(_with(0, -2.95, READY_POSE_RAD))
    assert past.margin_rad < 0 and past.side == "min" and "(up)" in past.describe()
    with pytest.raises(JointsError, match="7 finite numbers"):
        nearest_limit((0.0,) * 6)


def test_the_warning_starts_inside_its_margin_once_and_ends_only_past_the_clear_margin():
    watch = JointLimitWatch()
    limit = L.position_max_rad[6]
    assert watch.warn_margin_rad == WARNING_MARGIN_RAD == 0.1
    assert watch.update(_with(6, limit - 0.1, READY_POSE_RAD)) is None and watch.warning is None  # at the margin
    started = watch.update(_with(6, limit - 0.0999, READY_POSE_RAD))
    assert started is not None and started.joint == 7 and watch.warning is not None
    assert watch.update(_with(6, limit - 0.05, READY_POSE_RAD)) is None  # still on: not a second warning
    assert watch.update(_with(6, limit - 0.15, READY_POSE_RAD)) is None and watch.warning is not None  # at clear
    watch.update(_with(6, limit - 0.1501, READY_POSE_RAD))
    assert watch.warning is None
    assert watch.update(_with(6, limit - 0.09, READY_POSE_RAD)) is not None  # a new approach warns again


# Joint 4's max limit is -0.0698 rad; these positions put it exactly this far from it in floating point
# (-0.0698 - -0.1698 == 0.1), every other joint at least 1.5 rad from its limits.
def _joint4_at(q4: float) -> tuple:
    return (0.0, 0.0, 0.0, q4, 0.0, 1.5, 0.0)


@pytest.mark.parametrize("q4, margin, warns", [
    (-0.1688, 0.099, True),   # just inside the 0.1 rad margin: warns
    (-0.1698, 0.1, False),    # exactly at it: not yet (the margin is "closer than")
    (-0.1708, 0.101, False),  # just outside
])
def test_the_warning_starts_only_closer_than_0_1_rad_to_a_limit(q4, margin, warns):
    assert nearest_limit(_joint4_at(q4)).margin_rad == margin
    watch = JointLimitWatch()
    started = watch.update(_joint4_at(q4))
    assert (started is not None, watch.warning is not None) == (warns, warns)
    if warns:
        assert (started.joint, started.side, started.margin_rad) == (4, "max", margin)


@pytest.mark.parametrize("q4, margin, cleared", [
    (-0.2188, 0.149, False),               # still inside the 0.15 rad clear margin: the warning holds
    (-0.21980000000000002, 0.15000000000000002, False),  # exactly at it (1.5 x 0.1 in floating point): holds
    (-0.2208, 0.151, True),                # past it: the warning ends
])
def test_a_warning_ends_only_farther_than_0_15_rad_from_every_limit(q4, margin, cleared):
    watch = JointLimitWatch()
    assert watch.update(_joint4_at(-0.1688)) is not None
    assert nearest_limit(_joint4_at(q4)).margin_rad == margin
    assert watch.update(_joint4_at(q4)) is None  # never a second start while it lasts
    assert (watch.warning is None) == cleared
    if not cleared:
        assert watch.warning is not None and watch.warning.margin_rad == margin  # follows the joint


def test_a_warning_that_holds_follows_the_joint_and_a_clear_one_needs_a_new_approach():
    watch = JointLimitWatch()
    watch.update(_joint4_at(-0.1688))
    watch.update(_joint4_at(-0.1598))
    assert watch.warning is not None and watch.warning.margin_rad == pytest.approx(0.09)
    watch.update(_joint4_at(-0.2208))
    assert watch.warning is None
    assert watch.update(_joint4_at(-0.1708)) is None  # 0.101 rad: between the margins, no new warning
    assert watch.update(_joint4_at(-0.1688)) is not None


def test_a_watch_with_its_own_margins_judges_at_them():
    watch = JointLimitWatch(warn_margin_rad=0.25, clear_margin_rad=0.5)
    # joint 4 at -0.31980000000000003: 0.25 rad from its max in floating point (-0.3198 is 0.24999999999999997).
    assert nearest_limit(_joint4_at(-0.31980000000000003)).margin_rad == 0.25
    assert watch.update(_joint4_at(-0.31980000000000003)) is None
    assert watch.update(_joint4_at(-0.3188)) is not None
    watch.update(_joint4_at(-0.5698))  # 0.5 rad: at the clear margin, holds
    assert watch.warning is not None
    watch.update(_joint4_at(-0.5708))
    assert watch.warning is None
    assert JointLimitWatch(warn_margin_rad=0.1, clear_margin_rad=0.1).clear_margin_rad == 0.1  # equal margins: fine


def test_the_warning_pulses_while_it_lasts_and_is_silent_otherwise():
    watch = JointLimitWatch(rumble_level=0.6, pulse_period_s=0.4)
    assert watch.rumble(0.1) == 0.0
    watch.update(_with(6, 2.85, READY_POSE_RAD))
    assert [watch.rumble(t) for t in (0.0, 0.199, 0.2, 0.399, 0.4)] == [0.6, 0.6, 0.0, 0.0, 0.6]
    watch.clear()
    assert watch.rumble(0.0) == 0.0 and watch.warning is None


@pytest.mark.parametrize("kwargs, words", [
    ({"warn_margin_rad": 0.0}, "warn_margin_rad"),
    ({"warn_margin_rad": 0.2, "clear_margin_rad": 0.1}, "at least warn_margin_rad"),
    ({"rumble_level": 1.5}, "rumble_level"),
    ({"pulse_period_s": -1.0}, "pulse_period_s"),
])
def test_an_unusable_warning_setting_names_itself(kwargs, words):
    with pytest.raises(JointsError, match=words):
        JointLimitWatch(**kwargs)


@given(st.lists(st.floats(-3.2, 3.8), min_size=7, max_size=7))
def test_the_nearest_limit_is_never_farther_than_any_joints_limit(q):
    near = nearest_limit(q)
    for j in range(7):
        assert near.margin_rad <= q[j] - L.position_min_rad[j] + 1e-12
        assert near.margin_rad <= L.position_max_rad[j] - q[j] + 1e-12


@pytest.mark.parametrize("cause, words", [
    (ReflexCause(CARTESIAN_VELOCITY_LIMITS_VIOLATION, "translation", 1.8, 1.7), ["faster than", "1.8 m/s", "k_trans"]),
    (ReflexCause(CARTESIAN_VELOCITY_DISCONTINUITY, "rotation", 40.0, 25.0), ["rotation velocity jumped", "never step"]),
    (ReflexCause(CARTESIAN_ACCELERATION_DISCONTINUITY, "translation", 9e4, 6500.0), ["jerk", "Ramp"]),
    (ReflexCause(NON_FINITE_COMMAND, "translation", math.nan, math.inf), ["NaN or infinity"]),
    (ReflexCause(JOINT_POSITION_LIMITS_VIOLATION, "joint 7", 2.8974, 2.8973), ["joint 7 reached its upper limit",
                                                                               "turn the other way"]),
    (ReflexCause(JOINT_POSITION_LIMITS_VIOLATION, "joint 4", -3.08, -3.0718), ["lower limit"]),
    (ReflexCause(JOINT_VELOCITY_LIMITS_VIOLATION, "joint 2", 3.1, 2.175), ["Joint 2", "singular pose"]),
    (ReflexCause(JOINT_VELOCITY_LIMITS_VIOLATION, "joint 2", math.inf, 2.175), ["an infinite speed"]),
    (ReflexCause(JOINT_VELOCITY_DISCONTINUITY, "joint 2", -12.0, 7.5), ["Joint 2's velocity jumped", "12"]),
    (ReflexCause(JOINT_ACCELERATION_DISCONTINUITY, "joint 4", 9000.0, 6250.0), ["Joint 4's acceleration jumped"]),
    (ReflexCause("power_limit_violation", "joint 1", 1.0, 0.5), ["power_limit_violation"]),
])
def test_each_reflex_is_explained_in_plain_words(cause, words):
    text = explain_cause(cause)
    for word in words:
        assert word in text, text


def test_an_explanation_names_each_error_once_and_ends_with_how_to_recover():
    causes = [ReflexCause(JOINT_VELOCITY_DISCONTINUITY, "joint 2", 8.0, 7.5),
              ReflexCause(JOINT_VELOCITY_DISCONTINUITY, "joint 2", 8.0, 7.5),
              ReflexCause(JOINT_ACCELERATION_DISCONTINUITY, "joint 2", 9000.0, 3750.0)]
    lines = explain_reflex(causes)
    assert lines[0].startswith("The robot stopped itself") and lines[-1] == RECOVERY_HINT
    assert len(lines) == 4 and lines[1].endswith(f"[libfranka: {JOINT_VELOCITY_DISCONTINUITY}]")
    assert explain_reflex([]) == ["No reflex: the robot accepts commands."]


# -- the edges (make mutants) ----------------------------------------------------------------------------------------

def _square(velocity: float = 0.5) -> JointLimits:
    """Every joint within -1 .. 1 rad: margins exact in floating point."""
    return JointLimits(position_min_rad=(-1.0,) * 7, position_max_rad=(1.0,) * 7, velocity_rad_per_s=(velocity,) * 7,
                       acceleration_rad_per_s2=(1.0,) * 7, jerk_rad_per_s3=(1.0,) * 7)


@pytest.mark.parametrize("velocity", [1e-9, 0.5, 1.0, 2.0])
def test_any_positive_derivative_limit_is_accepted_below_1_too(velocity):
    assert _square(velocity).velocity_rad_per_s == (velocity,) * 7


def test_a_limit_that_is_not_7_numbers_is_refused_naming_its_field_exactly():
    with pytest.raises(JointsError) as info:
        JointLimits(position_min_rad=(-1.0,) * 7, position_max_rad=(1.0,) * 7, velocity_rad_per_s=2.0,
                    acceleration_rad_per_s2=(1.0,) * 7, jerk_rad_per_s3=(1.0,) * 7)
    assert str(info.value) == "JointLimits.velocity_rad_per_s must be 7 finite numbers, one per joint, got 2.0"


@pytest.mark.parametrize("position", [0.5, None, (0.0,) * 6])
def test_a_position_that_is_not_7_numbers_is_refused_naming_position_rad(position):
    with pytest.raises(JointsError) as info:
        nearest_limit(position)
    assert str(info.value) == f"position_rad must be 7 finite numbers, one per joint, got {position!r}"


def test_numpy_positions_of_any_precision_are_joint_positions():
    import numpy as np

    q = np.array([0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0], dtype=np.float32)
    assert nearest_limit(q, _square()) == LimitDistance(3, 0.5, "max", 0.5, 1.0)
    assert positions_by_name(list(JOINT_NAMES), list(q)) == (0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0)
    assert positions_by_name(list(JOINT_NAMES), [np.int64(0)] * 7) == ZERO7


def test_asking_a_joint_state_for_other_than_7_joints_is_refused_naming_position_rad():
    with pytest.raises(JointsError) as info:
        positions_by_name(["a", "b"], [0.5, 0.25], joint_names=["a", "b"])
    assert str(info.value) == "position_rad must be 7 finite numbers, one per joint, got [0.5, 0.25]"


def test_of_joints_equally_near_a_limit_the_first_and_its_min_side_are_named():
    assert nearest_limit(ZERO7, _square()) == LimitDistance(1, 1.0, "min", 0.0, -1.0)
    assert nearest_limit((0.0, 0.5, 0.0, -0.5, 0.0, 0.0, 0.5), _square()) == LimitDistance(2, 0.5, "max", 0.5, 1.0)


def test_a_watch_judges_at_its_own_limits():
    watch = JointLimitWatch(limits=_square())
    near = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.9375)  # 0.0625 rad from joint 7's max here, far from the Panda's limits
    assert watch.update(near) == LimitDistance(7, 0.0625, "max", 0.9375, 1.0)


@pytest.mark.parametrize("kwargs, message", [
    ({"rumble_level": -0.001}, "rumble_level must be in [0, 1], got -0.001; e.g. 0.6"),
    ({"rumble_level": 1.001}, "rumble_level must be in [0, 1], got 1.001; e.g. 0.6"),
    ({"pulse_period_s": 0.0}, "pulse_period_s must be a positive time in s, got 0.0; e.g. 0.4"),
])
def test_a_warning_setting_out_of_range_is_refused_exactly(kwargs, message):
    with pytest.raises(JointsError) as info:
        JointLimitWatch(**kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize("level", [0.0, 1.0])
def test_a_warning_rumble_of_0_or_1_is_accepted(level):
    watch = JointLimitWatch(limits=_square(), rumble_level=level, pulse_period_s=1e-9)
    watch.update((0.95,) + (0.0,) * 6)
    assert watch.rumble(0.0) == level


def test_before_any_joint_state_nothing_expires_and_nothing_rumbles():
    warning = JointStateWarning(JointLimitWatch(limits=_square()))
    assert warning.expire(10.0) is False
    assert warning.rumble(10.0) == 0.0


def test_a_watch_already_warning_when_handed_over_pulses_from_time_0():
    watch = JointLimitWatch(limits=_square())  # pulse 0.4 s, on for its first half, at 0.6
    watch.update((0.95,) + (0.0,) * 6)
    warning = JointStateWarning(watch)
    assert [warning.rumble(t) for t in (0.0, 0.125, 0.25, 0.375, 0.5)] == [0.6, 0.6, 0.0, 0.0, 0.6]
