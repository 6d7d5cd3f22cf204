"""Rumble requests: few, but never a pad left buzzing."""

from __future__ import annotations

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from hri_teleop.core.gamepad import GamepadError, RumblePolicy, RumbleRequests


def test_switching_on_and_off_is_sent_at_once():
    r = RumbleRequests()
    assert r.update(0.0, 0.0) is None  # nothing to say yet
    assert r.update(0.6, 0.02) == (0.6, 0.5)
    assert r.update(0.0, 0.04) == (0.0, 0.0)


def test_small_changes_wait_for_the_refresh_big_ones_do_not():
    r = RumbleRequests()
    r.update(0.5, 0.0)
    assert r.update(0.51, 0.02) is None
    assert r.update(0.53, 0.04) == (0.53, 0.5)
    assert r.update(0.535, 0.2) is None
    assert r.update(0.535, 0.3) == (0.535, 0.5)  # refreshed while on


class Pad:
    """What the pad does with the requests: the last one's intensity, until its duration runs out."""

    def __init__(self) -> None:
        self.intensity, self.until_s = 0.0, -1.0

    def receive(self, request, now_s: float) -> None:
        if request is not None:
            self.intensity, self.until_s = request[0], now_s + request[1]

    def level(self, now_s: float) -> float:
        return self.intensity if now_s < self.until_s else 0.0


CHANGE = RumblePolicy().change


# The edges, tried in every run (random lists reach them only now and then): on and off below the
# change step, a switch-off after refreshes, a long steady rumble across many refresh periods.
@example([0.0, CHANGE / 2, 0.0])
@example([CHANGE / 2, 0.0, CHANGE / 2])
@example([1.0, 0.0, 1.0, 0.0])
@example([CHANGE / 2] * 40 + [0.0])
@example([0.5] * 100)
@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(min_value=0.0, max_value=1.0), min_size=1, max_size=200))
def test_at_50_hz_the_pad_feels_every_intensity_within_the_change_step_and_is_never_left_buzzing(intensities):
    r = RumbleRequests()
    felt = Pad()
    for k, value in enumerate(intensities):
        now = k * 0.02
        felt.receive(r.update(value, now), now)
        # on while on (refreshed before its request runs out), off at once when off, near the intensity
        assert (felt.level(now) > 0.0) == (value > 0.0), (k, value, felt.level(now))
        assert abs(felt.level(now) - value) < CHANGE, (k, value, felt.level(now))
    end = len(intensities) * 0.02
    felt.receive(r.update(0.0, end), end)
    assert felt.level(end) == 0.0


def test_a_bad_policy_is_refused():
    with pytest.raises(GamepadError):
        RumblePolicy(refresh_s=1.0, hold_s=0.5)
