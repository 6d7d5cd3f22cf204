"""The lab's velocity controller never ramps faster than its acceleration bounds (franka_control's rate
limiter): commands that a busy PC delivers at once stop the arm smoothly instead of in a jerk reflex."""

from __future__ import annotations

import dataclasses
from typing import List, Optional, Tuple

import pytest

from hri_teleop.sim.arm import SimArm, SimArmConfig, SimArmError
from hri_teleop.sim.config import default_sim_yaml, load_world_config, world_config_from_dict
from hri_teleop.sim.world import LabWorld

#: the burst L30 recorded: lab_sim's twist subscriber was ~100 ms late, five ramp-down commands came at once
LATE_BURST_M_PER_S = (-0.0088, -0.0054, -0.0029, -0.0011, -0.0002, 0.0)


def _descend_then_late_burst(world: LabWorld) -> LabWorld:
    """The teleoperation node's ramps (0.006 m/s per 20 ms tick) down to -0.09 m/s and back to -0.0416 m/s
    near the table (below 6 cm, where the hand was in L30), then 0.23 s with no command (both nodes starved), then the burst in one instant."""
    t, v = 0.0, 0.0
    for target in (-0.09, -0.0416):
        while abs(v - target) > 1e-12 or (target == -0.09 and world.arm.position_m[2] > 0.06):
            v = max(v - 0.006, target) if target < v else min(v + 0.006, target)
            t += 0.02
            world.advance(t)
            world.command_twist((0.0, 0.0, v, 0.0, 0.0, 0.0), t)
    assert world.arm.position_m[2] < 0.06 and world.arm.reflex_errors == ()
    t += 0.23
    world.advance(t)
    for vz in LATE_BURST_M_PER_S:
        world.command_twist((0.0, 0.0, vz, 0.0, 0.0, 0.0), t)
    for _ in range(20):
        t += 0.02
        world.advance(t)
        world.command_twist((0.0,) * 6, t)
    return world


def _lab_world(**arm: Optional[float]) -> LabWorld:
    config = load_world_config(default_sim_yaml())
    return LabWorld(dataclasses.replace(config, arm=dataclasses.replace(config.arm, **arm)))


def test_the_labs_arm_stops_smoothly_when_late_commands_arrive_at_once():
    world = _descend_then_late_burst(_lab_world())
    assert world.arm.reflex_errors == ()
    assert abs(world.arm.velocity[2]) < 1e-9


def test_without_the_bound_the_same_burst_is_a_joint_jerk_reflex():
    """What L30 saw: the ramp from -0.0416 m/s to 0 in one command period jerks joint 2 past 3750 rad/s^3."""
    world = _descend_then_late_burst(_lab_world(max_ramp_acceleration_m_per_s2=None,
                                                max_ramp_acceleration_rad_per_s2=None))
    assert world.arm.reflex_errors == ("cartesian_motion_generator_joint_acceleration_discontinuity",)


def test_the_lab_config_bounds_the_ramp_at_half_a_metre_and_one_radian_per_second_squared():
    arm = load_world_config(default_sim_yaml()).arm
    assert (arm.max_ramp_acceleration_m_per_s2, arm.max_ramp_acceleration_rad_per_s2) == (0.5, 1.0)


def _ramp(config: SimArmConfig, twist: Tuple[float, ...], until_s: float) -> List[Tuple[float, Tuple[float, ...]]]:
    arm = SimArm(config)
    arm.command(twist, 0.0)
    out = []
    for k in range(1, int(round(until_s / 0.001)) + 1):
        arm.step(k * 0.001)
        out.append((round(k * 0.001, 3), arm.commanded_velocity))
    return out


HAND_ONLY = SimArmConfig(joints=False, timeout_s=1.0)


@pytest.mark.parametrize("twist, axis, bound", [
    ((0.05, 0.0, 0.0, 0.0, 0.0, 0.0), 0, {"max_ramp_acceleration_m_per_s2": 0.5}),
    ((0.0, 0.0, 0.0, 0.0, 0.0, 0.1), 5, {"max_ramp_acceleration_rad_per_s2": 1.0}),
])
def test_a_step_from_rest_takes_change_over_bound_seconds_and_not_one_period(twist, axis, bound):
    """0.05 m/s at 0.5 m/s^2 (0.1 rad/s at 1.0 rad/s^2): 0.1 s, five times the 0.02 s command period."""
    ramp = dict(_ramp(dataclasses.replace(HAND_ONLY, **bound), twist, 0.12))
    assert ramp[0.02][axis] == pytest.approx(twist[axis] * 0.2, rel=0.06)
    assert ramp[0.09][axis] < twist[axis]
    assert ramp[0.1][axis] == pytest.approx(twist[axis])
    unbounded = dict(_ramp(HAND_ONLY, twist, 0.12))
    assert unbounded[0.02][axis] == pytest.approx(twist[axis])


def test_the_teleoperation_nodes_own_ramp_is_left_as_it_is():
    """0.006 m/s per 20 ms tick is 0.3 m/s^2: below the bound, the path is the same with and without it."""
    paths = []
    for bound in (None, 0.5):
        arm = SimArm(dataclasses.replace(HAND_ONLY, max_ramp_acceleration_m_per_s2=bound))
        path = []
        for tick in range(30):
            arm.command((min(0.006 * (tick + 1), 0.09), 0.0, 0.0, 0.0, 0.0, 0.0), tick * 0.02)
            for k in range(1, 21):
                arm.step(tick * 0.02 + k * 0.001)
                path.append(arm.commanded_velocity[0])
        paths.append(path)
    assert paths[0] == paths[1]


@pytest.mark.parametrize("bad", [0.0, -0.5, float("nan"), float("inf")])
def test_a_bound_that_is_not_a_positive_number_is_refused_with_its_name(bad):
    with pytest.raises(SimArmError, match="max_ramp_acceleration_m_per_s2 must be a positive number"):
        SimArmConfig(max_ramp_acceleration_m_per_s2=bad)


def test_the_bounds_are_read_from_the_sim_yaml_arm_section():
    config = world_config_from_dict({"arm": {"max_ramp_acceleration_m_per_s2": 0.7,
                                             "max_ramp_acceleration_rad_per_s2": 1.5}})
    assert (config.arm.max_ramp_acceleration_m_per_s2, config.arm.max_ramp_acceleration_rad_per_s2) == (0.7, 1.5)
