"""The precision button (gains scaled while held, through the limiter) and the two rumble motors kept apart."""

from __future__ import annotations

import pytest

from hri_teleop.core.config import ConfigError, teleop_config_from_dict
from hri_teleop.core.gamepad import PadState
from hri_teleop.core.limits import DEFAULT_LIMITS
from hri_teleop.core.teleop import (
    AxisAssignment,
    Mode,
    TeleopController,
    TeleopError,
    TeleopParams,
    check_extra_button,
    combined_rumble,
    motor_rumble,
)

DT = 0.02
PRECISE = TeleopParams(precision_button="r1", precision_scale=0.3)


def stick(held: bool = False, value: float = 1.0) -> PadState:
    return PadState({"left_y": value}, {"r1": held}, True)


def test_the_precision_button_scales_the_gain_only_while_held():
    controller = TeleopController(PRECISE)
    assert controller.target_twist(stick(False))[0] == pytest.approx(PRECISE.k_trans)
    assert controller.target_twist(stick(True))[0] == pytest.approx(0.3 * PRECISE.k_trans)
    controller.step(stick(True, 0.0), None, 0.0, DT)
    controller.step(PadState({}, {"north": True}, True), None, 0.0, DT)  # rotation: k_rot is scaled too
    assert controller.mode is Mode.ROTATION
    assert controller.target_twist(stick(True))[3] == pytest.approx(0.3 * PRECISE.k_rot)


def test_without_a_precision_button_r1_changes_nothing():
    assert TeleopController().target_twist(stick(True))[0] == pytest.approx(TeleopParams().k_trans)


def test_a_press_ramps_the_twist_down_through_the_limiter_never_jumps():
    controller = TeleopController(PRECISE)
    for _ in range(200):
        vx = controller.step(stick(False), None, 0.0, DT).twist[0]
    assert vx == pytest.approx(PRECISE.k_trans)
    after = [controller.step(stick(True), None, 0.0, DT).twist[0] for _ in range(200)]
    steps = [a - b for a, b in zip([vx] + after, after)]
    assert max(steps) <= DEFAULT_LIMITS.translation.acceleration * DT * (1 + 1e-9)
    assert after[0] > 0.9 * PRECISE.k_trans and after[-1] == pytest.approx(0.3 * PRECISE.k_trans)


@pytest.mark.parametrize("scale, ok", [(1.0, True), (1e-6, True), (0.0, False), (1.0001, False), (-0.3, False)])
def test_precision_scale_is_in_zero_to_one(scale, ok):
    if ok:
        assert TeleopParams(precision_scale=scale).precision_scale == scale
    else:
        with pytest.raises(TeleopError, match="precision_scale must be in"):
            TeleopParams(precision_scale=scale)


def test_the_precision_button_must_be_free():
    with pytest.raises(TeleopError, match="different buttons"):
        TeleopParams(precision_button="south")
    with pytest.raises(TeleopError, match="different buttons"):
        TeleopParams(precision_button="l1", deadman_button="l1")
    with pytest.raises(TeleopError, match="already the precision button"):
        check_extra_button(PRECISE, "r1", "recover_button")
    with pytest.raises(TeleopError, match="precision_button must be empty or"):
        TeleopParams(precision_button="r4")


def test_the_config_file_names_the_precision_button_and_its_scale():
    config = teleop_config_from_dict({"buttons": {"precision": "r1"}, "precision_scale": 0.5})
    assert (config.params.precision_button, config.params.precision_scale) == ("r1", 0.5)
    assert teleop_config_from_dict({"buttons": {"precision": "none"}}).params.precision_button == ""
    with pytest.raises(ConfigError, match="precision_scale"):
        teleop_config_from_dict({"precision_scale": 2})


@pytest.mark.parametrize("force, warning, expected", [
    (0.6, 0.0, (0.6, 0.0)), (0.0, 0.6, (0.0, 0.6)), (0.3, 0.6, (0.3, 0.6)), (1.5, float("nan"), (1.0, 0.0))])
def test_split_motors_put_the_force_on_the_strong_motor_and_the_warning_on_the_weak_one(force, warning, expected):
    assert motor_rumble(force, warning, stopping=False) == expected


def test_combined_motors_both_feel_the_larger():
    assert motor_rumble(0.3, 0.6, False, motors="combined") == (0.6, 0.6) == (combined_rumble(0.3, 0.6, False),) * 2


@pytest.mark.parametrize("motors", ["split", "combined"])
def test_no_motor_runs_while_stopping_or_with_feedback_off(motors):
    assert motor_rumble(0.6, 0.6, True, motors=motors) == (0.0, 0.0)
    assert motor_rumble(0.6, 0.6, False, feedback=False, motors=motors) == (0.0, 0.0)


def test_rumble_motors_is_split_or_combined():
    assert TeleopParams().rumble_motors == "split"
    assert teleop_config_from_dict({"rumble_motors": "combined"}).params.rumble_motors == "combined"
    with pytest.raises(ConfigError, match="rumble_motors must be one of split, combined"):
        teleop_config_from_dict({"rumble_motors": "both"})
    with pytest.raises(TeleopError):
        motor_rumble(0.1, 0.1, False, motors="left")


def test_axes_used_are_what_drives_the_twist():
    assert AxisAssignment().axes_used() == ("left_x", "left_y", "right_y")
    assert AxisAssignment(rotation=("l2", "none", "-r2")).axes_used() == ("left_x", "left_y", "right_y", "l2", "r2")


@pytest.mark.parametrize("value, ok", [(0.0, True), (2.5, True), (-0.1, False)])
def test_stale_input_timeout_is_zero_for_off_or_positive(value, ok):
    if ok:
        assert teleop_config_from_dict({"stale_input_timeout": value}).params.stale_input_timeout_s == value
    else:
        with pytest.raises(ConfigError, match="stale_input_timeout"):
            teleop_config_from_dict({"stale_input_timeout": value})
