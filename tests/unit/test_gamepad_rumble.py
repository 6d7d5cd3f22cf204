"""Rumble requests: few, but never a pad left buzzing."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
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


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(min_value=0.0, max_value=1.0), min_size=1, max_size=200))
def test_at_50_hz_a_steady_on_pad_is_refreshed_before_its_request_runs_out(intensities):
    r = RumbleRequests()
    last_on_request_end = None
    for k, value in enumerate(intensities):
        now = k * 0.02
        request = r.update(value, now)
        if request is not None:
            last_on_request_end = now + request[1] if request[0] > 0 else None
        if value > 0.0:
            assert last_on_request_end is not None and last_on_request_end > now
    assert r.update(0.0, len(intensities) * 0.02) in (None, (0.0, 0.0))


def test_a_bad_policy_is_refused():
    with pytest.raises(GamepadError):
        RumblePolicy(refresh_s=1.0, hold_s=0.5)
