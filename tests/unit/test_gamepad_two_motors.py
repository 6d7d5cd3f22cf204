"""Two rumble motors apart (force on the strong one, the joint warning on the weak one) and the start check."""

from __future__ import annotations

import pytest
from test_gamepad_pygame import FakeJoystick, PygameError  # tests/unit, on sys.path under pytest

from hri_teleop.core.gamepad import RumbleRequests
from hri_teleop.hardware.real.pygame_pad import PygamePad
from hri_teleop.sim.virtual_pad import RumbleRecord, VirtualPad


def test_each_motor_gets_its_own_request_when_it_changes():
    requests = RumbleRequests()
    assert requests.update_motors(0.5, 0.0, 0.0) == (0.5, 0.0, 0.5)
    assert requests.update_motors(0.5, 0.0, 0.1) is None  # unchanged, before the refresh
    assert requests.update_motors(0.5, 0.6, 0.12) == (0.5, 0.6, 0.5)  # the warning starts on the weak motor
    assert requests.update_motors(0.5, 0.6 + 0.019, 0.13) is None  # below the change worth a request
    assert requests.update_motors(0.5, 0.6 + 0.021, 0.14) is not None
    assert requests.update_motors(0.0, 0.0, 0.15) == (0.0, 0.0, 0.0)  # off: at once, lasting until the next


def test_one_level_requests_keep_their_old_meaning():
    requests = RumbleRequests()
    assert requests.update(0.7, 0.0) == (0.7, 0.5) and requests.update(0.7, 0.1) is None
    assert requests.update(0.7, 0.25) == (0.7, 0.5)  # refreshed while on


def test_the_real_pad_drives_the_two_motors_apart():
    js = FakeJoystick()
    pad = PygamePad("dualshock4", joystick=js)
    pad.rumble_motors(0.8, 0.3, 0.5)
    pad.rumble(0.4, 0.5)
    assert js.rumble_calls == [(0.8, 0.3, 500), (0.4, 0.4, 500)]
    pad.rumble_motors(0.0, 0.0, 0.0)
    assert js.stops == 1


def test_the_virtual_pad_records_both_motors():
    pad = VirtualPad(clock=lambda: 1.0)
    pad.rumble_motors(0.2, 0.9, 0.5)
    pad.rumble(0.4, 0.5)
    assert pad.rumbles == [RumbleRecord(1.0, 0.9, 0.5, 0.2, 0.9), RumbleRecord(1.0, 0.4, 0.5, 0.4, 0.4)]
    assert pad.check_rumble(0.5, 0.2) == (True, "") and len(pad.rumbles) == 2  # a check leaves no record


def test_the_start_check_rumbles_briefly_and_reports_a_refusal_with_its_cause():
    ok = FakeJoystick()
    assert PygamePad("dualshock4", joystick=ok).check_rumble(0.5, 0.2) == (True, "")
    assert ok.rumble_calls == [(0.5, 0.5, 200)]
    logged: list = []
    refused = PygamePad("dualshock4", joystick=FakeJoystick(rumble_ok=False), log=logged.append)
    accepted, why = refused.check_rumble(0.5, 0.2)
    assert not accepted and "SDL reports no rumble" in why
    refused.rumble(0.7, 0.5)
    assert logged == []  # the node said it once, with the fix: no second warning


@pytest.mark.parametrize("error, words", [(AttributeError("rumble"), "pygame >= 2.0.2"),
                                          (PygameError("Haptic effect failed"), "SDL: Haptic effect failed")])
def test_the_start_check_names_why_a_pad_cannot_rumble(error, words):
    class Broken(FakeJoystick):
        def rumble(self, low, high, duration_ms):
            raise error

    accepted, why = PygamePad("dualshock4", joystick=Broken()).check_rumble(0.5, 0.2)
    assert not accepted and words in why


# ------------------------------------------------------------------ the visible cue in the notebook

def test_the_controller_view_says_in_red_when_the_real_pad_refuses_rumble():
    from hri_teleop.course.widgets.controller import ControllerView, rumble_cue

    refusing = PygamePad("dualshock4", joystick=FakeJoystick(rumble_ok=False))
    view = ControllerView(refusing, autostart=False)
    try:
        assert "refuses rumble" in view.status.value and "#b00020" in view.status.value
        assert "USB" in view.status.value
    finally:
        view.close()
    assert rumble_cue(PygamePad("dualshock4", joystick=FakeJoystick())) == ""
    assert rumble_cue(refusing, feedback=False) == ""  # Ex. 14's silent pad: not even the check
    assert rumble_cue(VirtualPad()) == ""


def test_the_live_plot_cue_follows_the_nodes_latched_check():
    from hri_teleop.course.widgets.live import pad_cue_html

    assert pad_cue_html(None) == ""
    assert "accepted" in pad_cue_html(True) and "#b00020" not in pad_cue_html(True)
    assert "refuses rumble" in pad_cue_html(False) and "#b00020" in pad_cue_html(False)


def test_the_controller_view_names_the_identified_layout_and_the_precision_button(monkeypatch):
    from test_gamepad_identify import GuidJoystick  # tests/unit, on sys.path under pytest

    from hri_teleop.core.teleop import TeleopParams
    from hri_teleop.course.widgets import controller

    device = GuidJoystick("050000004c050000e60c000000810000", "Wireless Controller", 6, 13)
    monkeypatch.setattr(controller, "open_gamepad", lambda kind, layout: PygamePad(layout, joystick=device))
    _pad, note = controller.open_pad("auto", "auto")
    assert "layout dualsense (auto: DualSense (054c:0ce6) over Bluetooth by its GUID" in note
    assert controller.button_roles(TeleopParams(precision_button="r1"))["r1"] == "precision"
