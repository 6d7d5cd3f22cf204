"""make doctor's verdicts (hri_teleop.core.doctor) at each threshold: what is ok, what fails and with which fix."""

from __future__ import annotations

from typing import List

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
    measured_rate_hz,
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


# What each finding says, word for word: the report is what a lab engineer reads. Every outcome of every
# check as the whole Finding (item, status, detail, fix), the texts written out here, not taken from the module.

URI = "http://lab:11311/"


def test_a_line_with_a_fix_prints_status_item_detail_the_arrow_and_the_fix_in_their_columns() -> None:
    assert Finding("board", FAIL, "gone", "plug it in").line() == "FAIL  board             gone  -> plug it in"
    assert Finding("real-time kernel", NOTE, "x").line() == "note  real-time kernel  x"


def test_a_line_of_a_finding_with_an_empty_detail_reads_back_at_its_24_characters() -> None:
    line = Finding("board", OK, "").line()
    assert len(line) == 24
    assert Finding.from_line(line) == Finding("board", OK, "")
    assert Finding.from_line(line[:23]) is None


@pytest.mark.parametrize("line", [
    "ok   xboard             fine",          # no blank after the status's column
    "FAIL  an item of 18 chars detail",     # the item runs into the detail's column
    "okay  board             fine",          # not a status
    "fail  board             fine"])         # a status is written as the report writes it
def test_a_line_out_of_the_reports_columns_is_not_a_finding(line: str) -> None:
    assert Finding.from_line(line) is None


def test_a_line_with_the_arrow_twice_keeps_the_second_in_the_fix() -> None:
    assert Finding.from_line("FAIL  board             gone  -> plug it in  -> again") == Finding(
        "board", FAIL, "gone", "plug it in  -> again")


def test_the_measured_rate_counts_the_intervals_between_the_first_and_the_last_arrival() -> None:
    assert measured_rate_hz([10.0, 10.25, 10.5, 10.75, 11.0]) == 4.0
    assert measured_rate_hz([0.0, 2.0]) == 0.5


@pytest.mark.parametrize("times_s", [[], [3.0], [3.0, 3.0], [3.0, 3.0, 3.0]])
def test_no_rate_from_fewer_than_two_arrivals_or_none_apart(times_s: List[float]) -> None:
    assert measured_rate_hz(times_s) is None


def test_a_finding_that_failed_fails_the_run_wherever_it_is_in_the_list() -> None:
    assert exit_code([Finding("a", FAIL, "", "x"), Finding("b", OK, "")]) == 1
    assert exit_code([Finding("a", NOTE, ""), Finding("b", NOTE, ""), Finding("c", FAIL, "", "x")]) == 1


@pytest.mark.parametrize("reachable, mode, private, expected", [
    (False, LAB, False, Finding("ROS master", FAIL, "none answers at http://lab:11311/ (lab mode)",
                                "start the lab's roscore or launch file first")),
    (False, LAB, True, Finding("ROS master", FAIL, "none answers at http://lab:11311/ (lab mode)",
                               "start the lab's roscore or launch file first")),
    (False, HOME, False, Finding("ROS master", FAIL, "none answers at http://lab:11311/ (home mode)",
                                 "start one: make demo (or roslaunch hri_lab teleoperation.launch sim:=true), "
                                 "or roscore")),
    (False, "grading", True, Finding("ROS master", FAIL, "none answers at http://lab:11311/ (grading mode)",
                                     "start one: make demo (or roslaunch hri_lab teleoperation.launch sim:=true), "
                                     "or roscore")),
    (True, LAB, True, Finding("ROS master", FAIL, "http://lab:11311/ is a private roscore, not the lab's",
                              "use the lab's ROS_MASTER_URI")),
    (True, LAB, False, Finding("ROS master", OK, "http://lab:11311/ (running, lab mode)")),
    (True, HOME, True, Finding("ROS master", OK, "http://lab:11311/ (a private roscore, home mode)")),
    (True, HOME, False, Finding("ROS master", OK, "http://lab:11311/ (running, home mode)")),
    (True, "grading", True, Finding("ROS master", OK, "http://lab:11311/ (a private roscore, grading mode)")),
])
def test_the_master_finding_says_whose_master_answers_and_the_fix_for_the_mode(
        reachable: bool, mode: str, private: bool, expected: Finding) -> None:
    assert master_finding(URI, reachable, mode, private) == expected


def test_a_bare_foreign_master_is_one_failure_with_its_cause_and_both_fixes_word_for_word() -> None:
    assert foreign_master_finding("http://localhost:11311") == Finding(
        "ROS master", FAIL,
        "a ROS master at http://localhost:11311 that the toolkit did not start, with no node on it: it is treated "
        "as the lab's (it may carry the robot), so nothing is simulated or checked there",
        "on the lab PC this is right: start the lab's launch file (or HRI_MODE=lab make doctor checks the bare "
        "station); at home stop that roscore (Ctrl-C in its terminal) and run make doctor again, which then checks "
        "a simulated lab on a master of its own")


NOBODY_LAB = Finding("robot", FAIL, "nobody subscribes to the velocity command",
                     "roslaunch franka_control franka_control_cartesian_velocity.launch (or the lab's launch file)")
NOBODY_HOME = Finding("robot", FAIL, "nobody subscribes to the velocity command",
                      "roslaunch hri_lab teleoperation.launch sim:=true")


@pytest.mark.parametrize("mode, listens, servers, missing, simulated, recovery, expected", [
    (LAB, False, [], [], False, True, NOBODY_LAB),
    (LAB, False, [], ["franka_gripper/move"], True, False, NOBODY_LAB),  # no subscriber is said first
    (HOME, False, [], [], True, True, NOBODY_HOME),
    ("grading", False, [], [], True, True, NOBODY_HOME),
    (LAB, True, ["move", "grasp"], ["franka_gripper/homing", "franka_gripper/stop"], False, True,
     Finding("robot", FAIL, "franka_control takes the twist, but franka_gripper/homing, franka_gripper/stop missing",
             "start franka_gripper (franka_control.launch load_gripper:=true)")),
    (LAB, True, GRIPPER, [], False, False,
     Finding("robot", FAIL, "franka_control takes the twist, but error_recovery missing",
             "start franka_gripper (franka_control.launch load_gripper:=true)")),
    (HOME, True, ["move"], ["franka_gripper/stop", "franka_gripper/grasp"], True, False,
     Finding("robot", FAIL, "the simulation (lab_sim) takes the twist, but franka_gripper/stop, franka_gripper/grasp, "
             "error_recovery missing", "restart lab_sim")),
    (LAB, True, GRIPPER, ["franka_gripper/stop"], True, True,  # a missing server is said before lab_sim in the lab
     Finding("robot", FAIL, "the simulation (lab_sim) takes the twist, but franka_gripper/stop missing",
             "restart lab_sim")),
    (LAB, True, GRIPPER, [], True, True,
     Finding("robot", FAIL, "lab_sim runs on the lab's master", "stop it: the real robot must be alone")),
    (LAB, True, GRIPPER, [], False, True,
     Finding("robot", OK, "franka_control: velocity command, gripper move, grasp, homing, stop, error_recovery")),
    (HOME, True, ["stop", "move"], [], True, True,
     Finding("robot", OK, "the simulation (lab_sim): velocity command, gripper stop, move, error_recovery")),
    (HOME, True, GRIPPER, [], False, True,
     Finding("robot", OK, "franka_control: velocity command, gripper move, grasp, homing, stop, error_recovery")),
])
def test_the_robot_finding_names_what_is_missing_in_order_and_the_fix_for_the_real_or_simulated_arm(
        mode: str, listens: bool, servers: List[str], missing: List[str], simulated: bool, recovery: bool,
        expected: Finding) -> None:
    assert robot_finding(mode, listens, servers, missing, simulated, recovery) == expected


REFUSED_FIX = "no force feedback this way: a USB cable or another pad, then restart the launch"


@pytest.mark.parametrize("mode, running, pad, rumble_ok, expected", [
    (LAB, False, "pygame", False,
     Finding("teleoperation", NOTE, "not running (roslaunch hri_lab teleoperation.launch starts it)")),
    (HOME, False, None, None,
     Finding("teleoperation", NOTE, "not running (roslaunch hri_lab teleoperation.launch starts it)")),
    (LAB, True, None, None, Finding("teleoperation", OK, "running with the pad teleop.yaml names")),
    (LAB, True, "", None, Finding("teleoperation", OK, "running with the pad teleop.yaml names")),
    (LAB, True, 3, True, Finding("teleoperation", OK, "running with the pad teleop.yaml names; rumble accepted")),
    (LAB, True, "pygame", True, Finding("teleoperation", OK, "running with pygame; rumble accepted")),
    (HOME, True, "script", None, Finding("teleoperation", OK, "running with script")),
    (HOME, True, "virtual", True, Finding("teleoperation", OK, "running with the virtual pad; rumble accepted")),
    (LAB, True, "pygame", False,
     Finding("teleoperation", FAIL, "running with pygame, whose pad refused the start check's rumble", REFUSED_FIX)),
    (LAB, True, None, False,
     Finding("teleoperation", FAIL, "running with the pad teleop.yaml names, whose pad refused the start check's "
             "rumble", REFUSED_FIX)),
    (LAB, True, "virtual", False,  # a refused rumble is said before the virtual pad in the lab
     Finding("teleoperation", FAIL, "running with the virtual pad, whose pad refused the start check's rumble",
             REFUSED_FIX)),
    (LAB, True, "virtual", None,
     Finding("teleoperation", NOTE, "running with the virtual pad: a notebook's widget drives the robot")),
    (LAB, True, "virtual", True,
     Finding("teleoperation", NOTE, "running with the virtual pad: a notebook's widget drives the robot")),
    ("grading", True, "virtual", None, Finding("teleoperation", OK, "running with the virtual pad")),
])
def test_the_teleoperation_finding_names_the_pad_read_and_the_start_checks_rumble(
        mode: str, running: bool, pad: object, rumble_ok: object, expected: Finding) -> None:
    assert teleop_finding(mode, running, pad, rumble_ok) == expected  # type: ignore[arg-type]


def test_the_start_checks_rumble_is_not_mentioned_unless_given() -> None:
    assert teleop_finding(LAB, True, "pygame") == Finding("teleoperation", OK, "running with pygame")


NO_COUNTS_FIX = "check the cable and that the sketch is uploaded (firmware/README.md)"


@pytest.mark.parametrize("rate_hz, samples, expected", [
    (None, 0, Finding("board", FAIL, "/dev/ttyUSB0: rosserial, no counts arrived", NO_COUNTS_FIX)),
    (None, 50, Finding("board", FAIL, "/dev/ttyUSB0: rosserial, no counts arrived", NO_COUNTS_FIX)),
    (3.3, 1, Finding("board", FAIL, "/dev/ttyUSB0: rosserial, no counts arrived", NO_COUNTS_FIX)),
    (3.3, 2, Finding("board", OK, "/dev/ttyUSB0: rosserial at 3.3 Hz (2 counts)")),
    (3.01, 3, Finding("board", OK, "/dev/ttyUSB0: rosserial at 3.0 Hz (3 counts)")),
    (2.99, 30, Finding("board", FAIL, "/dev/ttyUSB0: rosserial at 3.0 Hz, expected 3.3 Hz",
                       "re-upload the sketch, or check that nothing else reads the port")),
    (3.67, 30, Finding("board", FAIL, "/dev/ttyUSB0: rosserial at 3.7 Hz, expected 3.3 Hz",
                       "re-upload the sketch, or check that nothing else reads the port")),
    (3.66, 30, Finding("board", OK, "/dev/ttyUSB0: rosserial at 3.7 Hz (30 counts)")),
])
def test_the_board_finding_for_the_handouts_sketch_at_3_33_hz_is_ok_between_3_0_and_3_67_hz(
        rate_hz: object, samples: int, expected: Finding) -> None:
    assert board_rate_finding("/dev/ttyUSB0", ROSSERIAL, rate_hz, samples, 10 / 3) == expected  # type: ignore[arg-type]


NOT_A_COUNT_FIX = "set the count you read at full piston travel (Ex. 11), e.g. 700"


@pytest.mark.parametrize("value, live_max, pressed, expected", [
    (None, 500, True, Finding("max_sensor_force", FAIL, "not set", "calibrate (Ex. 11) and set it: hri_lab/config/"
                              "calibration.yaml, or rosparam set /max_sensor_force <count>")),
    (0, None, False, Finding("max_sensor_force", FAIL, "0 is not a count in 1..1023", NOT_A_COUNT_FIX)),
    (1024, 700, True, Finding("max_sensor_force", FAIL, "1024 is not a count in 1..1023", NOT_A_COUNT_FIX)),
    ("700", 700, True, Finding("max_sensor_force", FAIL, "'700' is not a count in 1..1023", NOT_A_COUNT_FIX)),
    (700.0, None, False, Finding("max_sensor_force", FAIL, "700.0 is not a count in 1..1023", NOT_A_COUNT_FIX)),
    (True, None, False, Finding("max_sensor_force", FAIL, "True is not a count in 1..1023", NOT_A_COUNT_FIX)),
    (1, None, True, Finding("max_sensor_force", OK, "1 (no live reading to compare)")),
    (1023, None, False, Finding("max_sensor_force", OK, "1023 (no live reading to compare)")),
    (700, 805, True, Finding("max_sensor_force", OK, "700; a full press reads 805")),
    (700, 595, True, Finding("max_sensor_force", OK, "700; a full press reads 595")),
    (700, 806, True, Finding("max_sensor_force", FAIL, "700, but a full press reads 806 now",
                             "calibrate again (Ex. 11): the FSR or its seat changed")),
    (700, 594, True, Finding("max_sensor_force", FAIL, "700, but a full press reads 594 now",
                             "calibrate again (Ex. 11): the FSR or its seat changed")),
    (700, 699, False, Finding("max_sensor_force", OK,
                              "700; the sensor reads up to 699 now (--walk: compare a full press)")),
    (700, 700, False, Finding("max_sensor_force", OK,
                              "700; the sensor reads up to 700 now (--walk: compare a full press)")),
    (700, 0, False, Finding("max_sensor_force", OK, "700; the sensor reads up to 0 now (--walk: compare a full press)")),
    (700, 701, False, Finding("max_sensor_force", FAIL, "700, but the sensor reads 701 now, above it",
                              "release the piston and run again; if it reads that at rest, calibrate again (Ex. 11)")),
])
def test_the_calibration_finding_compares_the_value_with_a_full_press_or_the_reading_at_rest(
        value: object, live_max: object, pressed: bool, expected: Finding) -> None:
    assert calibration_finding(value, live_max, pressed) == expected  # type: ignore[arg-type]


@pytest.mark.parametrize("live_max, status", [(84, FAIL), (85, OK), (86, OK), (114, OK), (115, OK), (116, FAIL)])
def test_a_full_press_of_a_100_count_calibration_reads_85_to_115(live_max: int, status: str) -> None:
    assert calibration_finding(100, live_max, True).status == status


LAYOUT_FIX = "pick one: layout:=dualshock4 | dualsense | dualsense_hid_generic | xbox, then WALK=1 to check it"


@pytest.mark.parametrize("mode, found, layout, reason, expected", [
    (LAB, None, None, "no gamepad",
     Finding("pad", FAIL, "no gamepad", "plug the pad in (USB); `ls /dev/input/js*` should list it")),
    (LAB, None, "xbox", "by name",
     Finding("pad", FAIL, "no gamepad", "plug the pad in (USB); `ls /dev/input/js*` should list it")),
    (HOME, None, None, "no gamepad",
     Finding("pad", NOTE, "no gamepad: the virtual pad (or widgets.BrowserPad) stands in at home")),
    ("grading", None, None, "no gamepad",
     Finding("pad", NOTE, "no gamepad: the virtual pad (or widgets.BrowserPad) stands in at home")),
    (LAB, "Some pad", None, "vendor 1234 unknown",
     Finding("pad", NOTE, "Some pad; layout not identified (vendor 1234 unknown)", LAYOUT_FIX)),
    (HOME, "Some pad", None, "no GUID", Finding("pad", NOTE, "Some pad; layout not identified (no GUID)", LAYOUT_FIX)),
    (LAB, "Wireless Controller", "dualshock4", "DualShock 4 by its GUID",
     Finding("pad", OK, "Wireless Controller; layout dualshock4 (DualShock 4 by its GUID)")),
    (HOME, "Xbox pad", "xbox", "by name", Finding("pad", OK, "Xbox pad; layout xbox (by name)")),
])
def test_the_pad_finding_names_the_pad_its_layout_and_how_it_was_identified(
        mode: str, found: object, layout: object, reason: str, expected: Finding) -> None:
    assert pad_finding(mode, found, layout, reason) == expected  # type: ignore[arg-type]


WALK_FIX = "pick this pad's layout (layout:=..., hri_teleop/core/gamepad/layouts/) or add one"


@pytest.mark.parametrize("wrong, unseen, expected", [
    (["cross / A reads as circle / B", "left stick up reads reversed"], ["square / X"],
     Finding("pad buttons", FAIL, "cross / A reads as circle / B; left stick up reads reversed", WALK_FIX)),
    (["cross / A reads as circle / B"], [], Finding("pad buttons", FAIL, "cross / A reads as circle / B", WALK_FIX)),
    ([], ["square / X", "L1 / LB"], Finding("pad buttons", NOTE, "not tried: square / X, L1 / LB")),
    ([], [], Finding("pad buttons", OK, "every button and stick the lab uses reads as it should")),
])
def test_the_walk_finding_lists_the_wrong_controls_else_the_untried_ones_in_the_order_of_the_walk(
        wrong: List[str], unseen: List[str], expected: Finding) -> None:
    assert walk_finding(wrong, unseen) == expected


REFUSES = Finding("rumble", FAIL, "the pad refuses to rumble: no force feedback with it",
                  "use a USB cable or another pad (some Bluetooth links carry no rumble); the driver needs force "
                  "feedback and /dev/input/event* writable")


@pytest.mark.parametrize("accepted, felt, expected", [
    (False, None, REFUSES),
    (False, True, REFUSES),
    (False, False, REFUSES),
    (True, None, Finding("rumble", OK, "accepted by the pad (--walk asks whether you felt it)")),
    (True, True, Finding("rumble", OK, "accepted and felt")),
    (True, False, Finding("rumble", FAIL, "accepted but not felt", "check the pad's battery and connection; try USB")),
])
def test_the_rumble_finding_says_refused_accepted_felt_or_not_felt(accepted: bool, felt: object,
                                                                    expected: Finding) -> None:
    assert rumble_finding(accepted, felt) == expected  # type: ignore[arg-type]


NOT_RT_LAB = Finding("real-time kernel", FAIL, "not a PREEMPT_RT kernel",
                     "boot the lab PC's real-time kernel (libfranka refuses to control the robot without it)")
NOT_RT_HOME = Finding("real-time kernel", NOTE, "not PREEMPT_RT: fine at home, the robot's PC needs one")


@pytest.mark.parametrize("mode, version, flag, expected", [
    (LAB, "#1 SMP PREEMPT_RT Tue Jan 9", None, Finding("real-time kernel", OK, "PREEMPT_RT")),
    (HOME, "#1 SMP PREEMPT_RT Tue Jan 9", "0", Finding("real-time kernel", OK, "PREEMPT_RT")),
    (LAB, "#1 SMP PREEMPT_DYNAMIC", "1", Finding("real-time kernel", OK, "PREEMPT_RT")),
    (LAB, "#1 SMP PREEMPT_DYNAMIC", " 1\n", Finding("real-time kernel", OK, "PREEMPT_RT")),
    (LAB, "#1 SMP PREEMPT_DYNAMIC", "0\n", NOT_RT_LAB),
    (LAB, "#1 SMP PREEMPT_DYNAMIC", "", NOT_RT_LAB),
    (LAB, "#1 SMP PREEMPT_DYNAMIC", "11", NOT_RT_LAB),
    (LAB, "#1 SMP preempt_rt", None, NOT_RT_LAB),
    (LAB, "#1 SMP PREEMPT_DYNAMIC", None, NOT_RT_LAB),
    (HOME, "#1 SMP PREEMPT_DYNAMIC", None, NOT_RT_HOME),
    ("grading", "#1 SMP PREEMPT_DYNAMIC", "0", NOT_RT_HOME),
])
def test_the_kernel_finding_is_ok_for_preempt_rt_in_uname_or_a_realtime_flag_of_1(
        mode: str, version: str, flag: object, expected: Finding) -> None:
    assert kernel_finding(mode, version, flag) == expected  # type: ignore[arg-type]


GOVERNOR_FIX = "sudo cpupower frequency-set -g performance (frequency changes cost the 1 kHz loop)"


@pytest.mark.parametrize("mode, governors, expected", [
    (LAB, [], Finding("CPU governor", NOTE, "no cpufreq here (a virtual machine?)")),
    (HOME, [], Finding("CPU governor", NOTE, "no cpufreq here (a virtual machine?)")),
    (LAB, ["performance", "performance"], Finding("CPU governor", OK, "performance on 2 cores")),
    (HOME, ["performance"] * 4, Finding("CPU governor", OK, "performance on 4 cores")),
    (LAB, ["powersave", "performance", "ondemand", "powersave"],
     Finding("CPU governor", FAIL, "ondemand, powersave on some cores", GOVERNOR_FIX)),
    (LAB, ["schedutil"], Finding("CPU governor", FAIL, "schedutil on some cores", GOVERNOR_FIX)),
    (HOME, ["schedutil", "powersave", "schedutil"],
     Finding("CPU governor", NOTE, "powersave, schedutil: fine at home, the robot's PC needs performance")),
    ("grading", ["powersave"],
     Finding("CPU governor", NOTE, "powersave: fine at home, the robot's PC needs performance")),
])
def test_the_governor_finding_names_each_slow_governor_once_in_alphabetical_order(
        mode: str, governors: List[str], expected: Finding) -> None:
    assert governor_finding(mode, governors) == expected
