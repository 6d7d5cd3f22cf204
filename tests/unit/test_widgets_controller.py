"""The controller view: the lab's TeleopController rules on a (virtual) pad, shown as SVG."""

from __future__ import annotations

import re
import time

import pytest

from hri_teleop.core.gamepad import PadState
from hri_teleop.core.teleop import Mode, TeleopParams
from hri_teleop.course.widgets.controller import (
    ControllerModel,
    ControllerView,
    button_roles,
    open_pad,
    pad_svg,
    stick_dot_xy,
)
from hri_teleop.sim.virtual_pad import VirtualPad


def test_holding_cross_closes_the_gripper_at_k_gripper_per_second_of_wall_time():
    pad = VirtualPad()
    params = TeleopParams(rate_hz=50.0, k_gripper=0.04, initial_width_m=0.08)
    model = ControllerModel(pad, params)
    pad.press("south")
    for _ in range(10):  # 10 refreshes of 0.05 s = 0.5 s, whatever the widget's rate
        snap = model.advance(0.05)
    assert snap.gripper_width_m == pytest.approx(0.08 - 0.04 * 0.5, abs=1e-9)
    assert model.ticks == 25


def test_a_slow_refresh_steps_whole_ticks_and_carries_the_rest():
    model = ControllerModel(VirtualPad(), TeleopParams(rate_hz=50.0))
    assert model.advance(0.03).ticks == 1
    assert model.advance(0.03).ticks == 2  # 0.01 carried + 0.03 = 0.04 s


def test_a_long_pause_of_the_kernel_is_not_replayed():
    model = ControllerModel(VirtualPad(), TeleopParams(rate_hz=50.0))
    assert model.advance(60.0).ticks == 25  # at most MAX_CATCH_UP_S = 0.5 s


def test_triangle_toggles_the_mode_once_per_press_and_square_quits():
    pad = VirtualPad()
    model = ControllerModel(pad)
    pad.press("north")
    assert model.advance(0.1).mode is Mode.ROTATION
    assert model.advance(0.1).mode is Mode.ROTATION  # still held: no second toggle
    pad.release("north")
    pad.press("west")
    assert model.advance(0.02).quit


def test_the_stick_drives_the_twist_through_the_dead_zone_and_the_limiter():
    pad = VirtualPad()
    model = ControllerModel(pad)
    pad.set_axis("left_y", 1.0)
    twist = [model.advance(0.02).twist for _ in range(200)][-1]
    assert twist[0] == pytest.approx(model.params.k_trans, rel=1e-6)
    pad.set_axis("left_y", 0.05)  # inside the 0.1 dead zone
    assert model.controller.target_twist(pad.poll())[0] == 0.0


def test_rumble_is_the_mapped_force_while_it_is_fresh():
    model = ControllerModel(VirtualPad())
    assert model.advance(0.02, mapped_force=0.6, force_age_s=0.0).rumble == 0.6
    assert model.advance(0.02, mapped_force=0.6, force_age_s=5.0).rumble == 0.0


def test_stick_up_is_up_on_screen():
    assert stick_dot_xy(100, 100, 40, 0.0, 1.0) == (100, 60)
    assert stick_dot_xy(100, 100, 40, 1.0, 0.0) == (140, 100)


def test_the_svg_shows_both_sticks_and_lights_held_buttons():
    state = PadState({"left_x": 0.5, "right_y": -1.0}, {"south": True})
    svg = pad_svg(state, 0.1, button_roles(TeleopParams()))
    left = re.search(r'class="stick-left-raw" cx="([\d.]+)" cy="([\d.]+)"', svg)
    right = re.search(r'class="stick-right-raw" cx="([\d.]+)" cy="([\d.]+)"', svg)
    assert (float(left.group(1)), float(left.group(2))) == (130 + 21, 135)
    assert (float(right.group(1)), float(right.group(2))) == (320, 135 + 42)
    assert 'class="button-south held"' in svg and 'class="button-north"' in svg
    assert ">close<" in svg and ">quit<" in svg


def test_without_a_gamepad_auto_falls_back_to_the_virtual_pad(monkeypatch):
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    pad, note = open_pad("auto")
    assert isinstance(pad, VirtualPad)
    assert "virtual pad" in note


def test_the_views_sliders_and_buttons_drive_the_virtual_pad():
    view = ControllerView("virtual", autostart=False)
    try:
        view.sticks["left_y"].value = 1.0
        view.hold_buttons["south"].held = True  # as the page sends it: pointer down on the button
        view.tap_buttons["north"].click()
        view._last_s -= 0.1
        snap = view.tick()
        assert snap.pad.axis("left_y") == 1.0 and snap.pad.pressed("south")
        assert snap.mode is Mode.ROTATION
        assert not view.pad.poll().pressed("north"), "a tap must be released once the controller saw it"
        assert "mode: rotation" in view.mode_label.value
        assert view.width_bar.value < 0.08
        view.reset()
        assert view.model.controller.mode is Mode.TRANSLATION and view.sticks["left_y"].value == 0.0
    finally:
        view.close()


def test_running_the_same_cell_again_closes_the_view_it_made_before():
    from hri_teleop.course.widgets._base import replace_in_cell

    first = ControllerView("virtual", autostart=False)
    first.ticker.start()
    replace_in_cell(first, "cell-1")
    second = ControllerView("virtual", autostart=False)
    replace_in_cell(second, "cell-1")
    assert not first.ticker.running and first.pad.poll().connected is False, "the old view still runs"
    other = ControllerView("virtual", autostart=False)
    replace_in_cell(other, "cell-2")
    assert second.pad.poll().connected
    for view in (second, other):
        view.close()


class _Clock:
    """A monotonic clock the test moves by hand."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def _held_view():
    clock = _Clock()
    view = ControllerView("virtual", autostart=False, clock=clock)
    return view, clock, view.hold_buttons[view.params.close_button]


def _tick(view, clock, seconds, beat=None):
    """``seconds`` of ticks of 0.05 s; ``beat``: the hold button the page keeps confirming meanwhile."""
    for _ in range(int(round(seconds / 0.05))):
        clock.now += 0.05
        if beat is not None and beat.held:
            beat.beat += 1
        snap = view.tick()
    return snap


def test_the_close_button_closes_the_gripper_only_while_it_is_held():
    view, clock, close = _held_view()
    try:
        close.held = True                         # pointer down
        held = _tick(view, clock, 0.5, beat=close)
        assert held.pad.pressed("south") and held.gripper_width_m == pytest.approx(0.08 - 0.04 * 0.5, abs=1e-3)
        close.held = False                        # pointer up (or it left the button, or the window lost focus)
        released = _tick(view, clock, 1.0)
        assert not released.pad.pressed("south")
        assert released.gripper_width_m == pytest.approx(held.gripper_width_m, abs=1e-3), \
            "the gripper went on closing after the button was let go (a latching button)"
    finally:
        view.close()


def test_a_held_button_whose_page_falls_silent_counts_as_released():
    view, clock, close = _held_view()
    try:
        close.held = True
        _tick(view, clock, 0.3, beat=close)
        silent = _tick(view, clock, 2.0)          # no beat: the tab closed, the link dropped
        assert not silent.pad.pressed("south")
        assert silent.gripper_width_m > 0.08 - 0.04 * (0.3 + close.timeout_s + 0.1), "closed on without the page"
        assert not close.is_held()
    finally:
        view.close()


def test_a_click_shorter_than_a_tick_closes_the_gripper_by_one_look_only():
    view, clock, close = _held_view()
    try:
        close.held = True
        close.held = False                        # down and up between two ticks
        once = _tick(view, clock, 0.05)
        assert once.pad.pressed("south") and once.gripper_width_m < 0.08
        later = _tick(view, clock, 1.0)
        assert not later.pad.pressed("south") and later.gripper_width_m == pytest.approx(once.gripper_width_m)
    finally:
        view.close()


def test_reset_lets_go_of_a_held_button():
    view, clock, close = _held_view()
    try:
        close.held = True
        _tick(view, clock, 0.2, beat=close)
        view.reset()
        after = _tick(view, clock, 0.5)
        assert not close.held and not after.pad.pressed("south") and after.gripper_width_m == pytest.approx(0.08)
    finally:
        view.close()


def test_the_browser_source_shows_the_page_pad_in_the_view_and_reads_it_without_ros():
    view = ControllerView("browser", autostart=False)
    try:
        page_pad = view.pad.widget
        assert page_pad in view.children and not view.virtual and page_pad.node is None
        buttons = [[False, 0.0]] * 17
        buttons[0] = [True, 1.0]  # the standard mapping's bottom face button: cross
        for number in range(1, 10):  # the page's clock is measured over a few readings in time first
            page_pad.reading = {"sent_s": time.monotonic() - 50.0, "visible": True, "seq": number,
                                "pad": {"id": "DualSense (STANDARD GAMEPAD)", "mapping": "standard",
                                        "connected": True, "axes": [0.0, -1.0, 0.0, 0.0], "buttons": buttons,
                                        "haptics": True}}
        view._last_s -= 0.1
        snap = view.tick()
        assert snap.pad.pressed("south") and snap.pad.axis("left_y") == 1.0 and snap.gripper_width_m < 0.08
        assert view.hold_buttons["south"].lit, "a button held on the page's pad is shown held"
        page_pad.tick()
        assert "is read by this notebook" in page_pad.status
    finally:
        view.close()
    assert not view.pad.widget.ticker.running
