"""Commands a busy PC delivers at once never shorten the ramp under way (the interpolating controller).

After a stall, lab_sim's twist subscriber can hand the simulated controller several ramp-down
commands in one instant. Each used to ramp from where the output was to its value in one command
period, so the burst's last command stopped the arm within 20 ms, and near the table that jerked
joint 2 into a reflex. A command now ends its ramp no sooner than the one it replaces; a step sent
at 100 Hz (the reflex lesson) and a steady 50 Hz stream are judged cycle for cycle as before.
"""

from __future__ import annotations

from typing import List

import pytest

from hri_teleop.sim.arm import SimArm, SimArmConfig
from hri_teleop.sim.config import default_sim_yaml, load_world_config
from hri_teleop.sim.world import LabWorld

#: the burst a loaded run recorded: lab_sim's twist subscriber was ~100 ms late, the ramp-down came at once
LATE_BURST_M_PER_S = (-0.0088, -0.0054, -0.0029, -0.0011, -0.0002, 0.0)
HAND_ONLY = SimArmConfig(joints=False, timeout_s=1.0)
X = 0  # the axis these hand-only cases drive


def _near_the_table(speed_m_per_s: float):
    """The lab's world after the teleoperation node's ramps (0.006 m/s per 20 ms tick) down to -0.09 m/s
    and back to ``speed_m_per_s`` below 6 cm (where the hand was in the loaded run); and the time."""
    world = LabWorld(load_world_config(default_sim_yaml()))
    t, v = 0.0, 0.0
    for target in (-0.09, speed_m_per_s):
        while abs(v - target) > 1e-12 or (target == -0.09 and world.arm.position_m[2] > 0.06):
            v = max(v - 0.006, target) if target < v else min(v + 0.006, target)
            t += 0.02
            world.advance(t)
            world.command_twist((0.0, 0.0, v, 0.0, 0.0, 0.0), t)
    assert world.arm.position_m[2] < 0.06 and world.arm.reflex_errors == ()
    return world, t


def _burst_then_on_time(world: LabWorld, t: float, burst_m_per_s) -> LabWorld:
    """The burst's twists at one instant ``t``, then the node's ramp on to zero on time, for 0.6 s."""
    world.advance(t)
    for vz in burst_m_per_s:
        world.command_twist((0.0, 0.0, vz, 0.0, 0.0, 0.0), t)
    vz = burst_m_per_s[-1]
    for _ in range(30):
        t += 0.02
        vz = min(vz + 0.006, 0.0)
        world.advance(t)
        world.command_twist((0.0, 0.0, vz, 0.0, 0.0, 0.0), t)
    return world


def _descend_then_late_burst() -> LabWorld:
    """0.23 s with no command at -0.0416 m/s (both nodes starved), then the recorded burst at once."""
    world, t = _near_the_table(-0.0416)
    return _burst_then_on_time(world, t + 0.23, LATE_BURST_M_PER_S)


def test_the_labs_arm_stops_without_a_reflex_when_late_commands_arrive_at_once():
    world = _descend_then_late_burst()
    assert world.arm.reflex_errors == ()
    assert world.arm.velocity[2] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("speed_m_per_s", [-0.0416, -0.09])
@pytest.mark.parametrize("stalled_ticks", [1, 4, 8, 14])
def test_every_tick_of_a_stall_delivered_at_once_stops_the_arm_without_a_reflex(stalled_ticks, speed_m_per_s):
    """The node kept ramping to zero (0.006 m/s a tick) while lab_sim heard nothing; then all of it at once.

    The old controller ramped to the burst's last twist in 20 ms: a reflex from 4 ticks (80 ms) on.
    """
    world, t = _near_the_table(speed_m_per_s)
    ramp = [min(speed_m_per_s + 0.006 * (k + 1), 0.0) for k in range(stalled_ticks)]
    world = _burst_then_on_time(world, t + 0.02 * stalled_ticks, ramp)
    assert world.arm.reflex_errors == ()


def _send(arm: SimArm, vx: float, at_s: float) -> None:
    """Run the arm's 1 ms cycles up to ``at_s``, then command ``vx`` m/s along x there (as lab_sim does)."""
    arm.run_until(at_s)
    arm.command((vx, 0.0, 0.0, 0.0, 0.0, 0.0), at_s)


def _path(arm: SimArm, to_s: float) -> List[float]:
    """The controller's x output at each 1 ms cycle after the last one, up to ``to_s``."""
    out = []
    while arm.time_s < to_s - 1e-9:
        arm.step(round(arm.time_s + 0.001, 6))
        out.append(arm.commanded_velocity[X])
    return out


def test_a_command_at_once_after_a_late_one_ends_where_the_late_ones_ramp_ends():
    """80 ms without a command: the next ramps over 80 ms; one delivered in the same instant keeps that end."""
    arm = SimArm(HAND_ONLY)
    _send(arm, 0.05, 0.0)
    _send(arm, 0.05, 0.1)
    _send(arm, 0.02, 0.18)                      # 80 ms after the one before: its ramp ends at 0.26 s
    _send(arm, 0.0, 0.18)                       # delivered with it
    path = _path(arm, 0.26)                      # path[k]: 0.181 + k ms
    assert path[19] == pytest.approx(0.05 * (1 - 20 / 80))  # 0.2 s: 20 of 80 ms, not 20 ms to zero
    assert path[78] > 1e-4                       # 0.259 s: still ramping
    assert path[79] == pytest.approx(0.0, abs=1e-12)  # 0.26 s: there


def test_a_command_after_a_gap_ramps_over_the_gap_up_to_100_ms():
    arm = SimArm(HAND_ONLY)
    _send(arm, 0.05, 0.0)
    _send(arm, 0.05, 0.1)
    _send(arm, 0.0, 0.3)                        # 200 ms later: the ramp is capped at 100 ms
    path = _path(arm, 0.4)                       # path[k]: 0.301 + k ms
    assert path[98] > 1e-4 and path[99] == pytest.approx(0.0, abs=1e-12)  # zero at 0.4 s, not before


@pytest.mark.parametrize("gap_ms, ramp_ms", [(19, 20), (21, 21)])
def test_a_command_ramps_over_one_period_or_the_interval_since_the_last_whichever_is_longer(gap_ms, ramp_ms):
    arm = SimArm(HAND_ONLY)
    for tick in range(6):                       # at 50 Hz until 0.1 s: no ramp is under way after 0.12 s
        _send(arm, 0.05, tick * 0.02)
    _send(arm, 0.0, 0.1 + gap_ms / 1000)
    path = _path(arm, 0.2)                       # path[k]: the command's time + (k + 1) ms
    assert path[ramp_ms - 2] > 1e-3 and path[ramp_ms - 1] == pytest.approx(0.0, abs=1e-12)


def test_a_step_sent_at_100_hz_still_ramps_over_one_period():
    """The reflex lesson: zeros every 10 ms, then a step; the controller's ramp to it takes 20 ms, not more."""
    arm = SimArm(HAND_ONLY)
    for k in range(10):
        _send(arm, 0.0, k * 0.01)
    _send(arm, 0.05, 0.1)
    path = _path(arm, 0.11)                      # path[k]: 0.101 + k ms
    assert path[0] == pytest.approx(0.0025)      # 2.5 m/s^2: 0.05 m/s over 20 ms
    assert path[9] == pytest.approx(0.025)


def test_a_steady_50_hz_ramp_reaches_each_command_one_period_after_it_arrives():
    arm = SimArm(HAND_ONLY)
    for tick in range(30):
        before, target = min(0.006 * tick, 0.09), min(0.006 * (tick + 1), 0.09)
        _send(arm, target, tick * 0.02)
        path = _path(arm, (tick + 1) * 0.02)
        assert path[9] == pytest.approx((before + target) / 2, abs=1e-12)
        assert path[19] == pytest.approx(target, abs=1e-12)
