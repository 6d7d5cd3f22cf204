"""A Franka reflex in plain words (hri_teleop.core.reflex): each sentence exactly as the student reads it,
with and without the robot's numbers, the side of a position limit at its edge, and each error once."""

from __future__ import annotations

import math

import pytest

from hri_teleop.core.reflex import ReflexCause, explain_cause, explain_reflex

nan, inf = math.nan, math.inf

# libfranka's names (franka::Errors), written out: a renamed error in the robot profile must fail these tests.
CART_VELOCITY = "cartesian_motion_generator_velocity_limits_violation"
CART_ACCELERATION = "cartesian_motion_generator_velocity_discontinuity"
CART_JERK = "cartesian_motion_generator_acceleration_discontinuity"
NON_FINITE = "commanding_value_is_infinite_or_nan"
JOINT_POSITION = "cartesian_motion_generator_joint_position_limits_violation"
JOINT_VELOCITY = "cartesian_motion_generator_joint_velocity_limits_violation"
JOINT_ACCELERATION = "cartesian_motion_generator_joint_velocity_discontinuity"
JOINT_JERK = "cartesian_motion_generator_joint_acceleration_discontinuity"

HINT = ("Then recover: press options (start) on the pad, or the notebook's recover button "
        "(franka_control's error_recovery action); the robot accepts commands again from rest.")
BACK = ("After recovering, move back the way you came (in rotation mode, turn the other way) or drive to the "
        "start pose first.")
SINGULAR = ("the arm is near a singular pose (stretched out, or two wrist axes in line), where a small hand motion "
            "needs a large joint motion. Move the hand back towards the middle of the workspace, slowly.")


@pytest.mark.parametrize("cause, text", [
    (ReflexCause(CART_VELOCITY, "translation", 1.8, 1.7),
     "The hand was commanded faster than the robot allows (translation 1.8 m/s, limit 1.7 m/s). "
     "Lower the gains k_trans/k_rot or the velocity limit of the twist limiter."),
    (ReflexCause(CART_VELOCITY, "rotation", 2.6, 2.5),
     "The hand was commanded faster than the robot allows (rotation 2.6 rad/s, limit 2.5 rad/s). "
     "Lower the gains k_trans/k_rot or the velocity limit of the twist limiter."),
    (ReflexCause(CART_ACCELERATION, "rotation", 40.0, 25.0),
     "The commanded rotation velocity jumped: its change within one millisecond is too large an acceleration "
     "(40 rad/s/s, limit 25). Ramp the velocity with the twist limiter, never step it, not even to zero."),
    (ReflexCause(CART_ACCELERATION, "translation", 13.5, 13.0),
     "The commanded translation velocity jumped: its change within one millisecond is too large an acceleration "
     "(13.5 m/s/s, limit 13). Ramp the velocity with the twist limiter, never step it, not even to zero."),
    (ReflexCause(CART_JERK, "translation", 9e4, 6500.0),
     "The commanded translation acceleration jumped: too large a jerk (9e+04 m/s/s^2, limit 6500). "
     "Ramp the velocity smoothly; a step, however small, is a jump of the acceleration."),
    (ReflexCause(NON_FINITE, "translation", nan, inf),
     "A command held NaN or infinity, which the robot refuses. Check the numbers your node computes."),
    (ReflexCause(JOINT_POSITION, "joint 4", -3.08, -3.0718),
     "The hand cannot go further this way: joint 4 reached its lower limit (-3.0800 rad, limit -3.0718 rad). " + BACK),
    (ReflexCause(JOINT_VELOCITY, "joint 2", 3.1, 2.175),
     "Joint 2 would have had to turn too fast (3.1 rad/s, limit 2.175 rad/s): " + SINGULAR),
    (ReflexCause(JOINT_ACCELERATION, "joint 2", -12.0, 7.5),
     "Joint 2's velocity jumped (12 rad/s^2, limit 7.5): for this arm pose the twist changed too abruptly. "
     "Ramp more gently, or move away from a stretched-out pose."),
    (ReflexCause(JOINT_JERK, "joint 4", -9000.0, 6250.0),
     "Joint 4's acceleration jumped (9e+03 rad/s^3, limit 6250): a step in the commanded twist reaches the joints "
     "as a jerk. Ramp the velocity, never step it."),
    (ReflexCause("power_limit_violation", "joint 1", 1.0, 0.5), "power_limit_violation (joint 1: 1, limit 0.5)."),
])
def test_each_reflex_reads_exactly_as_the_student_sees_it(cause, text):
    assert explain_cause(cause) == text


@pytest.mark.parametrize("cause, text", [
    (ReflexCause(CART_VELOCITY, "translation", nan, nan),
     "The hand was commanded faster than the robot allows. "
     "Lower the gains k_trans/k_rot or the velocity limit of the twist limiter."),
    (ReflexCause(CART_ACCELERATION, "translation", nan, nan),
     "The commanded translation velocity jumped: its change within one millisecond is too large an acceleration. "
     "Ramp the velocity with the twist limiter, never step it, not even to zero."),
    (ReflexCause(CART_JERK, "rotation", nan, nan),
     "The commanded rotation acceleration jumped: too large a jerk. "
     "Ramp the velocity smoothly; a step, however small, is a jump of the acceleration."),
    (ReflexCause(JOINT_POSITION, "joint 3", nan, nan),
     "The hand cannot go further this way: joint 3 reached its limit. " + BACK),
    (ReflexCause(JOINT_VELOCITY, "joint 3", nan, nan), "Joint 3 would have had to turn too fast: " + SINGULAR),
    (ReflexCause(JOINT_ACCELERATION, "joint 3", nan, nan),
     "Joint 3's velocity jumped: for this arm pose the twist changed too abruptly. "
     "Ramp more gently, or move away from a stretched-out pose."),
    (ReflexCause(JOINT_JERK, "joint 3", nan, nan),
     "Joint 3's acceleration jumped: a step in the commanded twist reaches the joints as a jerk. "
     "Ramp the velocity, never step it."),
    (ReflexCause("power_limit_violation", "joint 3", nan, nan), "power_limit_violation."),
])
def test_a_reflex_the_robot_gave_no_numbers_for_is_explained_without_them(cause, text):
    assert explain_cause(cause) == text


@pytest.mark.parametrize("value, limit, numbers", [
    (nan, 0.5, "(joint 3: nan, limit 0.5)"),
    (0.5, nan, "(joint 3: 0.5, limit nan)"),
])
def test_a_cause_with_only_one_number_missing_still_shows_both(value, limit, numbers):
    assert explain_cause(ReflexCause("power_limit_violation", "joint 3", value, limit)) == (
        f"power_limit_violation {numbers}.")


@pytest.mark.parametrize("value, side", [(2.8972, "lower"), (2.8973, "upper"), (2.8974, "upper")])
def test_a_position_at_or_above_its_limit_broke_the_upper_limit_below_it_the_lower(value, side):
    assert explain_cause(ReflexCause(JOINT_POSITION, "joint 7", value, 2.8973)) == (
        f"The hand cannot go further this way: joint 7 reached its {side} limit ({value:+.4f} rad, limit +2.8973 rad). "
        + BACK)


@pytest.mark.parametrize("value, speed", [(inf, "an infinite speed"), (-inf, "an infinite speed"), (-3.0, "3 rad/s")])
def test_a_joint_speed_is_shown_without_its_sign_and_an_infinite_one_in_words(value, speed):
    assert explain_cause(ReflexCause(JOINT_VELOCITY, "joint 7", value, 2.61)) == (
        f"Joint 7 would have had to turn too fast ({speed}, limit 2.61 rad/s): " + SINGULAR)


def test_a_reflex_names_each_error_once_where_it_first_broke_in_order_then_how_to_recover():
    causes = [ReflexCause("power_limit_violation", "joint 1", 1.0, 2.0),
              ReflexCause(JOINT_ACCELERATION, "joint 2", 8.0, 7.5),
              ReflexCause("power_limit_violation", "joint 3", 5.0, 2.0),
              ReflexCause(JOINT_ACCELERATION, "joint 4", 9.0, 7.5)]
    assert explain_reflex(causes) == [
        "The robot stopped itself (a reflex) because a command would have broken one of its limits:",
        "- power_limit_violation (joint 1: 1, limit 2). [libfranka: power_limit_violation]",
        "- Joint 2's velocity jumped (8 rad/s^2, limit 7.5): for this arm pose the twist changed too abruptly. "
        "Ramp more gently, or move away from a stretched-out pose. [libfranka: " + JOINT_ACCELERATION + "]",
        HINT,
    ]


def test_no_cause_is_no_reflex():
    assert explain_reflex([]) == ["No reflex: the robot accepts commands."]
