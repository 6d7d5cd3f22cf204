"""The simulated arm's interpolating controller at the command timeout's edge: a command that comes exactly one
timeout after the one before still ramps over the interval (capped at 100 ms); one that comes later ramps over one
period. Times are multiples of 1/8 s, exact in binary, so "exactly" is exact; the 1 ms cycles are judged one by one.
"""

from __future__ import annotations

from typing import List

import numpy as np
import pytest

from hri_teleop.sim.arm import STATE_TIMEOUT, SimArm, SimArmConfig

TIMEOUT_S = 0.125
X = 0


def _arm() -> SimArm:
    return SimArm(SimArmConfig(joints=False, timeout_s=TIMEOUT_S))


def _send(arm: SimArm, vx: float, at_s: float) -> None:
    arm.run_until(at_s)
    arm.command((vx, 0.0, 0.0, 0.0, 0.0, 0.0), at_s)


def _path(arm: SimArm, to_s: float) -> List[float]:
    out = []
    while arm.time_s < to_s - 1e-9:
        arm.step(round(arm.time_s + 0.001, 6))
        out.append(arm.commanded_velocity[X])
    return out


def test_a_command_exactly_one_timeout_after_the_last_ramps_over_100_ms():
    arm = _arm()
    _send(arm, 0.05, 0.25)
    _send(arm, 0.0, 0.25 + TIMEOUT_S)            # 0.375 s: the gap is the timeout, not more
    assert arm.state != STATE_TIMEOUT
    path = _path(arm, 0.5)                        # path[k]: 0.376 + k ms
    assert path[19] == pytest.approx(0.05 * (1 - 20 / 100))
    assert path[98] > 1e-4 and path[99] == pytest.approx(0.0, abs=1e-12)


def test_a_command_after_the_timeout_ramps_over_one_period_from_where_the_stop_left_it():
    arm = _arm()
    _send(arm, 0.05, 0.25)
    arm.run_until(0.5)
    assert arm.state == STATE_TIMEOUT and arm.commanded_velocity[X] == 0.0   # stopped
    _send(arm, 0.04, 0.5)                         # 0.25 s after the last: a new start, not a late tick
    path = _path(arm, 0.6)                        # path[k]: 0.501 + k ms
    assert path[9] == pytest.approx(0.02)
    assert path[18] < 0.04 and path[19] == pytest.approx(0.04, abs=1e-12)


@pytest.mark.parametrize("now", [np.float64(0.25), np.float32(0.25), 0.25, 1])
def test_a_command_time_from_numpy_is_a_time(now):
    arm = _arm()
    arm.run_until(float(now))
    assert arm.command((0.01, 0.0, 0.0, 0.0, 0.0, 0.0), now) is True
