"""widgets.BrowserPad's kernel side without a browser: readings in, the state for the node and the rumble out."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from hri_teleop.core.gamepad import PadState, RumblePolicy
from hri_teleop.course import widgets
from hri_teleop.course.widgets._base import WidgetError
from hri_teleop.course.widgets.browser_pad import RUMBLE_SILENCE_S, BrowserPad, pad_line


class _NoRos:
    problem = "rospy is not installed: run `make setup` (test)"

    def __bool__(self) -> bool:
        return False


class _Clock:
    def __init__(self) -> None:
        self.now_s = 100.0

    def __call__(self) -> float:
        return self.now_s


def _pad_msg(left_y_browser=0.0, connected=True, mapping="standard"):
    return {"id": "Xbox Wireless Controller (STANDARD GAMEPAD)", "mapping": mapping, "connected": connected,
            "axes": [0.0, left_y_browser, 0.0, 0.0], "buttons": [[False, 0.0]] * 17, "haptics": False}


def _widget():
    clock = _Clock()
    pad = BrowserPad(session=_NoRos(), autostart=False, clock=clock)
    return pad, clock


def _send(pad, clock, count, period_s=0.0625, **pad_msg):
    """``count`` readings, sent and received ``period_s`` apart (a steady link)."""
    for _ in range(count):
        clock.now_s += period_s
        pad.reading = {"sent_s": clock.now_s - 90.0, "visible": True, "pad": _pad_msg(**pad_msg),
                       "seq": pad.input.received + 1}


def test_without_ros_it_says_why_in_one_red_line_and_the_pad_reads_released():
    pad, _clock = _widget()
    assert pad.status_error and "rospy is not installed" in pad.status
    assert not pad.tick().connected
    pad.close()


def test_a_steady_page_drives_and_a_silent_one_releases_after_the_heartbeat():
    pad, clock = _widget()
    _send(pad, clock, 6, left_y_browser=-1.0)  # browser up
    state = pad.tick()
    assert state.axis("left_y") == 1.0 and "left (+0.00, +1.00)" in pad.pad_line
    assert pad.echo_seq == 6  # the first usable reading is echoed for the round trip
    clock.now_s += pad.input.heartbeat.timeout_s
    assert pad.tick().axis("left_y") == 1.0
    clock.now_s += 1e-3
    assert pad.tick().axis("left_y") == 0.0
    assert pad.status_error and "no reading from the browser" in pad.status
    pad.close()


def test_an_unplugged_pad_releases_at_once_and_says_so():
    pad, clock = _widget()
    _send(pad, clock, 6, left_y_browser=-1.0)
    _send(pad, clock, 1, connected=False)
    assert pad.tick().axis("left_y") == 0.0 and "disconnected" in pad.status
    pad.close()


def test_the_nodes_rumble_goes_to_both_motors_and_stops_when_the_node_falls_silent():
    pad, clock = _widget()
    pad.on_rumble(SimpleNamespace(data=0.6))
    pad.tick()
    hold_ms = round(RumblePolicy().hold_s * 1000)
    assert pad.rumble == {"strong": pytest.approx(0.6), "weak": pytest.approx(0.6), "duration_ms": hold_ms, "seq": 1}
    clock.now_s += RUMBLE_SILENCE_S
    pad.tick()
    assert pad.rumble["strong"] == pytest.approx(0.6)  # a refresh at the same value
    clock.now_s += 1e-3
    pad.tick()
    assert pad.rumble["strong"] == 0.0 and pad.rumble["duration_ms"] == 0
    pad.close()


def test_pad_line_shows_sticks_triggers_and_held_buttons():
    line = pad_line(PadState({"left_x": 0.5, "r2": 0.25}, {"south": True}))
    assert line.startswith("left (+0.50, +0.00)  right (+0.00, +0.00)") and "R2 0.25" in line
    assert line.endswith("held: south")


def test_a_node_name_that_is_not_a_full_name_is_refused():
    with pytest.raises(WidgetError, match="full name"):
        BrowserPad("teleoperation", session=_NoRos(), autostart=False)


def test_widgets_gives_browser_pad_on_first_use():
    assert widgets.BrowserPad is BrowserPad
    with pytest.raises(AttributeError):
        widgets.NoSuchWidget  # noqa: B018 - the attribute access is the test
