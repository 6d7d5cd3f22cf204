"""hri_teleop.ros.clock: a node's time on the wall clock, or on /clock when the grader owns it."""

from __future__ import annotations

import threading
import time

import pytest

rospy = pytest.importorskip("rospy")

from hri_teleop.ros import clock as C  # noqa: E402 - only where rospy is


class FakeRosTime:
    """rospy.get_time() as the grader's /clock would move it: only when told to."""

    def __init__(self, now: float = 1.0) -> None:
        self.now = now

    def __call__(self) -> float:
        return self.now


class FakeWall:
    """The wall clock as hri_teleop.ros.clock sees it (its module ``time``): moves only when slept on."""

    def __init__(self) -> None:
        self.now = 100.0
        self.sleeps = []

    def monotonic(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds


@pytest.fixture
def wall(monkeypatch):
    fake = FakeWall()
    monkeypatch.setattr(C, "time", fake)
    return fake


@pytest.fixture
def ros_time(monkeypatch):
    fake = FakeRosTime()
    monkeypatch.setattr(C.rospy, "get_time", fake)
    monkeypatch.setattr(C.rospy, "is_shutdown", lambda: False)
    return fake


def test_on_the_wall_clock_now_is_monotonic_and_started_at_once():
    clock = C.NodeClock(sim_time=False)
    before = time.monotonic()
    assert before <= clock.wait_started() <= clock.now() <= time.monotonic()


def test_a_target_within_a_microsecond_counts_as_reached(ros_time):
    clock = C.NodeClock(sim_time=True)
    ros_time.now = 1.04  # the clock in whole ns; a schedule summed in floats lands a few ulp above
    assert clock.reached(1.0 + 0.02 + 0.02)
    assert clock.reached(1.04 + C.TOLERANCE_S)
    assert not clock.reached(1.04 + 2 * C.TOLERANCE_S)


def test_waiting_for_the_first_clock_reading(ros_time):
    clock = C.NodeClock(sim_time=True)
    ros_time.now = 0.0
    threading.Timer(0.05, lambda: setattr(ros_time, "now", 3.5)).start()
    assert clock.wait_started(timeout_s=2.0) == 3.5
    ros_time.now = 0.0
    with pytest.raises(C.ClockError, match="nothing published /clock for 0 s; start what owns the clock first"):
        clock.wait_started(timeout_s=0.01)


def test_sleep_until_follows_the_clock_not_the_wall(monkeypatch, wall):
    readings = iter([1.0] * 50 + [1.02])  # the grader's /clock moves on after 50 looks
    looks = []
    monkeypatch.setattr(C.rospy, "get_time", lambda: looks.append(1) or next(readings))
    monkeypatch.setattr(C.rospy, "is_shutdown", lambda: False)
    clock = C.NodeClock(sim_time=True)
    assert clock.sleep_until(1.02) is False
    assert len(looks) == 51 and next(readings, None) is None  # it returned on the reading that reached the target
    assert wall.sleeps == [C.POLL_S] * 49  # between looks it slept on the wall, a poll at a time


def test_sleep_until_ends_early_when_woken_and_says_so(ros_time):
    clock = C.NodeClock(sim_time=True)
    wake = threading.Event()
    threading.Timer(0.05, wake.set).start()
    assert clock.sleep_until(5.0, wake) is True
    assert ros_time.now == 1.0


def test_a_clock_that_stopped_moving_ends_the_wait_after_stall_s(ros_time, wall):
    clock = C.NodeClock(sim_time=True)
    started = wall.now
    assert clock.sleep_until(5.0, stall_s=0.1) is False
    assert ros_time.now == 1.0
    stalled_s = wall.now - started  # the fake wall's: what the clock waited through, not how long this took
    assert 0.1 < stalled_s <= 0.1 + 2 * C.POLL_S


def test_on_the_wall_clock_sleep_until_waits_the_remaining_time(wall):
    clock = C.NodeClock(sim_time=False)
    assert clock.now() == wall.now
    assert clock.sleep_until(clock.now() + 0.05) is False
    assert wall.sleeps == [pytest.approx(0.05)]
    assert clock.sleep_until(clock.now() - 1.0) is False
    assert len(wall.sleeps) == 1  # a time already past: no sleep at all
