"""The simulated Franka arm's Cartesian side judges commands as the robot does, stops as it does, and
moves as commanded.

These tests isolate the twist: the hand alone (``joints=False``) behind a controller that holds each
command (``controller="hold"``), the arm as the Cartesian judge sees it. The key agreement: a stream
from hri_teleop.core.limits.TwistLimiter with the lab's DEFAULT_LIMITS at 50 Hz, held at 1 kHz,
never trips the Cartesian judge; steps do, with libfranka's error names. The joints and the lab's
interpolating controller: test_sim_arm_joints.py.
"""

from __future__ import annotations

import math
import re
from typing import List, Optional, Sequence, Tuple

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core.joints import READY_POSE_RAD
from hri_teleop.core.limits import (
    DEFAULT_LIMITS,
    ROBOT_LIMITS,
    ROBOT_PERIOD_S,
    AxisLimits,
    CartesianLimits,
    TwistLimiter,
    hold_at_robot_rate,
    limit_violations,
)
from hri_teleop.sim.arm import (
    ACCELERATION_DISCONTINUITY,
    EVENT_IGNORED,
    EVENT_RECOVERED,
    EVENT_REFLEX,
    EVENT_TIMEOUT,
    EVENT_WORKSPACE,
    LIBFRANKA_ERROR_FOR,
    NON_FINITE_COMMAND,
    STATE_IDLE,
    STATE_MOVING,
    STATE_REFLEX,
    STATE_TIMEOUT,
    VELOCITY_DISCONTINUITY,
    VELOCITY_LIMITS_VIOLATION,
    SimArm,
    SimArmConfig,
    SimArmError,
)

RATE_HZ = 50.0
ZERO = (0.0,) * 6
#: The hand alone behind a holding controller: the Cartesian judge on its own.
HAND = {"joints": False, "controller": "hold", "stop_limits": None}


def drive(arm: SimArm, limiter: TwistLimiter, targets: Sequence[Sequence[float]], rate_hz: float = RATE_HZ,
          t0_s: Optional[float] = None) -> float:
    """Send limiter.step(target) at rate_hz and run the arm between commands; returns the last command time."""
    dt = 1.0 / rate_hz
    t = arm.time_s if t0_s is None else t0_s
    for target in targets:
        t += dt
        arm.command(limiter.step(target, dt), t)
        arm.run_until(t)
    return t


def ramp_to(arm: SimArm, target: Sequence[float], limits: CartesianLimits = ROBOT_LIMITS,
            seconds: float = 0.5) -> float:
    """Reach ``target`` smoothly with commands every 1 ms; returns the time of the last command."""
    limiter = TwistLimiter(limits)
    t = arm.time_s
    for _ in range(int(round(seconds / ROBOT_PERIOD_S))):
        t += ROBOT_PERIOD_S
        arm.command(limiter.step(target, ROBOT_PERIOD_S), t)
        arm.step(t)
    assert arm.violation_count == 0, arm.violations
    assert arm.commanded_velocity == tuple(float(c) for c in target), "the ramp did not land on the target"
    return t


def hold(arm: SimArm, twist: Sequence[float], seconds: float, rate_hz: float = RATE_HZ) -> int:
    """Keep sending the same twist at rate_hz for ``seconds`` (as a node does); returns the cycles run."""
    t0 = arm.time_s
    cycles = 0
    for k in range(int(round(seconds * rate_hz))):
        t = t0 + k / rate_hz
        arm.command(twist, t)
        cycles += arm.run_until(t + 1.0 / rate_hz)
    return cycles


def quat_mul(p: Sequence[float], q: Sequence[float]) -> Tuple[float, float, float, float]:
    px, py, pz, pw = p
    qx, qy, qz, qw = q
    return (pw * qx + qw * px + py * qz - pz * qy,
            pw * qy + qw * py + pz * qx - px * qz,
            pw * qz + qw * pz + px * qy - py * qx,
            pw * qw - px * qx - py * qy - pz * qz)


def quat_conj(q: Sequence[float]) -> Tuple[float, float, float, float]:
    return (-q[0], -q[1], -q[2], q[3])


def rotation_between(q0: Sequence[float], q1: Sequence[float]) -> Tuple[float, Tuple[float, float, float]]:
    """Angle (rad, in [0, pi]) and unit axis of the base-frame rotation taking q0 to q1."""
    x, y, z, w = quat_mul(q1, quat_conj(q0))
    if w < 0:
        x, y, z, w = -x, -y, -z, -w
    s = math.sqrt(x * x + y * y + z * z)
    angle = 2.0 * math.atan2(s, w)
    axis = (x / s, y / s, z / s) if s > 0 else (0.0, 0.0, 0.0)
    return angle, axis


# --- configuration ------------------------------------------------------------------------------


def test_default_config_is_the_panda_at_its_ready_pose():
    arm = SimArm()
    assert arm.config.limits == ROBOT_LIMITS and arm.config.joints and arm.config.controller == "interpolate"
    assert arm.joint_positions == pytest.approx(READY_POSE_RAD, abs=2e-3)
    assert arm.config.timeout_s == 0.1
    assert arm.pose.position_m == (0.3069, 0.0, 0.4867)
    assert arm.pose.orientation_xyzw == (1.0, 0.0, 0.0, 0.0)  # pointing down
    assert arm.state == STATE_IDLE and arm.velocity == ZERO and arm.violation_count == 0
    assert "idle" in arm.status


@pytest.mark.parametrize("kwargs, words", [
    (dict(timeout_s=0), "timeout_s"),
    (dict(timeout_s=True), "timeout_s"),
    (dict(workspace_min_m=(0.9, -0.5, 0.05)), "workspace x"),
    (dict(workspace_max_m=(0.8, 0.5)), "workspace_max_m"),
    (dict(start_position_m=(0.1, 0.0, 0.4)), "outside the workspace"),
    (dict(start_orientation_xyzw=(1.0, 1.0, 0.0, 0.0)), "unit quaternion"),
    (dict(start_position_m=(0.3, float("nan"), 0.4)), "finite"),
    (dict(stop_limits=CartesianLimits(AxisLimits(2.0, 13, 6500), AxisLimits(2.5, 25, 12500))), "stop_limits"),
    (dict(limits="panda"), "CartesianLimits"),
])
def test_config_refuses_what_cannot_be_simulated_and_says_why(kwargs, words):
    with pytest.raises(SimArmError, match=words):
        SimArmConfig(**kwargs)


def test_config_normalises_the_start_quaternion():
    q = SimArmConfig(start_orientation_xyzw=(0.0, 0.0, 0.0, 1.0000001)).start_orientation_xyzw
    assert math.isclose(math.sqrt(sum(c * c for c in q)), 1.0, rel_tol=0, abs_tol=1e-15)


# --- the judge -----------------------------------------------------------------------------------


def test_a_step_to_0_1_m_s_is_an_acceleration_and_jerk_violation_and_a_reflex():
    arm = SimArm(SimArmConfig(**HAND))
    arm.command((0.1, 0, 0, 0, 0, 0), 0.0)
    assert arm.run_until(0.010) == 10
    assert arm.state == STATE_REFLEX
    # 0.1 m/s in 1 ms: 100 m/s^2 > 13 and 1e5 m/s^3 > 6500; the velocity itself is fine
    assert arm.reflex_errors == (VELOCITY_DISCONTINUITY, ACCELERATION_DISCONTINUITY)
    assert [(v.error, v.group, v.limit) for v in arm.violations] == [
        (VELOCITY_DISCONTINUITY, "translation", 13.0), (ACCELERATION_DISCONTINUITY, "translation", 6500.0)]
    assert arm.violations[0].value == pytest.approx(100.0) and arm.violations[1].value == pytest.approx(1e5)
    assert arm.violations[0].time_s == pytest.approx(0.001)  # the very first cycle
    assert arm.violation_counts == {VELOCITY_DISCONTINUITY: 1, ACCELERATION_DISCONTINUITY: 1}
    assert arm.velocity == ZERO and arm.pose.position_m == (0.3069, 0.0, 0.4867)  # aborted, not moved
    assert arm.reflex_message == ('libfranka: Move command aborted: motion aborted by reflex! '
                                  '["cartesian_motion_generator_velocity_discontinuity", '
                                  '"cartesian_motion_generator_acceleration_discontinuity"]')
    assert arm.reflex_message in arm.status and "recover()" in arm.status
    assert [e.kind for e in arm.events] == [EVENT_REFLEX]


def test_a_small_step_breaks_only_the_jerk_limit():
    """8 mm/s in 1 ms is 8 m/s^2 (< 13) but 8000 m/s^3 (> 6500)."""
    arm = SimArm(SimArmConfig(**HAND))
    arm.command((0.0, 0.008, 0, 0, 0, 0), 0.0)
    arm.run_until(0.002)
    assert arm.reflex_errors == (ACCELERATION_DISCONTINUITY,)


@pytest.mark.parametrize("group, axis, limit", [("translation", 0, 1.7), ("rotation", 5, 2.5)])
def test_above_the_velocity_limit_is_a_velocity_limits_violation(group, axis, limit):
    arm = SimArm(SimArmConfig(**HAND))
    target = [0.0] * 6
    target[axis] = limit  # the limiter stops a hair below the limit
    limiter = TwistLimiter(ROBOT_LIMITS)
    t = 0.0
    for _ in range(500):
        t += ROBOT_PERIOD_S
        arm.command(limiter.step(target, ROBOT_PERIOD_S), t)
        arm.step(t)
    assert arm.violation_count == 0 and arm.state == STATE_MOVING
    over = list(arm.commanded_velocity)
    over[axis] += 0.004  # 4 m/s^2, 4000 /s^3: only the velocity is out
    arm.command(over, t + ROBOT_PERIOD_S)
    arm.step(t + ROBOT_PERIOD_S)
    assert arm.state == STATE_REFLEX
    assert arm.reflex_errors == (VELOCITY_LIMITS_VIOLATION,)
    (v,) = arm.violations
    assert v.group == group and v.limit == limit and v.value == pytest.approx(limit + 0.004)


def test_a_non_finite_command_stops_the_arm_as_libfranka_refuses_it():
    arm = SimArm(SimArmConfig(**HAND))
    assert arm.command((0, 0, float("nan"), 0, 0, 0), 0.0)
    arm.run_until(0.001)
    assert arm.state == STATE_REFLEX and arm.reflex_errors == (NON_FINITE_COMMAND,)
    assert arm.violations[0].group == "translation" and math.isnan(arm.violations[0].value)
    assert arm.pose.position_m == (0.3069, 0.0, 0.4867)


def test_reflex_ignores_commands_until_recover_then_starts_from_rest():
    arm = SimArm(SimArmConfig(**HAND))
    arm.command((0.1, 0, 0, 0, 0, 0), 0.0)
    arm.run_until(0.005)
    assert arm.state == STATE_REFLEX
    for k in range(5):
        assert arm.command((0.0, 0.001, 0, 0, 0, 0), 0.006 + k * 0.001) is False
    arm.run_until(0.5)
    assert arm.ignored_command_count == 5
    assert arm.state == STATE_REFLEX and arm.velocity == ZERO
    assert arm.pose.position_m == (0.3069, 0.0, 0.4867)
    assert [e.kind for e in arm.events] == [EVENT_REFLEX, EVENT_IGNORED]  # ignored: reported once
    assert "recover()" in arm.events[-1].message

    assert arm.recover(0.5) is True
    assert arm.recover(0.5) is False  # nothing left to recover
    assert arm.state == STATE_IDLE and arm.reflex_errors == () and arm.reflex_message == ""
    assert arm.events[-1].kind == EVENT_RECOVERED
    arm.run_until(1.0)  # the held step was dropped: nothing moves, no new reflex
    assert arm.state == STATE_IDLE and arm.violation_count == 2
    drive(arm, TwistLimiter(DEFAULT_LIMITS), [(0.1, 0, 0, 0, 0, 0)] * 50)
    assert arm.state == STATE_MOVING and arm.violation_count == 2
    assert arm.pose.position_m[0] > 0.3069


def test_violations_accumulate_over_reflexes():
    arm = SimArm(SimArmConfig(**HAND))
    for k in range(3):
        arm.command((0.0, 0.0, 0.0, 0.0, 0.0, 1.0), k * 1.0)  # 1 rad/s in 1 ms: 1000 rad/s^2 > 25
        arm.run_until(k * 1.0 + 0.01)
        arm.recover(k * 1.0 + 0.01)
    assert arm.violation_counts == {VELOCITY_DISCONTINUITY: 3, ACCELERATION_DISCONTINUITY: 3}
    assert arm.violation_count == 6 and all(v.group == "rotation" for v in arm.violations)


def _sim_first_reflex(twists: Sequence[Sequence[float]]) -> Tuple[Optional[int], List[Tuple[str, str]]]:
    arm = SimArm(SimArmConfig(**HAND, workspace_min_m=(-1e6,) * 3, workspace_max_m=(1e6,) * 3, timeout_s=1.0))
    for k, twist in enumerate(twists):
        t = (k + 1) * ROBOT_PERIOD_S
        arm.command(twist, t)
        arm.step(t)
        if arm.state == STATE_REFLEX:
            quantity = {name: what for what, name in LIBFRANKA_ERROR_FOR.items()}
            return k, sorted((v.group, quantity[v.error]) for v in arm.violations)
    return None, []


def _first_problem(twists: Sequence[Sequence[float]]) -> Tuple[Optional[int], List[Tuple[str, str]]]:
    problems = limit_violations(ROBOT_LIMITS, twists, [ROBOT_PERIOD_S] * len(twists))
    if not problems:
        return None, []
    first = int(problems[0].split(":")[0].split()[1])
    found = [re.match(r"step \d+: (\w+) (\w+) ", p).groups() for p in problems if p.startswith(f"step {first}:")]
    return first, sorted(found)


@st.composite
def kilohertz_sequences(draw):
    """1 kHz command sequences: a random walk with a random step size, some on top of a smooth
    approach to just below a velocity limit (so velocity violations come up too)."""
    scale = draw(st.sampled_from([1e-5, 1e-4, 1e-3, 5e-3, 2e-2]))
    near = draw(st.sampled_from([None, (0, 1.6999), (4, 2.4999)]))
    steps = draw(st.lists(st.tuples(*[st.floats(-1.0, 1.0)] * 6), min_size=1, max_size=40))
    out: List[Tuple[float, ...]] = []
    if near is not None:
        limiter = TwistLimiter(ROBOT_LIMITS)
        target = [0.0] * 6
        target[near[0]] = near[1]
        out = [limiter.step(target, ROBOT_PERIOD_S) for _ in range(400)]
    v = list(out[-1]) if out else [0.0] * 6
    for step in steps:
        v = [c + scale * d for c, d in zip(v, step)]
        out.append(tuple(v))
    return out


@settings(max_examples=150, deadline=None)
@given(kilohertz_sequences())
def test_the_sim_judges_exactly_as_limit_violations(twists):
    """Same cycle, same errors as hri_teleop.core.limits.limit_violations on any 1 kHz sequence."""
    assert _sim_first_reflex(twists) == _first_problem(twists)


# --- the key agreement: limiter at 50 Hz, held at 1 kHz, never trips the robot ----------------------


def test_a_limited_50_hz_stream_held_at_1_khz_has_no_violation():
    arm = SimArm(SimArmConfig(**HAND))
    targets = ([(0.1, 0, 0, 0, 0, 0)] * 50 + [(0, -0.1, 0.05, 0, 0, 0.3)] * 50 + [(-0.1, 0.1, -0.1, 0.3, -0.3, 0)] * 10
               + [ZERO] * 60)
    drive(arm, TwistLimiter(DEFAULT_LIMITS), targets)
    assert arm.violations == () and arm.events == ()
    assert arm.state == STATE_IDLE and arm.velocity == ZERO


finite_or_wild = st.one_of(st.floats(-0.3, 0.3), st.sampled_from([0.0, 10.0, -10.0, float("nan"), float("inf")]))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.tuples(*[finite_or_wild] * 6), st.integers(1, 40)), min_size=1, max_size=8))
def test_any_limited_50_hz_stream_held_at_1_khz_has_no_violation(segments):
    targets = [target for target, repeat in segments for _ in range(repeat)]
    limiter = TwistLimiter(DEFAULT_LIMITS)
    commands = [limiter.step(target, 1.0 / RATE_HZ) for target in targets]
    held = hold_at_robot_rate(commands, RATE_HZ)
    assert limit_violations(ROBOT_LIMITS, held, [ROBOT_PERIOD_S] * len(held)) == []
    arm = SimArm(SimArmConfig(**HAND, workspace_min_m=(-1e3,) * 3, workspace_max_m=(1e3,) * 3))
    t = 0.0
    for command in commands:
        t += 1.0 / RATE_HZ
        arm.command(command, t)
        arm.run_until(t)
    assert arm.violations == ()
    assert arm.state in (STATE_IDLE, STATE_MOVING)


# --- command timeout ---------------------------------------------------------------------------------


def test_a_timeout_ramps_to_zero_without_violation_and_is_reported_once():
    arm = SimArm(SimArmConfig(**HAND))
    last = drive(arm, TwistLimiter(DEFAULT_LIMITS), [(0.1, 0, 0, 0, 0, 0.3)] * 40)
    assert arm.state == STATE_MOVING and arm.velocity[0] == pytest.approx(0.1)
    arm.run_until(last + 0.1)  # exactly timeout_s old: still holding
    assert arm.state == STATE_MOVING and arm.velocity[0] == pytest.approx(0.1)
    speeds = []
    t = arm.time_s
    for _ in range(100):
        t += ROBOT_PERIOD_S
        arm.step(t)
        speeds.append(arm.commanded_velocity[0])
    assert arm.state == STATE_TIMEOUT
    assert arm.violations == ()
    assert arm.velocity == ZERO and arm.commanded_velocity == ZERO  # reached exactly
    assert all(b <= a for a, b in zip(speeds, speeds[1:])), "the ramp is monotonic"
    assert 0.0 < speeds[0] < 0.1 and speeds.index(0.0) < 20  # a ramp, not a step; about 8 ms
    timeouts = [e for e in arm.events if e.kind == EVENT_TIMEOUT]
    assert len(timeouts) == 1 and timeouts[0].time_s == pytest.approx(last + 0.101)
    assert "no velocity command" in timeouts[0].message and "timeout" in arm.status
    arm.run_until(t + 2.0)
    assert [e.kind for e in arm.events] == [EVENT_TIMEOUT] and arm.state == STATE_TIMEOUT

    # a new command ends the timeout and is judged as usual
    drive(arm, TwistLimiter(DEFAULT_LIMITS), [(0, 0.05, 0, 0, 0, 0)] * 30)
    assert arm.state == STATE_MOVING and arm.violations == ()


def test_no_timeout_before_the_first_command():
    arm = SimArm(SimArmConfig(**HAND))
    arm.run_until(5.0)
    assert arm.state == STATE_IDLE and arm.events == ()


def test_a_gentler_stop_ramp_can_be_configured():
    config = SimArmConfig(**{**HAND, "stop_limits": DEFAULT_LIMITS})
    arm = SimArm(config)
    last = drive(arm, TwistLimiter(DEFAULT_LIMITS), [(0.1, 0, 0, 0, 0, 0)] * 40)
    arm.run_until(last + 0.2)
    assert arm.state == STATE_TIMEOUT and 0.0 < arm.velocity[0] < 0.1  # still braking after 0.1 s
    arm.run_until(last + 1.0)
    assert arm.velocity == ZERO and arm.violations == ()


@settings(max_examples=60, deadline=None)
@given(st.tuples(*[st.floats(-3.0, 3.0)] * 6), st.integers(1, 300))
def test_a_timeout_in_mid_acceleration_still_ramps_without_violation(target, n_commands):
    """timeout_s below one cycle: the stop starts while the command is still accelerating."""
    arm = SimArm(SimArmConfig(**HAND, timeout_s=0.0005, workspace_min_m=(-1e3,) * 3, workspace_max_m=(1e3,) * 3))
    limiter = TwistLimiter(ROBOT_LIMITS)
    t = 0.0
    for _ in range(n_commands):
        t += ROBOT_PERIOD_S
        arm.command(limiter.step(target, ROBOT_PERIOD_S), t)
        arm.step(t)
    arm.run_until(t + 0.5)
    assert arm.violations == ()
    assert arm.state == STATE_TIMEOUT and arm.commanded_velocity == ZERO


# --- workspace box -----------------------------------------------------------------------------------


def test_the_workspace_box_holds_and_the_arm_slides_along_the_wall():
    arm = SimArm(SimArmConfig(**HAND))
    limiter = TwistLimiter(DEFAULT_LIMITS)
    # towards x max (0.8 m, 0.49 m away) at 0.2 m/s and along y: the wall is reached after about 3 s
    drive(arm, limiter, [(0.2, 0.02, 0, 0, 0, 0)] * 200)
    x, y, _ = arm.pose.position_m
    assert x == 0.8
    assert arm.state == STATE_MOVING and arm.violations == ()  # a wall is not a reflex
    assert arm.velocity == (0.0, 0.02, 0.0, 0.0, 0.0, 0.0)  # the outward component is not applied
    assert arm.commanded_velocity == (0.2, 0.02, 0.0, 0.0, 0.0, 0.0)  # the judge still sees the command
    hold(arm, arm.commanded_velocity, 0.5)
    assert arm.pose.position_m[0] == 0.8 and arm.pose.position_m[1] == pytest.approx(y + 0.01)
    walls = [e for e in arm.events if e.kind == EVENT_WORKSPACE]
    assert len(walls) == 1 and "x at its max 0.8 m" in walls[0].message  # reported when contact begins

    drive(arm, limiter, [(-0.1, 0, 0, 0, 0, 0)] * 100)  # away from the wall: it lets go at once
    assert arm.pose.position_m[0] < 0.7 and arm.velocity[0] == pytest.approx(-0.1)
    drive(arm, limiter, [(0.2, 0, 0, 0, 0, 0)] * 100)  # and back: a new contact, a new event
    assert arm.pose.position_m[0] == 0.8
    assert len([e for e in arm.events if e.kind == EVENT_WORKSPACE]) == 2 and arm.violations == ()


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(*[st.floats(-0.25, 0.25)] * 3), min_size=1, max_size=6))
def test_the_arm_never_leaves_the_box(directions):
    config = SimArmConfig(**HAND)
    arm = SimArm(config)
    targets = [(vx, vy, vz, 0.0, 0.0, 0.0) for vx, vy, vz in directions for _ in range(100)]
    limiter = TwistLimiter(DEFAULT_LIMITS)
    t = 0.0
    for target in targets:
        t += 1.0 / RATE_HZ
        arm.command(limiter.step(target, 1.0 / RATE_HZ), t)
        arm.run_until(t)
        p = arm.pose.position_m
        assert all(lo <= c <= hi for lo, c, hi in zip(config.workspace_min_m, p, config.workspace_max_m)), p
    assert arm.violations == ()


# --- pose integration --------------------------------------------------------------------------------


def test_constant_vx_for_one_second_moves_0_1_m():
    arm = SimArm(SimArmConfig(**HAND))
    ramp_to(arm, (0.1, 0, 0, 0, 0, 0))
    start = arm.pose
    assert hold(arm, (0.1, 0, 0, 0, 0, 0), 1.0) == 1000
    end = arm.pose
    assert end.position_m[0] - start.position_m[0] == pytest.approx(0.1, abs=1e-12)
    assert end.position_m[1:] == start.position_m[1:] and end.orientation_xyzw == start.orientation_xyzw
    assert arm.velocity == (0.1, 0, 0, 0, 0, 0) and arm.state == STATE_MOVING


@pytest.mark.parametrize("w", [(0, 0, 0.5, ), (0.3, 0, 0), (0.2, -0.4, 1.0)])
def test_constant_angular_velocity_rotates_by_w_times_t_about_w(w):
    arm = SimArm(SimArmConfig(**HAND))
    twist = (0.0, 0.0, 0.0) + tuple(float(c) for c in w)
    ramp_to(arm, twist)
    q0 = arm.pose.orientation_xyzw
    assert hold(arm, twist, 1.0) == 1000
    q1 = arm.pose.orientation_xyzw
    angle, axis = rotation_between(q0, q1)
    speed = math.sqrt(sum(c * c for c in w))
    assert angle == pytest.approx(speed * 1.0, abs=1e-9)
    assert axis == pytest.approx(tuple(c / speed for c in w), abs=1e-9)  # about the base-frame axis
    assert math.sqrt(sum(c * c for c in q1)) == pytest.approx(1.0, abs=1e-15)
    assert arm.pose.position_m == (0.3069, 0.0, 0.4867)


def test_yaw_of_the_downward_gripper_turns_its_x_axis_in_the_base_frame():
    """Pointing down (pi about x) then +0.5 rad about base z: q = (cos 0.25, sin 0.25, 0, 0)."""
    arm = SimArm(SimArmConfig(**HAND))
    ramp_to(arm, (0, 0, 0, 0, 0, 0.5))
    q_ramp = arm.pose.orientation_xyzw
    hold(arm, (0, 0, 0, 0, 0, 0.5), 1.0)
    angle_ramp, _ = rotation_between((1.0, 0.0, 0.0, 0.0), q_ramp)
    half = (angle_ramp + 0.5) / 2.0
    assert arm.pose.orientation_xyzw == pytest.approx((math.cos(half), math.sin(half), 0.0, 0.0), abs=1e-9)


# --- time, inputs, read-outs -------------------------------------------------------------------------


def test_run_until_runs_every_due_cycle_once():
    arm = SimArm(SimArmConfig(**HAND), start_time_s=10.0)
    assert arm.run_until(10.0) == 0
    assert arm.run_until(9.0) == 0
    assert arm.run_until(11.0) == 1000
    assert arm.time_s == pytest.approx(11.0)
    assert arm.run_until(11.0005) == 0
    assert arm.run_until(11.0015) == 1


def test_bad_inputs_are_refused_with_the_fix():
    arm = SimArm(SimArmConfig(**HAND))
    arm.step(0.001)
    with pytest.raises(SimArmError, match="time must move forward"):
        arm.step(0.001)
    with pytest.raises(SimArmError, match="6 values"):
        arm.command((0.0, 0.0, 0.0), 0.002)
    with pytest.raises(SimArmError, match="6 numbers"):
        arm.command("fast", 0.002)
    with pytest.raises(SimArmError, match="finite time"):
        arm.command(ZERO, float("nan"))
    with pytest.raises(SimArmError, match="SimArmConfig"):
        SimArm(config={"timeout_s": 0.1})


def test_new_events_returns_each_event_once():
    arm = SimArm(SimArmConfig(**HAND))
    arm.command((0.1, 0, 0, 0, 0, 0), 0.0)
    arm.run_until(0.01)
    assert [e.kind for e in arm.new_events()] == [EVENT_REFLEX]
    assert arm.new_events() == []
    arm.recover(0.02)
    assert [e.kind for e in arm.new_events()] == [EVENT_RECOVERED]


# --- work per simulated second (its CPU cost: make bench, "Panda joints per 1 kHz cycle") ------------


def _one_simulated_second(arm: SimArm, commands: Sequence[Sequence[float]]) -> int:
    """The 1 ms cycles the arm ran for one simulated second of 50 Hz commands."""
    t0 = arm.time_s
    cycles = 0
    for k, command in enumerate(commands):
        t = t0 + (k + 1) / RATE_HZ
        arm.command(command, t)
        cycles += arm.run_until(t)
    return cycles


def test_one_simulated_second_is_1000_cycles_of_the_seven_joints_under_50_commands():
    """1 s of simulation: 1000 cycles with the seven joints, translating and rotating, 50 commands, and
    the joints move in every second. How fast this runs is a figure of make bench, not a pass/fail here."""
    limiter = TwistLimiter(DEFAULT_LIMITS)
    commands = [limiter.step((0.04, -0.02, 0.01, 0.05, 0.1, 0.2), 1.0 / RATE_HZ) for _ in range(500)]
    arm = SimArm()
    assert arm.joint_positions is not None
    for k in range(5):
        before = arm.joint_positions
        assert _one_simulated_second(arm, commands[50 * k: 50 * (k + 1)]) == 1000
        assert arm.time_s == pytest.approx(k + 1.0, abs=1e-9)
        assert arm.joint_positions != before
    assert arm.violations == () and arm.state == STATE_MOVING
