"""The simulated Panda's joints: they follow the hand, the robot's joint-side checks judge them, and the
lab's velocity controller interpolates between commands so a smooth stream passes and a step does not."""

from __future__ import annotations

import math
from typing import List, Sequence, Tuple

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core.joints import (
    JOINT_ACCELERATION_DISCONTINUITY,
    JOINT_POSITION_LIMITS_VIOLATION,
    JOINT_VELOCITY_DISCONTINUITY,
    JOINT_VELOCITY_LIMITS_VIOLATION,
    READY_POSE_RAD,
    ROBOT_JOINT_LIMITS,
)
from hri_teleop.core.limits import DEFAULT_LIMITS, TwistLimiter
from hri_teleop.core.reflex import explain_reflex
from hri_teleop.sim.arm import (
    STATE_IDLE,
    STATE_MOVING,
    STATE_REFLEX,
    VELOCITY_DISCONTINUITY,
    SimArm,
    SimArmConfig,
    SimArmError,
)
from hri_teleop.sim.joint_motion import JointMotion
from hri_teleop.sim.kinematics import PandaKinematics
from hri_teleop.sim.world import LAB_ARM_CONFIG

RATE_HZ = 50.0
JOINT_ERRORS = {JOINT_POSITION_LIMITS_VIOLATION, JOINT_VELOCITY_LIMITS_VIOLATION, JOINT_VELOCITY_DISCONTINUITY,
                JOINT_ACCELERATION_DISCONTINUITY}


def drive(arm: SimArm, targets: Sequence[Sequence[float]], limiter: TwistLimiter) -> float:
    """The teleoperation node: limiter.step(target) at 50 Hz, the arm run between commands."""
    dt = 1.0 / RATE_HZ
    t = arm.time_s
    for target in targets:
        t += dt
        arm.command(limiter.step(target, dt), t)
        arm.run_until(t)
        if arm.state == STATE_REFLEX:
            break
    return t


def errors(arm: SimArm) -> List[Tuple[str, str]]:
    return sorted({(v.error, v.group) for v in arm.violations})


def test_the_arm_starts_at_the_ready_pose_and_a_start_out_of_reach_is_refused_naming_the_fix():
    arm = SimArm()
    assert arm.joint_positions == pytest.approx(READY_POSE_RAD, abs=2e-3)
    position, _ = PandaKinematics().pose(arm.joint_positions)
    assert position == pytest.approx(arm.pose.position_m, abs=1e-9)
    with pytest.raises(SimArmError, match="out of the Panda's reach.*nearer the ready pose"):
        SimArm(SimArmConfig(start_orientation_xyzw=(0.0, 0.0, 0.0, 1.0)))  # the hand pointing up
    assert SimArm(SimArmConfig(joints=False)).joint_positions is None


def test_the_joints_follow_the_hand_through_translation_and_rotation():
    arm = SimArm(LAB_ARM_CONFIG)
    limiter = TwistLimiter(DEFAULT_LIMITS)
    drive(arm, [(0.05, -0.03, -0.05, 0.1, -0.1, 0.3)] * 100 + [(0.0,) * 6] * 50, limiter)
    assert arm.violations == () and arm.state == STATE_IDLE
    kinematics = PandaKinematics()
    position, (x, y, z, w) = kinematics.pose(arm.joint_positions)
    assert position == pytest.approx(arm.pose.position_m, abs=1e-7)
    qx, qy, qz, qw = arm.pose.orientation_xyzw
    assert abs(x * qx + y * qy + z * qz + w * qw) == pytest.approx(1.0, abs=1e-9)  # the same rotation
    assert arm.joint_positions[2] == pytest.approx(READY_POSE_RAD[2], abs=1e-9)  # the elbow is held
    assert arm.joint_velocities == pytest.approx((0.0,) * 7, abs=1e-9)


def test_the_controller_reaches_a_command_one_interval_after_it_arrived():
    arm = SimArm()
    arm.command((0.0, 0.0, 0.01, 0.0, 0.0, 0.0), 0.0)  # the first after rest: over command_period_s
    arm.run_until(0.019)
    assert arm.commanded_velocity[2] == pytest.approx(0.01 * 19 / 20)
    arm.run_until(0.020)
    assert arm.commanded_velocity[2] == 0.01
    arm.run_until(0.030)  # lab_sim: the world runs up to the message's arrival, then takes it
    arm.command((0.0, 0.0, 0.02, 0.0, 0.0, 0.0), 0.030)  # 30 ms after the one before: over 30 ms
    arm.run_until(0.045)
    assert arm.commanded_velocity[2] == pytest.approx(0.015)
    arm.run_until(0.060)
    assert arm.commanded_velocity[2] == 0.02 and arm.violations == ()
    # a message late and the next right after: not over the 2 ms between them, nor the node's 20 ms,
    # until the late one's ramp would have ended: 32 ms (since 0.030 s) from the arm's 0.060 s, 0.092 s
    arm.command((0.0, 0.0, 0.021, 0.0, 0.0, 0.0), 0.062)
    arm.run_until(0.064)
    before = arm.commanded_velocity[2]
    arm.command((0.0, 0.0, 0.022, 0.0, 0.0, 0.0), 0.064)  # 2 ms after the one before
    arm.run_until(0.065)
    assert arm.commanded_velocity[2] - before == pytest.approx((0.022 - before) / 28)
    arm.run_until(0.091)
    assert arm.commanded_velocity[2] < 0.022 - 1e-6
    arm.run_until(0.092)
    assert arm.commanded_velocity[2] == pytest.approx(0.022, abs=1e-12)
    # a lock-step loop commands first and runs the cycles up to the command's time after: they ramp too
    arm.command((0.0, 0.0, 0.0, 0.0, 0.0, 0.0), 0.104)  # 40 ms after the last: from the arm's 0.092 s on
    arm.run_until(0.104)
    assert arm.commanded_velocity[2] == pytest.approx(0.022 * (1 - 12 / 40))
    assert arm.time_s == pytest.approx(0.104) and arm.violations == ()


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.tuples(*[st.sampled_from([-1.0, -0.3, 0.0, 0.5, 1.0])] * 3), st.integers(1, 25)),
                min_size=1, max_size=6))
def test_any_limited_50_hz_translation_in_the_labs_box_passes_every_check(segments):
    """The teleoperation node's promise, also for the joints, where the lab's box keeps the hand."""
    arm = SimArm(LAB_ARM_CONFIG)
    targets = [(0.1 * a, 0.1 * b, 0.1 * c, 0.0, 0.0, 0.0) for (a, b, c), n in segments for _ in range(n)]
    drive(arm, targets + [(0.0,) * 6] * 40, TwistLimiter(DEFAULT_LIMITS))
    assert arm.violations == (), errors(arm)


def test_the_same_stream_held_without_interpolation_breaks_a_joint_limit_but_no_cartesian_one():
    """Why the controller interpolates: at 50 Hz, each ramp step held for 20 ms reaches the robot within
    1 ms; the Cartesian judge allows it, the joints (about 3 rad per metre here) do not."""
    arm = SimArm(SimArmConfig(controller="hold"))
    drive(arm, [(0.1, 0.0, 0.0, 0.0, 0.0, 0.0)] * 50, TwistLimiter(DEFAULT_LIMITS))
    assert arm.state == STATE_REFLEX
    assert {error for error, _ in errors(arm)} <= JOINT_ERRORS
    assert any(error in (JOINT_VELOCITY_DISCONTINUITY, JOINT_ACCELERATION_DISCONTINUITY) for error, _ in errors(arm))


def test_a_velocity_step_still_stops_the_robot_through_the_joints():
    arm = SimArm()
    arm.command((0.1, 0.0, 0.0, 0.0, 0.0, 0.0), 0.02)  # 0 -> 0.1 m/s, spread over 20 ms: 5 m/s^2, fine
    arm.run_until(0.05)
    assert arm.state == STATE_REFLEX
    assert VELOCITY_DISCONTINUITY not in arm.reflex_errors
    assert set(arm.reflex_errors) <= {JOINT_VELOCITY_DISCONTINUITY, JOINT_ACCELERATION_DISCONTINUITY}
    assert all(v.group.startswith("joint ") for v in arm.reflex_violations)
    assert arm.pose.position_m == pytest.approx(SimArmConfig().start_position_m, abs=1e-5)


def turn_until_reflex(arm: SimArm, wz: float, seconds: float) -> float:
    return drive(arm, [(0.0, 0.0, 0.0, 0.0, 0.0, wz)] * int(seconds * RATE_HZ), TwistLimiter(DEFAULT_LIMITS))


def test_turning_the_hand_about_z_ends_at_joint_7s_limit_with_libfrankas_name():
    arm = SimArm(LAB_ARM_CONFIG)
    # the hand turned about the base's z turns joint 7 the other way: -0.3 rad/s takes it up to +2.8973
    turn_until_reflex(arm, -0.3, 12.0)
    assert arm.state == STATE_REFLEX and arm.reflex_errors == (JOINT_POSITION_LIMITS_VIOLATION,)
    (violation,) = arm.reflex_violations
    assert violation.group == "joint 7" and violation.limit == ROBOT_JOINT_LIMITS.position_max_rad[6]
    assert 2.8973 < violation.value < 2.8973 + 0.3 * 0.001 * 1.01  # the step that would have passed it
    assert arm.joint_positions[6] <= 2.8973  # not moved past it
    text = "\n".join(explain_reflex([violation.cause()]))
    assert "joint 7 reached its upper limit" in text and "turn the other way" in text


def test_after_recovery_turning_back_away_from_the_limit_is_accepted():
    arm = SimArm(LAB_ARM_CONFIG)
    turn_until_reflex(arm, -0.3, 12.0)
    before = arm.joint_positions[6]
    assert arm.recover(arm.time_s) and arm.state == STATE_IDLE
    assert arm.joint_velocities == (0.0,) * 7
    turn_until_reflex(arm, 0.3, 2.0)
    assert arm.state == STATE_MOVING and len(arm.violations) == 1
    assert arm.joint_positions[6] < before - 0.3


def test_stretching_the_arm_out_ends_in_a_joint_side_reflex_before_the_reach():
    """Out beyond the lab's box the arm straightens: a small hand motion needs large joint motion."""
    arm = SimArm(SimArmConfig(workspace_max_m=(1.5, 0.5, 1.5)))
    drive(arm, [(0.1, 0.0, 0.05, 0.0, 0.0, 0.0)] * 600, TwistLimiter(DEFAULT_LIMITS))
    assert arm.state == STATE_REFLEX
    assert {error for error, _ in errors(arm)} <= JOINT_ERRORS
    x, _y, z = arm.pose.position_m
    assert math.hypot(x, z - 0.333) < 0.95  # the shoulder's reach with the hand is about 0.95 m


def test_an_exactly_singular_pose_is_an_infinite_joint_velocity_not_a_crash():
    """Straight up, joints 1, 3, 5 and 7 share one axis: no joint motion moves the hand sideways."""
    straight = np.zeros(7)
    kinematics = PandaKinematics()
    sideways = np.array([[0.1], [0.0], [0.0], [0.0], [0.0], [0.0]])
    assert np.isinf(kinematics.joint_velocities(straight, sideways)).all()
    assert np.isfinite(kinematics.joint_velocities(READY_POSE_RAD, sideways)).all()
    motion = JointMotion(straight)
    broken = motion.step((0.1, 0.0, 0.0, 0.0, 0.0, 0.0), kinematics.position(straight) + [1e-4, 0.0, 0.0],
                         kinematics.rotation(straight), 0.001)
    assert (JOINT_VELOCITY_LIMITS_VIOLATION, 1, math.inf, 2.175) in broken
    assert motion.positions == (0.0,) * 7  # not moved
