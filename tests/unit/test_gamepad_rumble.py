"""Rumble requests: few, but never a pad left buzzing."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from hri_teleop.core.gamepad import GamepadError, RumblePolicy, RumbleRequests
from hri_teleop.core.gamepad.rumble import unit_intensity


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


# The default policy asks for a new request when a motor's intensity changed by 0.02 or more. The
# levels start at 0.02 (on) so that the differences are exact in floating point: 0.04 - 0.02 == 0.02.
@pytest.mark.parametrize("level, sent", [(0.039, False), (0.04, True), (0.041, True),
                                         (0.001, False), (0.0, True)])  # 0.0: switched off, at once
def test_a_change_of_0_02_or_more_is_sent_at_once_a_smaller_one_waits(level, sent):
    r = RumbleRequests()
    assert r.update(0.02, 0.0) == (0.02, 0.5)
    assert (r.update(level, 0.02) is not None) is sent


@pytest.mark.parametrize("level, sent", [(0.021, False), (0.02, True), (0.019, True)])
def test_a_drop_of_0_02_or_more_is_sent_at_once(level, sent):
    r = RumbleRequests()
    r.update(0.04, 0.0)
    assert (r.update(level, 0.02) is not None) is sent


def test_a_faint_rumble_switching_on_or_off_is_sent_though_it_changed_less_than_0_02():
    r = RumbleRequests()
    assert r.update(0.01, 0.0) == (0.01, 0.5)
    assert r.update(0.0, 0.02) == (0.0, 0.0)  # the stop: never a pad left buzzing
    assert r.update(0.0, 0.04) is None
    assert r.update_motors(0.0, 0.01, 0.06) == (0.0, 0.01, 0.5)
    assert r.update_motors(0.0, 0.0, 0.08) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("after_s, sent", [(0.249, False), (0.25, True), (0.251, True)])
def test_a_steady_rumble_is_refreshed_every_0_25_s(after_s, sent):
    r = RumbleRequests()
    r.update(0.5, 0.0)
    assert (r.update(0.5, after_s) == (0.5, 0.5)) is sent


def test_a_one_level_request_is_the_same_on_both_motors():
    r = RumbleRequests()
    assert r.update(0.5, 0.0) == (0.5, 0.5)
    assert r.update_motors(0.5, 0.5, 0.02) is None  # both motors already got 0.5
    assert r.update_motors(0.5, 0.0, 0.04) == (0.5, 0.0, 0.5)


@pytest.mark.parametrize("value, intensity", [(0.5, 0.5), (1.5, 1.0), (-0.5, 0.0), (1.0, 1.0), (0.0, 0.0),
                                              (float("nan"), 0.0), (float("inf"), 0.0), (float("-inf"), 0.0),
                                              ("0.5", 0.0), (None, 0.0), (True, 0.0),
                                              (np.float32(0.5), 0.5), (np.int64(1), 1.0)])
def test_a_rumble_strength_is_clipped_to_0_1_and_anything_but_a_finite_number_is_0(value, intensity):
    assert unit_intensity(value) == intensity


@pytest.mark.parametrize("kwargs", [dict(change=0.001), dict(change=1.0), dict(refresh_s=0.001),
                                    dict(refresh_s=0.499, hold_s=0.5), dict(refresh_s=0.25, hold_s=0.5)])
def test_a_policy_at_the_edge_of_its_ranges_is_accepted(kwargs):
    assert RumblePolicy(**kwargs)


@pytest.mark.parametrize("kwargs", [dict(change=0.0), dict(change=1.001), dict(refresh_s=0.0),
                                    dict(refresh_s=0.5, hold_s=0.5), dict(hold_s=float("inf")),
                                    dict(change=float("nan"))])
def test_a_policy_just_outside_its_ranges_is_refused(kwargs):
    with pytest.raises(GamepadError, match="0 < change <= 1 and 0 < refresh_s < hold_s"):
        RumblePolicy(**kwargs)


def test_a_pad_that_refuses_the_start_check_is_named_with_the_cause_and_the_fixes():
    from hri_teleop.core.gamepad.rumble import rumble_refused

    assert rumble_refused("Wireless Controller", "no force feedback device") == (
        "gamepad 'Wireless Controller' refuses rumble (no force feedback device): no force feedback with it; connect "
        "the pad with a USB cable (some Bluetooth links carry no rumble), check that its kernel driver supports force "
        "feedback and that /dev/input/event* is writable (`ls -l /dev/input/`), or use another pad")
