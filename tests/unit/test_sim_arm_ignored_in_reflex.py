"""A reflex ignores commands until recover(): the first ignored command is reported once, at its own time, and
every one is counted. The same reflex each time: a step of 0.1 m/s from rest, far above the acceleration limit."""

from __future__ import annotations

import pytest

from hri_teleop.sim.arm import EVENT_IGNORED, EVENT_REFLEX, STATE_REFLEX, SimArm, SimArmConfig

HAND = {"joints": False, "controller": "hold", "stop_limits": None}


def _in_a_reflex() -> SimArm:
    arm = SimArm(SimArmConfig(**HAND))
    arm.command((0.1, 0, 0, 0, 0, 0), 0.0)
    arm.run_until(0.005)
    assert arm.state == STATE_REFLEX
    return arm


@pytest.mark.parametrize("ignored", [1, 2, 3])
def test_the_first_command_ignored_in_a_reflex_is_reported_once_at_its_time(ignored):
    arm = _in_a_reflex()
    for k in range(ignored):
        assert arm.command((0.0, 0.001, 0, 0, 0, 0), 0.006 + k * 0.001) is False
    assert arm.ignored_command_count == ignored
    assert [(e.kind, e.time_s) for e in arm.events if e.kind == EVENT_IGNORED] == [(EVENT_IGNORED, 0.006)]


def test_after_recover_a_new_reflex_reports_its_first_ignored_command_again():
    arm = _in_a_reflex()
    arm.command((0.0, 0.0, 0, 0, 0, 0), 0.006)
    assert arm.recover(0.01) is True
    arm.command((0.1, 0, 0, 0, 0, 0), 0.02)
    arm.run_until(0.03)
    assert arm.state == STATE_REFLEX
    arm.command((0.0, 0.0, 0, 0, 0, 0), 0.031)
    assert [e.kind for e in arm.events].count(EVENT_REFLEX) == 2
    assert [e.time_s for e in arm.events if e.kind == EVENT_IGNORED] == [0.006, 0.031]
