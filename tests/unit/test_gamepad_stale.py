"""The stale-input watchdog: a held stick reading bit for bit the same too long means a frozen link."""

from __future__ import annotations

import pytest

from hri_teleop.core.gamepad import GamepadError, PadState
from hri_teleop.core.gamepad.stale import StaleInputWatch
from hri_teleop.sim.virtual_pad import ScriptedPad, parse_script

TIMEOUT_S = 1.0
DEADZONE = 0.1


def held(value: float = 0.5, axis: str = "left_y") -> PadState:
    return PadState({axis: value}, {}, True)


def run(watch: StaleInputWatch, states, dt_s: float = 0.02, start_s: float = 0.0):
    """Feed one state per tick; the watch's answer after each."""
    return [watch.update(state, start_s + i * dt_s) for i, state in enumerate(states)]


def test_a_held_stick_identical_for_just_over_the_timeout_is_stale_and_not_at_the_timeout():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    assert not watch.update(held(), 0.0)
    assert not watch.update(held(), TIMEOUT_S)  # exactly the timeout: not yet
    assert watch.update(held(), TIMEOUT_S + 0.001) and watch.stale


def test_one_changed_bit_in_any_axis_restarts_the_count():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    watch.update(held(0.5), 0.0)
    watch.update(held(0.5), 0.9)
    nudged = PadState({"left_y": 0.5, "r2": 1e-9}, {}, True)  # a trigger at rest moved a hair: the link lives
    assert not watch.update(nudged, 1.0)
    assert not watch.update(nudged, 1.9) and watch.update(nudged, 2.01)


def test_readings_that_change_again_end_the_stale_state():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    assert run(watch, [held(0.5)] * 60)[-1]  # 1.18 s identical
    assert not watch.update(held(0.51), 1.2) and not watch.stale


def test_a_resting_pad_may_read_the_same_forever():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    inside = held(DEADZONE)  # exactly at the dead zone's edge: at rest
    assert not any(run(watch, [inside] * 500))
    beyond = held(DEADZONE + 0.001)
    assert run(StaleInputWatch(TIMEOUT_S, DEADZONE), [beyond] * 60)[-1]


def test_the_stick_back_at_rest_ends_the_stale_state():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    run(watch, [held()] * 60)
    assert watch.stale and not watch.update(PadState.neutral(), 1.3)


def test_only_the_watched_axes_count_as_held():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE, watched=("left_x", "left_y"))
    assert not any(run(watch, [held(0.8, "right_x")] * 100))


def test_a_lost_pad_or_timeout_zero_never_reports_stale():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    run(watch, [held()] * 60)
    assert not watch.update(None, 1.3) and not watch.update(PadState.neutral(connected=False), 1.4)
    assert not any(run(StaleInputWatch(0.0, DEADZONE), [held()] * 500))


@pytest.mark.parametrize("kwargs", [dict(timeout_s=-1.0), dict(timeout_s=float("nan")), dict(deadzone=1.0),
                                    dict(watched=("left_z",))])
def test_bad_settings_are_one_line(kwargs):
    with pytest.raises(GamepadError) as info:
        StaleInputWatch(**kwargs)
    assert "\n" not in str(info.value)


def test_a_scripted_hand_trembles_until_the_freeze_and_not_after():
    clock = [0.0]
    pad = ScriptedPad(parse_script([{"t": 0.0, "axis": "left_y", "value": 1.0}, {"t": 2.0, "freeze": True},
                                    {"t": 4.0, "axis": "left_y", "value": 0.5}]), clock=lambda: clock[0])
    assert pad.stale_input_watch
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    states = []
    for tick in range(300):  # 6 s at 50 Hz
        clock[0] = tick * 0.02
        states.append(pad.poll())
        watch.update(states[-1], clock[0])
        if tick == 99:  # 1.98 s: held for 2 s, trembling
            assert not watch.stale
        if tick == 199:  # 3.98 s: frozen for 1.98 s
            assert watch.stale
    assert not watch.stale  # the next step changed the reading
    assert abs(states[50].axis("left_y") - 1.0) < 1e-15 and states[50].axis("left_y") != states[51].axis("left_y")
    assert states[150].axis("left_y") == states[151].axis("left_y")


def test_pads_driven_by_code_are_not_watched():
    assert not ScriptedPad(parse_script([{"t": 0.0, "axis": "left_y", "value": 1.0}])).stale_input_watch


class FakeTime:
    """pad_check's ``time`` module: a clock that moves only by what it sleeps (no wall time in the test)."""

    def __init__(self) -> None:
        self.now = 1000.0

    def monotonic(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.now += seconds


def test_pad_check_measures_the_longest_identical_run_of_a_held_stick(monkeypatch, capsys):
    from test_gamepad_pygame import FakeJoystick  # tests/unit, on sys.path under pytest

    from hri_teleop.apps import pad_check
    from hri_teleop.hardware.real.pygame_pad import PygamePad

    class Trembling(FakeJoystick):
        calls = 0

        def get_axis(self, i: int) -> float:  # the held axis moves by a hair every other read
            if i != 1:
                return self.axes[i]
            self.calls += 1
            return self.axes[i] + (1e-4 if self.calls % 2 else 0.0)

    for device, frozen in ((FakeJoystick(), True), (Trembling(), False)):
        device.axes[1] = -0.8  # left stick held up
        monkeypatch.setattr(pad_check, "time", FakeTime())  # 0.3 s at 200 Hz: 60 reads, 5 ms apart
        monkeypatch.setattr(pad_check, "PygamePad", lambda layout, index, device=device, **kw:
                            PygamePad(layout, joystick=device, **kw))
        assert pad_check.main(["--layout", "dualshock4", "--stale", "--seconds", "0.3", "--rate", "200"]) == 0
        longest_s = float(capsys.readouterr().out.splitlines()[-1].split(": ")[1].split()[0])
        # frozen: identical from the first read to the last (59 periods); trembling: never two reads alike
        assert longest_s == (pytest.approx(0.295, abs=0.006) if frozen else 0.0), longest_s


@pytest.mark.parametrize("value", [-0.5, -1.0])
def test_a_stick_frozen_in_a_negative_direction_is_stale_too(value):
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    assert not watch.update(held(value), 0.0)
    assert not watch.update(held(value), 1.0)
    assert watch.update(held(value), 1.001)


@pytest.mark.parametrize("value, counts_as_held", [(-0.099, False), (-0.1, False), (-0.101, True),
                                                   (0.099, False), (0.1, False), (0.101, True)])
def test_a_stick_counts_as_held_only_beyond_the_dead_zone_either_way(value, counts_as_held):
    watch = StaleInputWatch(1.0, 0.1)
    watch.update(held(value), 0.0)
    assert watch.update(held(value), 1.5) is counts_as_held
    assert watch.frozen_s(1.5) == (1.5 if counts_as_held else 0.0)


@pytest.mark.parametrize("frozen_for_s, stale", [(0.999, False), (1.0, False), (1.001, True)])
def test_the_default_watch_calls_a_held_stick_stale_after_1_s(frozen_for_s, stale):
    watch = StaleInputWatch()  # the defaults: 1 s, no dead zone
    watch.update(held(0.05), 0.0)  # a small deflection counts as held without a dead zone
    assert watch.update(held(0.05), frozen_for_s) is stale and watch.stale is stale


def test_a_fresh_watch_is_not_stale_and_has_seen_nothing_frozen():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    assert watch.stale is False and watch.frozen_s(5.0) == 0.0


def test_a_resting_reading_counts_no_frozen_time_however_long_ago():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    watch.update(PadState.neutral(), 0.0)
    watch.update(PadState.neutral(), 3.0)
    assert watch.frozen_s(10.0) == 0.0 and watch.stale is False


def test_a_lost_pad_forgets_the_stale_state():
    watch = StaleInputWatch(TIMEOUT_S, DEADZONE)
    run(watch, [held()] * 60)
    assert watch.stale
    watch.update(None, 1.3)
    assert watch.stale is False and watch.frozen_s(2.0) == 0.0
    assert not watch.update(held(), 1.4)  # held again: the count starts anew
    assert not watch.update(held(), 2.4) and watch.update(held(), 2.401)


@pytest.mark.parametrize("kwargs", [dict(deadzone=0.0), dict(deadzone=0.999), dict(timeout_s=0.0)])
def test_settings_at_the_edge_of_their_range_are_accepted(kwargs):
    StaleInputWatch(**kwargs)


@pytest.mark.parametrize("kwargs", [dict(deadzone=-0.001), dict(deadzone=1.0), dict(timeout_s=-0.001)])
def test_settings_just_outside_their_range_are_refused(kwargs):
    with pytest.raises(GamepadError):
        StaleInputWatch(**kwargs)
