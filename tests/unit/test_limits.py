"""TwistLimiter: the command sequence stays inside the limits for ANY input, and converges.

The checks work on the emitted sequence exactly as the robot sees it: velocity norm,
acceleration as the first difference / dt, jerk as the second difference / dt, per group
(translation xyz, rotation xyz), starting from rest (v_-1 = a_-1 = 0), with a relative
tolerance of 1e-9.
"""

from __future__ import annotations

import math
from typing import List, Sequence, Tuple

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from hri_teleop.core.limits import (
    DEFAULT_LIMITS,
    ROBOT_LIMITS,
    AxisLimits,
    CartesianLimits,
    LimitsError,
    TwistLimiter,
    Watchdog,
    limit_violations,
)

REL_TOL = 1e-9
GROUPS = (("translation", slice(0, 3)), ("rotation", slice(3, 6)))


def _norm(values: Sequence[float]) -> float:
    return math.sqrt(sum(v * v for v in values))


def assert_within_limits(limits: CartesianLimits, outputs: Sequence[Sequence[float]], dts: Sequence[float]) -> None:
    """Finite-difference velocity/acceleration/jerk norms of ``outputs`` within ``limits``."""
    v_prev = (0.0,) * 6
    a_prev = (0.0,) * 6
    for k, (v, dt) in enumerate(zip(outputs, dts)):
        assert len(v) == 6 and all(math.isfinite(c) for c in v), (k, v)
        a = tuple((x - y) / dt for x, y in zip(v, v_prev))
        j = tuple((x - y) / dt for x, y in zip(a, a_prev))
        for group, sl in GROUPS:
            lim = getattr(limits, group)
            for what, vec, bound in (("velocity", v, lim.velocity), ("acceleration", a, lim.acceleration), ("jerk", j, lim.jerk)):
                n = _norm(vec[sl])
                assert n <= bound * (1 + REL_TOL), f"step {k}: {group} {what} {n!r} > {bound!r}"
        v_prev, a_prev = v, a


def axis_limits(v_hi: float, a_hi: float, j_hi: float, v_lo: float = 0.01, a_lo: float = 0.05, j_lo: float = 1.0):
    return st.builds(
        AxisLimits,
        st.floats(min_value=v_lo, max_value=v_hi),
        st.floats(min_value=a_lo, max_value=a_hi),
        st.floats(min_value=j_lo, max_value=j_hi),
    )


any_limits = st.one_of(
    st.just(DEFAULT_LIMITS),
    st.just(ROBOT_LIMITS),
    st.builds(CartesianLimits, axis_limits(1.7, 13.0, 6500.0), axis_limits(2.5, 25.0, 12500.0)),
)
component = st.one_of(
    st.floats(min_value=-3.0, max_value=3.0),
    st.just(0.0),
    st.floats(allow_nan=True, allow_infinity=True),  # huge, NaN, +-inf
)
target = st.tuples(*([component] * 6))
dt_any = st.floats(min_value=1e-3, max_value=0.1)


# --- configuration -------------------------------------------------------------------


def test_panda_limits_are_the_documented_ones():
    assert ROBOT_LIMITS == CartesianLimits(AxisLimits(1.7, 13.0, 6500.0), AxisLimits(2.5, 25.0, 12500.0))


def test_default_limits_are_well_inside_the_panda():
    assert DEFAULT_LIMITS.within(ROBOT_LIMITS)
    for group in ("translation", "rotation"):
        mine, panda = getattr(DEFAULT_LIMITS, group), getattr(ROBOT_LIMITS, group)
        for name in ("velocity", "acceleration", "jerk"):
            assert getattr(mine, name) <= 0.25 * getattr(panda, name)
    # Above the full-stick speeds of the default gains (k_trans 0.1 m/s, k_rot 0.3 rad/s).
    assert DEFAULT_LIMITS.translation.velocity > 0.1 and DEFAULT_LIMITS.rotation.velocity > 0.3
    # At 50 Hz one tick's step, seen by a 1 kHz differentiation within 1 ms, stays inside
    # the Panda's acceleration and jerk (see the DEFAULT_LIMITS comment).
    for group in ("translation", "rotation"):
        step = getattr(DEFAULT_LIMITS, group).acceleration * 0.02
        panda = getattr(ROBOT_LIMITS, group)
        assert step / 1e-3 <= panda.acceleration and step / 1e-6 <= panda.jerk


@pytest.mark.parametrize("bad", [0, -1.0, float("nan"), float("inf"), True, "1.0", None])
def test_axis_limits_reject_non_positive_or_non_numbers(bad):
    with pytest.raises(LimitsError) as info:
        AxisLimits(bad, 1.0, 1.0)
    assert "\n" not in str(info.value)


def test_within_and_excess():
    above = CartesianLimits(AxisLimits(2.0, 1.0, 1.0), AxisLimits(1.0, 1.0, 13000.0))
    assert not above.within(ROBOT_LIMITS)
    assert above.excess(ROBOT_LIMITS) == ("translation.velocity", "rotation.jerk")
    assert ROBOT_LIMITS.within(ROBOT_LIMITS)


def test_limits_above_the_robot_are_refused():
    above = CartesianLimits(AxisLimits(2.0, 1.0, 1.0), DEFAULT_LIMITS.rotation)
    with pytest.raises(LimitsError, match=r"translation\.velocity=2 > 1\.7") as info:
        TwistLimiter(above)
    assert "\n" not in str(info.value)
    TwistLimiter(ROBOT_LIMITS)  # exactly the robot's is allowed
    with pytest.raises(LimitsError):
        TwistLimiter(ROBOT_LIMITS, hard_limits=DEFAULT_LIMITS)


@pytest.mark.parametrize("dt", [0.0, -0.02, float("nan"), float("inf"), True, "0.02"])
def test_step_rejects_bad_time_steps(dt):
    with pytest.raises(LimitsError):
        TwistLimiter().step((0.0,) * 6, dt)


@pytest.mark.parametrize("bad", [(0.0,) * 5, (0.0,) * 7, "abcdef", None])
def test_step_rejects_bad_targets(bad):
    with pytest.raises(LimitsError):
        TwistLimiter().step(bad, 0.02)


# --- behaviour -------------------------------------------------------------------------


def run(limiter: TwistLimiter, targets, dts) -> List[Tuple[float, ...]]:
    return [limiter.step(t, dt) for t, dt in zip(targets, dts)]


def test_from_rest_to_full_stick_and_back_to_exact_zero():
    limiter = TwistLimiter()
    dt = 0.02
    outputs = run(limiter, [(0.1, 0, 0, 0, 0, 0)] * 40 + [(0.0,) * 6] * 40, [dt] * 80)
    assert_within_limits(DEFAULT_LIMITS, outputs, [dt] * 80)
    # The first step from rest is a jerk-limited one: a_0 = j dt at most, v_0 = j dt^2.
    assert outputs[0][0] == pytest.approx(DEFAULT_LIMITS.translation.jerk * dt * dt, rel=1e-6)
    # Near time-optimal: dv/a_max + a_max/j_max = 0.1/0.3 + 0.3/2 = 0.48 s = 24.2 ticks.
    reached = next(k for k, v in enumerate(outputs) if v[0] == 0.1)
    assert reached <= 26
    assert outputs[39] == (0.1, 0.0, 0.0, 0.0, 0.0, 0.0)
    # No overshoot (beyond float rounding) on the way up, monotone on the way down, and
    # an exact zero at rest.
    assert max(v[0] for v in outputs) <= 0.1 + 1e-15
    down = [v[0] for v in outputs[40:]]
    assert all(b <= a + 1e-15 for a, b in zip(down, down[1:]))
    assert min(down) >= -1e-15
    assert outputs[-1] == (0.0,) * 6
    assert limiter.velocity == (0.0,) * 6 and limiter.acceleration == (0.0,) * 6


def test_going_to_zero_is_ramped_not_stepped():
    limiter = TwistLimiter()
    for _ in range(100):
        limiter.step((0.2, 0, 0, 0, 0, 0.4), 0.02)
    first_stop = limiter.step((0.0,) * 6, 0.02)
    # One jerk-limited step away from cruising: the velocity barely changes.
    assert first_stop[0] == pytest.approx(0.2 - DEFAULT_LIMITS.translation.jerk * 0.02 ** 2, rel=1e-6)
    assert first_stop[5] == pytest.approx(0.4 - DEFAULT_LIMITS.rotation.jerk * 0.02 ** 2, rel=1e-6)


def test_non_finite_targets_count_as_zero():
    limiter = TwistLimiter()
    for _ in range(100):
        limiter.step((0.1, 0.0, 0.0, 0.2, 0.0, 0.0), 0.02)
    nan, inf = float("nan"), float("inf")
    outputs = [limiter.step((nan, inf, -inf, nan, nan, nan), 0.02) for _ in range(100)]
    assert outputs[-1] == (0.0,) * 6


def test_huge_targets_are_clipped_to_the_velocity_limit_along_their_direction():
    limiter = TwistLimiter()
    outputs = [limiter.step((1e308, 1e308, 0.0, 0.0, 0.0, -1e300), 0.02) for _ in range(300)]
    assert_within_limits(DEFAULT_LIMITS, outputs, [0.02] * 300)
    vx, vy, vz, wx, wy, wz = outputs[-1]
    assert vx == pytest.approx(vy) and vz == 0.0
    assert _norm((vx, vy, vz)) == pytest.approx(DEFAULT_LIMITS.translation.velocity, rel=1e-6)
    assert wz == pytest.approx(-DEFAULT_LIMITS.rotation.velocity, rel=1e-6)


def test_reset_and_properties():
    limiter = TwistLimiter()
    assert limiter.limits is DEFAULT_LIMITS
    out = limiter.step((0.1, 0, 0, 0, 0, 0), 0.02)
    assert limiter.velocity == out
    assert limiter.acceleration[0] == pytest.approx(out[0] / 0.02)
    limiter.reset()
    assert limiter.velocity == (0.0,) * 6 and limiter.acceleration == (0.0,) * 6


# --- properties --------------------------------------------------------------------------


# Examples at the thresholds, run on every run whatever the random draws: full-stick reversals that
# saturate every limit, at the smallest and the largest time step, and targets that are not numbers.
SATURATING = [((3.0, -3.0, 3.0, 3.0, -3.0, 3.0), 0.02)] * 30 + [((-3.0, 3.0, -3.0, -3.0, 3.0, -3.0), 0.02)] * 30
UNIT_LIMITS = CartesianLimits(AxisLimits(1.0, 50.0, 2500.0), AxisLimits(1.0, 50.0, 2500.0))  # above the Panda's
EDGE_LIMITS = CartesianLimits(AxisLimits(1.0, 12.5, 6250.0), AxisLimits(2.5, 25.0, 12500.0))  # rotation: the Panda's


@settings(max_examples=150, deadline=None)
@given(
    limits=any_limits,
    steps=st.lists(st.tuples(target, dt_any), min_size=1, max_size=60),
)
@example(limits=DEFAULT_LIMITS, steps=SATURATING)
@example(limits=ROBOT_LIMITS, steps=SATURATING)
@example(limits=ROBOT_LIMITS, steps=[((1.7, 0.0, 0.0, 2.5, 0.0, 0.0), 0.1)] * 5 + [((-1.7, 0.0, 0.0, -2.5, 0.0, 0.0), 0.1)] * 5)
@example(limits=DEFAULT_LIMITS, steps=[((3.0,) * 6, 1e-3)] * 60)
@example(limits=EDGE_LIMITS, steps=[((1.0, 0.0, 0.0, 2.5, 0.0, 0.0), 0.02)] * 20 + [((0.0,) * 6, 0.02)] * 20)
@example(limits=DEFAULT_LIMITS, steps=[((math.nan, math.inf, -math.inf, 1e308, -1e308, 0.0), 0.02)] * 10
         + [((3.0,) * 6, 0.02)] * 10 + [((math.nan,) * 6, 0.02)] * 10)
def test_any_target_sequence_stays_within_the_limits(limits, steps):
    limiter = TwistLimiter(limits)
    targets = [t for t, _ in steps]
    dts = [dt for _, dt in steps]
    outputs = run(limiter, targets, dts)
    assert_within_limits(limits, outputs, dts)


@settings(max_examples=100, deadline=None)
@given(
    limits=any_limits,
    level=st.floats(min_value=0.5, max_value=5.0),
    period=st.integers(min_value=1, max_value=15),
    dt=dt_any,
)
@example(limits=DEFAULT_LIMITS, level=5.0, period=1, dt=0.02)
@example(limits=DEFAULT_LIMITS, level=0.25, period=15, dt=0.1)  # at the translation velocity limit
@example(limits=ROBOT_LIMITS, level=5.0, period=1, dt=1e-3)
@example(limits=ROBOT_LIMITS, level=1.7, period=7, dt=0.1)
@example(limits=EDGE_LIMITS, level=2.5, period=2, dt=0.02)  # the rotation at the Panda's velocity limit
def test_bang_bang_targets_stay_within_the_limits(limits, level, period, dt):
    # The hardest input for a velocity limit: full reversals, held for random times.
    limiter = TwistLimiter(limits)
    targets = [((level if (k // period) % 2 else -level),) * 6 for k in range(200)]
    outputs = run(limiter, targets, [dt] * 200)
    assert_within_limits(limits, outputs, [dt] * 200)


reachable_limits = st.one_of(
    st.just(DEFAULT_LIMITS),
    st.just(ROBOT_LIMITS),
    # Ranges keep the settling time a few thousand steps so the test stays fast.
    st.builds(
        CartesianLimits,
        axis_limits(1.7, 13.0, 6500.0, v_lo=0.05, a_lo=0.3, j_lo=2.0),
        axis_limits(2.5, 25.0, 12500.0, v_lo=0.05, a_lo=0.3, j_lo=2.0),
    ),
)


def settle_bound_s(limits: CartesianLimits, dt: float) -> float:
    """A generous settling-time bound: twice (full reversal + building/removing acceleration)."""
    worst = 0.0
    for group in (limits.translation, limits.rotation):
        worst = max(worst, 2.0 * (2.0 * group.velocity / group.acceleration + 3.0 * group.acceleration / group.jerk))
    return worst + 10 * dt


@settings(max_examples=60, deadline=None)
@given(
    limits=reachable_limits,
    prefix=st.lists(target, max_size=20),
    goal=st.tuples(*([st.floats(min_value=-3.0, max_value=3.0)] * 6)),
    dt=st.floats(min_value=0.005, max_value=0.05),
)
@example(limits=DEFAULT_LIMITS, prefix=[], goal=(0.25, 0.0, 0.0, 0.5, 0.0, 0.0), dt=0.02)  # at the velocity limits
@example(limits=DEFAULT_LIMITS, prefix=[], goal=(0.3, 0.0, 0.0, -0.6, 0.0, 0.0), dt=0.02)  # beyond: scaled down
@example(limits=DEFAULT_LIMITS, prefix=[(-3.0,) * 6] * 20, goal=(0.0,) * 6, dt=0.005)  # to rest from a reversal
@example(limits=ROBOT_LIMITS, prefix=[(3.0,) * 6] * 5, goal=(-3.0, 0.0, 0.0, 0.0, 0.0, 3.0), dt=0.05)
def test_a_constant_target_is_reached_in_bounded_time_and_held(limits, prefix, goal, dt):
    limiter = TwistLimiter(limits)
    outputs = run(limiter, prefix, [dt] * len(prefix))
    # Where the limiter must end: the goal, scaled down to the velocity limit per group.
    expected = []
    for group, sl in GROUPS:
        v_max = getattr(limits, group).velocity
        n = _norm(goal[sl])
        scale = 1.0 if n <= v_max else v_max / n
        expected.extend(c * scale for c in goal[sl])
    bound_steps = int(math.ceil(settle_bound_s(limits, dt) / dt))
    reached_at = None
    for k in range(bound_steps):
        out = limiter.step(goal, dt)
        outputs.append(out)
        if max(abs(a - b) for a, b in zip(out, expected)) <= 1e-6:
            reached_at = k
            break
    assert reached_at is not None, f"not within 1e-6 of {expected} after {bound_steps} steps: {limiter.velocity}"
    # Held there: no limit cycle, and exactly constant for goals inside the velocity limit.
    tail = [limiter.step(goal, dt) for _ in range(30)]
    outputs.extend(tail)
    for out in tail:
        assert max(abs(a - b) for a, b in zip(out, expected)) <= 1e-6
    inside = all(_norm(goal[sl]) < 0.999 * getattr(limits, g).velocity for g, sl in GROUPS)
    if inside:
        assert tail[-1] == tail[-2] == tuple(goal)
    assert_within_limits(limits, outputs, [dt] * len(outputs))


@settings(max_examples=100, deadline=None)
@given(
    limits=any_limits,
    raw=st.lists(st.tuples(*([st.floats(min_value=-3.0, max_value=3.0)] * 6)), min_size=1, max_size=8),
    scale=st.sampled_from([1.0, 1e-2, 1e-4, 1e-6]),
    dt=dt_any,
)
# Exactly at each bound from rest (1.0 m/s, 1.0 / 0.02 = 50.0 m/s^2, 50.0 / 0.02 = 2500.0 m/s^3): within; a
# millionth above: not. The same for the rotation, and a stop at the bound (jerk -2500.0).
@example(limits=UNIT_LIMITS, raw=[(1.0, 0.0, 0.0, 0.0, 0.0, 0.0)], scale=1.0, dt=0.02)
@example(limits=UNIT_LIMITS, raw=[(1.000001, 0.0, 0.0, 0.0, 0.0, 0.0)], scale=1.0, dt=0.02)
@example(limits=UNIT_LIMITS, raw=[(0.0, 0.0, 0.0, 0.0, 0.0, 1.0)], scale=1.0, dt=0.02)
@example(limits=UNIT_LIMITS, raw=[(0.0, 0.0, 0.0, 0.0, 0.0, -1.000001)], scale=1.0, dt=0.02)
@example(limits=UNIT_LIMITS, raw=[(1.0, 0.0, 0.0, 0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0, 0.0, 0.0)], scale=1.0, dt=0.02)
@example(limits=UNIT_LIMITS, raw=[(0.6, 0.8, 0.0, 0.0, 0.0, 0.0)], scale=1.0, dt=0.02)
@example(limits=DEFAULT_LIMITS, raw=[(3.0,) * 6], scale=1e-6, dt=0.1)
def test_limit_violations_agrees_with_the_independent_check(limits, raw, scale, dt):
    # Arbitrary sequences, some inside, most outside: the library checker and this file's agree.
    twists = [tuple(c * scale for c in t) for t in raw]
    dts = [dt] * len(twists)
    try:
        assert_within_limits(limits, twists, dts)
        ok = True
    except AssertionError:
        ok = False
    assert (limit_violations(limits, twists, dts) == []) == ok


def test_limit_violations_messages():
    problems = limit_violations(DEFAULT_LIMITS, [(1.0, 0, 0, 0, 0, 0)], [0.02])
    assert problems[0].startswith("step 0: translation velocity 1 > 0.25")
    assert len(problems) == 3  # velocity, acceleration and jerk
    assert limit_violations(DEFAULT_LIMITS, [], []) == []
    with pytest.raises(LimitsError):
        limit_violations(DEFAULT_LIMITS, [(0.0,) * 6], [])


# --- watchdog ---------------------------------------------------------------------------


def test_watchdog():
    dog = Watchdog(0.5)
    assert dog.is_stale(0.0) and dog.age_s(0.0) == math.inf  # never fed: stale
    dog.feed(10.0)
    assert not dog.is_stale(10.5) and dog.age_s(10.25) == pytest.approx(0.25)
    assert dog.is_stale(10.51)
    dog.feed(11.0)
    assert not dog.is_stale(11.2)
    dog.reset()
    assert dog.is_stale(11.2)


@pytest.mark.parametrize("bad", [0, -1.0, float("nan"), float("inf"), True])
def test_watchdog_rejects_bad_timeouts(bad):
    with pytest.raises(LimitsError):
        Watchdog(bad)


def test_reset_can_continue_from_a_known_motion():
    lim = TwistLimiter(DEFAULT_LIMITS)
    lim.reset(velocity=(0.1, 0, 0, 0, 0, 0.2), acceleration=(0.0,) * 6)
    assert lim.velocity == (0.1, 0.0, 0.0, 0.0, 0.0, 0.2)
    out = lim.step((0.1, 0, 0, 0, 0, 0.2), 0.02)
    assert out == (0.1, 0.0, 0.0, 0.0, 0.0, 0.2)  # already there: holds, no jump
    lim.reset()
    assert lim.velocity == (0.0,) * 6
