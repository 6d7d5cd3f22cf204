"""make doctor's verdicts (hri_teleop.core.doctor) at each threshold: what is ok, what fails and with which fix."""

from __future__ import annotations

import pytest

from hri_teleop.core.doctor import (
    CALIBRATION_TOLERANCE,
    FAIL,
    FSR_SERIAL,
    HANDOUT_SKETCH_HZ,
    LAB_BOARD_HZ,
    MAX_PERIOD_MS,
    MIN_PERIOD_MS,
    NOTE,
    OK,
    RATE_TOLERANCE,
    ROSSERIAL,
    Finding,
    board_rate_finding,
    calibration_finding,
    exit_code,
    expected_board_hz,
    foreign_master_finding,
    governor_finding,
    kernel_finding,
    master_finding,
    pad_finding,
    robot_finding,
    rumble_finding,
    teleop_finding,
    walk_finding,
)
from hri_teleop.core.modes import HOME, LAB

GRIPPER = ["move", "grasp", "homing", "stop"]


def test_a_line_names_status_item_detail_and_the_fix_only_when_there_is_one() -> None:
    assert Finding("board", OK, "fine").line() == "ok    board             fine"
    assert Finding("board", FAIL, "gone", "plug it in").line().endswith("gone  -> plug it in")


def test_exit_code_fails_on_a_failure_only_notes_pass() -> None:
    assert exit_code([Finding("a", OK, ""), Finding("b", NOTE, "")]) == 0
    assert exit_code([Finding("a", OK, ""), Finding("b", FAIL, "", "x")]) == 1
    assert exit_code([]) == 0


@pytest.mark.parametrize("mode", [HOME, LAB])
def test_no_master_fails_with_a_fix_for_the_mode(mode: str) -> None:
    finding = master_finding("http://localhost:11311/", False, mode, private=False)
    assert finding.status == FAIL
    assert ("lab's roscore" in finding.fix) == (mode == LAB)


def test_a_private_master_is_wrong_in_the_lab_and_fine_at_home() -> None:
    assert master_finding("http://127.0.0.1:40000/", True, LAB, private=True).status == FAIL
    assert master_finding("http://127.0.0.1:40000/", True, HOME, private=True).status == OK
    assert master_finding("http://lab:11311/", True, LAB, private=False).status == OK


def test_robot_needs_a_twist_subscriber_every_gripper_server_and_recovery() -> None:
    assert robot_finding(LAB, False, [], [], False, False).status == FAIL
    assert robot_finding(LAB, True, GRIPPER, [], False, True).status == OK
    missing = robot_finding(LAB, True, GRIPPER[:3], ["franka_gripper/stop"], False, True)
    assert missing.status == FAIL and "franka_gripper/stop" in missing.detail
    no_recovery = robot_finding(LAB, True, GRIPPER, [], False, False)
    assert no_recovery.status == FAIL and "error_recovery" in no_recovery.detail


def test_the_simulated_robot_is_fine_at_home_and_refused_on_the_labs_master() -> None:
    assert robot_finding(HOME, True, GRIPPER, [], True, True).status == OK
    refused = robot_finding(LAB, True, GRIPPER, [], True, True)
    assert refused.status == FAIL and "lab_sim" in refused.detail


def test_teleoperation_not_running_is_a_note_and_its_pad_is_named() -> None:
    assert teleop_finding(HOME, False, None).status == NOTE
    assert teleop_finding(HOME, True, "virtual") == Finding("teleoperation", OK, "running with the virtual pad")
    assert teleop_finding(LAB, True, "pygame").detail == "running with pygame"
    assert teleop_finding(LAB, True, "virtual").status == NOTE
    assert "teleop.yaml" in teleop_finding(LAB, True, None).detail


def test_a_pad_that_refused_the_nodes_start_rumble_fails_and_an_accepted_one_says_so() -> None:
    refused = teleop_finding(LAB, True, "pygame", rumble_ok=False)
    assert refused.status == FAIL and "refused" in refused.detail and "USB" in refused.fix
    assert teleop_finding(LAB, True, "pygame", rumble_ok=True).detail == "running with pygame; rumble accepted"
    assert teleop_finding(LAB, True, "pygame", rumble_ok=None).detail == "running with pygame"


def test_expected_rate_fsr_serial_from_its_banner_else_100_hz() -> None:
    assert expected_board_hz(FSR_SERIAL, banner_period_us=20000) == pytest.approx(50.0)
    assert expected_board_hz(FSR_SERIAL, banner_period_us=0) == LAB_BOARD_HZ
    assert expected_board_hz(FSR_SERIAL) == LAB_BOARD_HZ


@pytest.mark.parametrize("period_ms, hz", [
    (MIN_PERIOD_MS, 1000 / MIN_PERIOD_MS), (MIN_PERIOD_MS - 1, HANDOUT_SKETCH_HZ),
    (MAX_PERIOD_MS, 1000 / MAX_PERIOD_MS), (MAX_PERIOD_MS + 1, HANDOUT_SKETCH_HZ),
    (10, 100.0), (None, HANDOUT_SKETCH_HZ), ("10", HANDOUT_SKETCH_HZ), (True, HANDOUT_SKETCH_HZ)])
def test_expected_rate_rosserial_from_publish_period_ms_within_the_sketchs_range(period_ms: object, hz: float) -> None:
    assert expected_board_hz(ROSSERIAL, period_param_ms=period_ms) == pytest.approx(hz)


@pytest.mark.parametrize("fraction, status", [(1 - RATE_TOLERANCE + 1e-6, OK), (1 - RATE_TOLERANCE - 1e-3, FAIL),
                                              (1 + RATE_TOLERANCE - 1e-6, OK), (1 + RATE_TOLERANCE + 1e-3, FAIL)])
def test_board_rate_within_the_tolerance_is_ok(fraction: float, status: str) -> None:
    assert board_rate_finding("/dev/ttyACM0", ROSSERIAL, 100.0 * fraction, 200, 100.0).status == status


@pytest.mark.parametrize("rate_hz, status", [(89.9, FAIL), (90.0, OK), (90.1, OK),
                                             (109.9, OK), (110.0, OK), (110.1, FAIL)])
def test_a_board_expected_at_100_hz_is_ok_from_90_to_110_hz(rate_hz: float, status: str) -> None:
    assert board_rate_finding("/dev/ttyACM0", FSR_SERIAL, rate_hz, 200, 100.0).status == status


@pytest.mark.parametrize("rate_hz, status", [(44.9, FAIL), (45.0, OK), (55.0, OK), (55.1, FAIL)])
def test_a_board_expected_at_50_hz_is_ok_from_45_to_55_hz(rate_hz: float, status: str) -> None:
    assert board_rate_finding("/dev/ttyACM0", ROSSERIAL, rate_hz, 200, 50.0).status == status


def test_the_board_line_names_the_port_the_sketch_and_both_rates() -> None:
    bad = board_rate_finding("/dev/ttyACM1", ROSSERIAL, 3.0, 12, 100.0)
    assert bad.detail == "/dev/ttyACM1: rosserial at 3.0 Hz, expected 100.0 Hz" and "re-upload" in bad.fix
    good = board_rate_finding("/dev/ttyACM1", FSR_SERIAL, 99.5, 200, 100.0)
    assert good.detail == "/dev/ttyACM1: fsr_serial at 99.5 Hz (200 counts)" and good.fix == ""


@pytest.mark.parametrize("banner_period_us, hz", [(10000, 100.0), (20000, 50.0), (1, 1e6), (0, 100.0), (-5, 100.0),
                                                  ("10000", 100.0), (None, 100.0)])
def test_fsr_serial_is_expected_at_its_banners_period_else_at_100_hz(banner_period_us: object, hz: float) -> None:
    assert expected_board_hz(FSR_SERIAL, banner_period_us=banner_period_us) == hz


@pytest.mark.parametrize("period_ms, hz", [(4, 1000 / 300), (5, 200.0), (6, 1000 / 6), (9999, 1000 / 9999),
                                           (10000, 0.1), (10001, 1000 / 300), (300, 1000 / 300)])
def test_rosserial_is_expected_at_its_period_from_5_to_10000_ms_else_every_300_ms(period_ms: int, hz: float) -> None:
    assert expected_board_hz(ROSSERIAL, period_param_ms=period_ms) == hz


@pytest.mark.parametrize("live_max, status", [(594, FAIL), (595, OK), (596, OK), (804, OK), (805, OK), (806, FAIL)])
def test_a_full_press_of_a_700_count_calibration_reads_595_to_805(live_max: int, status: str) -> None:
    assert calibration_finding(700, live_max, True).status == status


def test_a_board_that_sent_fewer_than_two_counts_fails() -> None:
    assert board_rate_finding("/dev/ttyACM0", FSR_SERIAL, None, 0, 100.0).status == FAIL
    assert board_rate_finding("/dev/ttyACM0", FSR_SERIAL, 100.0, 1, 100.0).status == FAIL
    assert board_rate_finding("/dev/ttyACM0", FSR_SERIAL, 100.0, 2, 100.0).status == OK


@pytest.mark.parametrize("value", [None, 0, 1024, "700", 700.5, True])
def test_calibration_unset_or_not_a_count_fails(value: object) -> None:
    assert calibration_finding(value, None, False).status == FAIL


def test_calibration_at_rest_fails_only_above_the_value() -> None:
    assert calibration_finding(700, 700, False).status == OK
    assert calibration_finding(700, 701, False).status == FAIL
    assert calibration_finding(700, None, False).status == OK
    assert calibration_finding(1, None, False).status == OK and calibration_finding(1023, None, False).status == OK


def test_a_full_press_must_read_within_the_tolerance_of_the_value() -> None:
    edge = round(CALIBRATION_TOLERANCE * 700)  # 105
    assert calibration_finding(700, 700 - edge, True).status == OK
    assert calibration_finding(700, 700 - edge - 1, True).status == FAIL
    assert calibration_finding(700, 700 + edge, True).status == OK
    assert calibration_finding(700, 700 + edge + 1, True).status == FAIL


def test_pad_missing_fails_in_the_lab_only_and_an_unknown_layout_is_a_note_with_the_fix() -> None:
    assert pad_finding(LAB, None, None, "no gamepad").status == FAIL
    assert pad_finding(HOME, None, None, "no gamepad").status == NOTE
    unknown = pad_finding(LAB, "Some pad", None, "vendor 1234 unknown")
    assert unknown.status == NOTE and "layout:=" in unknown.fix
    known = pad_finding(LAB, "Wireless Controller", "dualshock4", "DualShock 4 by its GUID")
    assert known.status == OK and "dualshock4" in known.detail


def test_walk_fails_on_a_control_under_another_name_notes_the_skipped_and_passes_all_seen() -> None:
    assert walk_finding(["cross reads as circle"], ["square"]).status == FAIL
    assert walk_finding([], ["square"]) == Finding("pad buttons", NOTE, "not tried: square")
    assert walk_finding([], []).status == OK


def test_rumble_refused_or_not_felt_fails_accepted_or_felt_passes() -> None:
    assert rumble_finding(False, None).status == FAIL
    assert rumble_finding(True, None).status == OK
    assert rumble_finding(True, True).status == OK
    assert rumble_finding(True, False).status == FAIL


def test_the_real_time_kernel_is_required_in_the_lab_only() -> None:
    assert kernel_finding(LAB, "#1 SMP PREEMPT_RT Tue", None).status == OK
    assert kernel_finding(LAB, "#1 SMP PREEMPT_DYNAMIC", "1").status == OK
    assert kernel_finding(LAB, "#1 SMP PREEMPT_DYNAMIC", "0").status == FAIL
    assert kernel_finding(HOME, "#1 SMP PREEMPT_DYNAMIC", None).status == NOTE


def test_the_governor_must_be_performance_on_every_core_in_the_lab() -> None:
    assert governor_finding(LAB, ["performance", "performance"]).status == OK
    slow = governor_finding(LAB, ["performance", "powersave"])
    assert slow.status == FAIL and "powersave" in slow.detail
    assert governor_finding(HOME, ["powersave"]).status == NOTE
    assert governor_finding(LAB, []).status == NOTE


@pytest.mark.parametrize("finding", [Finding("ROS master", OK, "http://x:1/ (running, lab mode)"),
                                     Finding("real-time kernel", FAIL, "not PREEMPT_RT", "boot it -> now"),
                                     Finding("pad buttons", NOTE, "not tried: square")])
def test_a_printed_line_reads_back_as_its_finding(finding: Finding) -> None:
    assert Finding.from_line(finding.line()) == finding


@pytest.mark.parametrize("line", ["doctor: 3 of 3 ok or noted, 0 to fix (1.0 s)", "      press cross / A",
                                  "ok", ""])
def test_other_lines_are_not_findings(line: str) -> None:
    assert Finding.from_line(line) is None


def test_a_bare_master_somebody_else_started_fails_once_naming_it_and_the_fix_at_home_and_in_the_lab() -> None:
    finding = foreign_master_finding("http://localhost:11311")
    assert (finding.status, finding.item) == (FAIL, "ROS master")
    assert finding.detail.startswith("a ROS master at http://localhost:11311 that the toolkit did not start")
    assert "start the lab's launch file" in finding.fix and "at home stop that roscore" in finding.fix
    assert Finding.from_line(finding.line()) == finding
