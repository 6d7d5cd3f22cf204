"""The simulated Franka Hand, object and FSR attachment (hri_teleop.hardware.sim.hand): physics and goals."""

from __future__ import annotations

import ast
import math
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core import attachment, fsr
from hri_teleop.core.attachment import Attachment, AttachmentError
from hri_teleop.core.gripper import GoalThrottle
from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M
from hri_teleop.hardware.sim import grasp_objects, gripper_goals, hand_params
from hri_teleop.hardware.sim import hand as hand_module
from hri_teleop.hardware.sim.grasp_objects import OBJECTS, GraspObject, holding_force_n, is_held
from hri_teleop.hardware.sim.gripper_goals import (
    GoalStatus,
    GraspCommand,
    HomingCommand,
    MoveCommand,
    StopCommand,
)
from hri_teleop.hardware.sim.hand import HandSim
from hri_teleop.hardware.sim.hand_params import (
    COMMAND_ABORTED,
    COMMAND_FAILED,
    GRAVITY_M_PER_S2,
    MAX_FORCE_N,
    MAX_SPEED_M_PER_S,
    HandParams,
    HandSimError,
)

DT = 0.001  # the simulation node steps at 1 kHz
TRAVEL = Attachment().piston_travel_m
FULL_FORCE = Attachment().full_travel_force_n
SETTINGS = settings(max_examples=80, deadline=None)


def advance(hand: HandSim, seconds: float, vz: float = 0.0, az=None, on_step=None) -> None:
    """Step ``hand`` at 1 kHz for ``seconds`` (times computed from the start: no drift)."""
    start = hand.now_s
    for k in range(1, round(seconds / DT) + 1):
        hand.step(start + k * DT, vz, az)
        if on_step is not None:
            on_step(hand)


def until_done(hand: HandSim, record, limit_s: float = 5.0, vz: float = 0.0) -> None:
    start = hand.now_s
    k = 0
    while not record.done:
        k += 1
        assert k * DT <= limit_s, f"{record.action} goal still {record.status.name} after {limit_s} s: {record}"
        hand.step(start + k * DT, vz)


def hand_with(name: str, **params) -> HandSim:
    hand = HandSim(HandParams(**params)) if params else HandSim()
    hand.place_object(OBJECTS[name])
    return hand


# --------------------------------------------------------------------------- numbers


def test_hand_limits_are_the_franka_hands():
    params = HandParams()
    assert params.max_width_m == GRIPPER_MAX_WIDTH_M == 0.08
    assert params.max_speed_m_per_s == MAX_SPEED_M_PER_S == 0.1
    assert params.max_force_n == params.move_force_n == MAX_FORCE_N == 70.0
    assert HandSim().width_m == 0.08  # starts open, as after homing


def test_full_piston_travel_reads_about_700_counts():
    # Handout Ex. 11: the count "when the piston is pressed in level with the housing" (~700 in the lab).
    attachment = Attachment()
    assert abs(attachment.full_travel_count - 700) <= 20
    assert attachment.full_travel_count == int(fsr.force_to_count(attachment.full_travel_force_n))
    assert attachment.full_travel_force_n == pytest.approx(float(fsr.count_to_force(700)), rel=0.03)


def test_spring_saturates_at_full_travel():
    attachment = Attachment()
    assert attachment.spring_force_n(0.0) == 0.0
    assert attachment.spring_force_n(TRAVEL / 2) == pytest.approx(FULL_FORCE / 2)
    assert attachment.spring_force_n(TRAVEL) == pytest.approx(FULL_FORCE)
    assert attachment.spring_force_n(10 * TRAVEL) == pytest.approx(FULL_FORCE)


@given(st.floats(min_value=0.0, max_value=300.0, allow_nan=False))
@settings(max_examples=300, deadline=None)
def test_count_is_exactly_hri_teleop_fsr(force_n):
    assert Attachment().count(force_n) == int(fsr.force_to_count(force_n))


def test_count_is_exact_at_and_next_to_every_adc_threshold():
    attachment = Attachment()
    thresholds = fsr.count_to_force(np.arange(1024))
    for threshold in thresholds[1:]:
        for force in (float(threshold), np.nextafter(threshold, 0.0), np.nextafter(threshold, np.inf)):
            assert attachment.count(float(force)) == int(fsr.force_to_count(float(force))), force
    for force in (0.0, -1.0, float("nan"), float("inf"), 1e6):
        assert attachment.count(force) == int(fsr.force_to_count(force)), force


def test_other_wiring_goes_through_fsr_too():
    attachment = Attachment(pulldown_ohm=3.3e3, supply_v=3.3, adc_bits=12)
    for force in (0.05, 0.7, 1.77, 9.0):
        assert attachment.count(force) == int(fsr.force_to_count(force, pulldown_ohm=3.3e3, supply_v=3.3, adc_bits=12))


def test_the_object_set_is_realistic():
    for name in ("block", "sponge", "egg"):
        assert name in OBJECTS
    egg, block, sponge = OBJECTS["egg"], OBJECTS["block"], OBJECTS["sponge"]
    assert 25.0 <= egg.breaking_force_n <= 35.0
    assert 0.04 <= egg.mass_kg <= 0.075 and 0.04 <= egg.width_m <= 0.05
    assert block.breaking_force_n is None and sponge.breaking_force_n is None
    assert sponge.stiffness_n_per_m < 1e4 < egg.stiffness_n_per_m < block.stiffness_n_per_m
    for obj in OBJECTS.values():
        assert 0.005 <= obj.mass_kg <= 0.5 and obj.width_m + TRAVEL <= GRIPPER_MAX_WIDTH_M, obj
    # A careful grip (inside the piston's travel) lifts the egg; the heavy block needs more.
    assert egg.min_grip_force_n() < FULL_FORCE < OBJECTS["heavy_block"].min_grip_force_n()


# --------------------------------------------------------------------------- contact and forces


@pytest.mark.parametrize("name", sorted(OBJECTS))
def test_contact_starts_at_object_width_plus_piston_travel(name):
    obj = OBJECTS[name]
    hand = hand_with(name)
    hand.send(MoveCommand(obj.width_m + TRAVEL + 0.002, 0.1), 0.0)
    advance(hand, 1.0)
    assert not hand.in_contact and hand.grip_force_n == 0.0 and hand.fsr_count == 0
    hand.send(MoveCommand(obj.width_m + TRAVEL, 0.001), hand.now_s)
    advance(hand, 2.5)
    assert hand.width_m == pytest.approx(obj.width_m + TRAVEL)
    assert hand.in_contact and hand.grip_force_n == 0.0
    hand.send(MoveCommand(obj.width_m + TRAVEL - 0.0005, 0.001), hand.now_s)
    advance(hand, 1.0)
    assert hand.in_contact and hand.grip_force_n > 0.0 and hand.fsr_count > 0


def test_without_an_object_the_piston_meets_the_other_finger():
    hand = HandSim()
    hand.send(MoveCommand(TRAVEL + 0.0001, 0.1), 0.0)
    advance(hand, 1.0)
    assert hand.spring_force_n == 0.0 and not hand.in_contact
    hand.send(MoveCommand(0.0, 0.1), hand.now_s)
    advance(hand, 0.5)
    assert hand.width_m == 0.0
    assert hand.spring_force_n == pytest.approx(FULL_FORCE)
    assert hand.fsr_count == Attachment().full_travel_count


def test_object_and_spring_act_in_series():
    sponge = OBJECTS["sponge"]
    hand = hand_with("sponge")
    squeeze = 0.002
    hand.send(MoveCommand(sponge.width_m + TRAVEL - squeeze, 0.1), 0.0)
    advance(hand, 1.0)
    series = 1.0 / (1.0 / Attachment().spring_n_per_m + 1.0 / sponge.stiffness_n_per_m)
    assert hand.grip_force_n == pytest.approx(series * squeeze)
    assert hand.spring_force_n == pytest.approx(hand.grip_force_n)
    assert hand.piston_compression_m == pytest.approx(hand.spring_force_n / Attachment().spring_n_per_m)


def test_beyond_full_travel_the_housing_takes_the_force_and_the_fsr_saturates():
    block = OBJECTS["block"]
    hand = hand_with("block")
    hand.send(GraspCommand(block.width_m, 0.05, 40.0), 0.0)
    advance(hand, 1.0)
    assert hand.grip_force_n == pytest.approx(40.0)
    assert hand.spring_force_n == pytest.approx(FULL_FORCE)
    assert hand.piston_compression_m == pytest.approx(TRAVEL)
    assert hand.fsr_count == Attachment().full_travel_count


def test_fsr_count_follows_the_spring_through_hri_teleop_fsr_at_every_step():
    hand = hand_with("sponge")
    hand.send(MoveCommand(0.0, 0.01), 0.0)
    seen = set()

    def check(h: HandSim) -> None:
        assert h.fsr_count == int(fsr.force_to_count(h.spring_force_n))
        seen.add(h.fsr_count)

    advance(hand, 3.5, on_step=check)  # contact at 2.7 s, piston level with the housing 0.42 s later
    assert len(seen) > 100 and max(seen) == Attachment().full_travel_count  # it swept through the range


# --------------------------------------------------------------------------- lift and slip


def test_is_held_is_two_faces_of_coulomb_friction():
    egg = OBJECTS["egg"]
    need = egg.mass_kg * GRAVITY_M_PER_S2 / (2 * egg.friction_coefficient)
    assert egg.min_grip_force_n() == pytest.approx(need)
    assert holding_force_n(need, egg.friction_coefficient) == pytest.approx(egg.mass_kg * GRAVITY_M_PER_S2)
    assert is_held(need * 1.001, egg) and not is_held(need * 0.999, egg)
    assert not is_held(need * 1.2, egg, hand_accel_up_m_per_s2=5.0)  # accelerating up needs more
    assert is_held(0.0, egg, hand_accel_up_m_per_s2=-GRAVITY_M_PER_S2)  # free fall needs nothing


def test_squeezed_enough_the_object_lifts_with_the_hand():
    hand = hand_with("egg")
    record = hand.send(GraspCommand(0.044, 0.05, 5.0), 0.0)
    until_done(hand, record)
    assert record.success
    moved = []
    advance(hand, 1.0, vz=0.05, on_step=lambda h: moved.append(h.object_moves_with_hand))
    assert hand.object_height_m == pytest.approx(0.05, abs=0.001)
    assert sum(moved) >= 990  # a few ms of slip while the egg is accelerated off the table
    assert not hand.object_crushed and hand.fsr_count == Attachment().full_travel_count


def test_careful_grip_inside_the_piston_travel_lifts_the_egg():
    egg = OBJECTS["egg"]
    hand = hand_with("egg")
    # The piston pushed in by 2.5 mm: 1.5 N, above the 0.84 N the egg needs, below full travel.
    hand.send(MoveCommand(egg.width_m + TRAVEL - 0.0025, 0.05), 0.0)
    advance(hand, 1.0)
    assert egg.min_grip_force_n() < hand.grip_force_n < FULL_FORCE
    assert hand.fsr_count < Attachment().full_travel_count
    advance(hand, 1.0, vz=0.05)
    assert hand.object_height_m == pytest.approx(0.05, abs=0.001)


def test_squeezed_too_little_the_object_slips_and_stays_on_the_table():
    egg = OBJECTS["egg"]
    hand = hand_with("egg")
    hand.send(MoveCommand(egg.width_m + TRAVEL - 0.001, 0.05), 0.0)  # 0.6 N < 0.84 N
    advance(hand, 1.0)
    assert 0.0 < hand.grip_force_n < egg.min_grip_force_n()
    moved = []
    advance(hand, 0.01, vz=0.05, on_step=lambda h: moved.append(h.object_moves_with_hand))
    assert hand.object_height_m == 0.0 and not any(moved)
    advance(hand, 0.5, vz=0.05)
    assert hand.object_height_m == 0.0
    # It slid out of the fingers: the fingers no longer touch it.
    assert hand.finger_offset_m > HandParams().grip_zone_m
    assert hand.grip_force_n == 0.0 and hand.fsr_count == 0


def test_a_hard_upward_jerk_makes_a_lightly_held_object_slip():
    block = OBJECTS["block"]
    hand = hand_with("block")
    force = 1.2 * block.min_grip_force_n()  # holds at rest, not at 5 m/s^2 up (needs 1.51x)
    record = hand.send(GraspCommand(block.width_m, 0.05, force), 0.0)
    until_done(hand, record)
    advance(hand, 0.5, vz=0.02)  # gentle lift: held
    height = hand.object_height_m
    assert height == pytest.approx(0.01, abs=5e-4)
    start = hand.now_s
    for k in range(1, 101):  # 0.1 s at +5 m/s^2
        vz = 0.02 + 5.0 * k * DT
        hand.step(start + k * DT, vz, 5.0)
        assert not hand.object_moves_with_hand
    assert hand.finger_offset_m > 0.001  # the hand went up more than the block


def test_an_object_let_go_in_the_air_falls_back_to_the_table():
    hand = hand_with("block")
    record = hand.send(GraspCommand(0.05, 0.05, 10.0), 0.0)
    until_done(hand, record)
    advance(hand, 1.0, vz=0.05)
    assert hand.object_height_m == pytest.approx(0.05, abs=0.001)
    hand.send(StopCommand(), hand.now_s)
    advance(hand, 0.5)
    assert hand.object_height_m == 0.0
    assert hand.grip_force_n == 0.0


def test_the_table_carries_an_unheld_object_when_the_hand_moves_down():
    hand = hand_with("sponge")
    hand.place_object(OBJECTS["sponge"], finger_offset_m=0.1)  # fingers 10 cm above it
    advance(hand, 1.0, vz=-0.1)  # approach
    assert hand.object_height_m == 0.0
    assert hand.finger_offset_m == pytest.approx(0.0, abs=1e-9)
    record = hand.send(GraspCommand(0.05, 0.1, 2.0), hand.now_s)
    until_done(hand, record)
    assert record.success


def test_closed_fingers_coming_back_down_do_not_take_the_object_in():
    # Found by the property test below: the hand rose without the block, closed, and came
    # back down over it.  That is a collision, not a grasp: no force, and nothing inside.
    block = OBJECTS["block"]
    hand = hand_with("block")
    hand.send(MoveCommand(0.0, 0.1), 0.0)
    advance(hand, 0.3, vz=0.1)  # 3 cm up: out of the 2 cm grip zone before the fingers reach it
    assert hand.finger_offset_m > HandParams().grip_zone_m and hand.width_m < block.width_m
    advance(hand, 0.6, vz=-0.1)  # back down through the grasp height
    assert hand.grip_force_n <= FULL_FORCE and not hand.in_contact
    hand.send(MoveCommand(0.08, 0.1), hand.now_s)
    advance(hand, 0.8)  # open (3 cm below the grasp height) ...
    advance(hand, 0.3, vz=0.1)  # ... and back up to it
    assert hand.finger_offset_m == pytest.approx(0.0, abs=1e-9) and hand.width_m == 0.08
    record = hand.send(GraspCommand(block.width_m, 0.1, 10.0), hand.now_s)
    until_done(hand, record)
    assert record.success and hand.in_contact


# --------------------------------------------------------------------------- crushing


@given(st.floats(min_value=0.0, max_value=29.9), st.floats(min_value=30.1, max_value=70.0))
@SETTINGS
def test_the_egg_is_crushed_above_its_breaking_force_and_not_below(gentle_n, firm_n):
    egg = OBJECTS["egg"]
    assert egg.breaking_force_n == 30.0
    gentle = hand_with("egg")
    record = gentle.send(GraspCommand(egg.width_m, 0.1, gentle_n, 0.01, 0.01), 0.0)
    until_done(gentle, record)
    advance(gentle, 0.2)
    assert not gentle.object_crushed
    assert gentle.grip_force_n == pytest.approx(gentle_n, abs=1e-6)
    firm = hand_with("egg")
    record = firm.send(GraspCommand(egg.width_m, 0.1, firm_n, 0.01, 0.01), 0.0)
    until_done(firm, record)
    assert firm.object_crushed and firm.object_crushed_s is not None
    assert firm.grip_force_n < egg.breaking_force_n


def test_crushed_egg_collapses_and_cannot_be_lifted():
    egg = OBJECTS["egg"]
    hand = hand_with("egg")
    hand.send(MoveCommand(0.02, 0.05), 0.0)  # a heavy squeeze: move presses with up to 70 N
    advance(hand, 1.5)
    assert hand.object_crushed
    assert hand.width_m == pytest.approx(0.02)  # nothing resists any more
    assert hand.grip_force_n == 0.0 and hand.fsr_count == 0
    advance(hand, 0.5, vz=0.05)
    assert hand.object_height_m == 0.0
    assert egg.width_m == 0.044  # the predefined object itself is untouched
    with pytest.raises(HandSimError, match="open them first"):
        hand.place_object(egg)  # a fresh egg does not fit between fingers 2 cm apart
    hand.send(MoveCommand(0.08), hand.now_s)
    advance(hand, 1.0)
    hand.place_object(egg)
    assert not hand.object_crushed and hand.grip_force_n == 0.0


def test_unbreakable_objects_never_crush():
    for name in ("block", "sponge", "heavy_block"):
        hand = hand_with(name)
        hand.send(MoveCommand(0.0, 0.1), 0.0)
        advance(hand, 1.0)
        assert not hand.object_crushed
        assert hand.grip_force_n <= MAX_FORCE_N + 1e-9


# --------------------------------------------------------------------------- move


def test_move_reaches_its_width_at_its_speed_and_holds_it():
    hand = HandSim()
    record = hand.send(MoveCommand(0.05, 0.05), 0.0)
    assert record.status == GoalStatus.ACTIVE and record.action == "move"
    until_done(hand, record)
    assert record.status == GoalStatus.SUCCEEDED and record.success and record.error == ""
    assert record.finished_s == pytest.approx(0.03 / 0.05, abs=2 * DT)
    assert hand.width_m == 0.05
    assert hand.joint_positions_m == (0.025, 0.025)
    advance(hand, 0.5)
    assert hand.width_m == 0.05
    assert hand.pop_finished() == [record]


def test_move_faster_than_the_hand_is_clipped():
    hand = HandSim()
    record = hand.send(MoveCommand(0.0, 1.0), 0.0)
    until_done(hand, record)
    assert record.success and "clipped" in record.detail
    assert record.finished_s == pytest.approx(0.08 / MAX_SPEED_M_PER_S, abs=2 * DT)


@pytest.mark.parametrize("command", [
    MoveCommand(0.09, 0.1), MoveCommand(-0.01, 0.1), MoveCommand(0.04, 0.0), MoveCommand(0.04, -0.1),
    MoveCommand(float("nan"), 0.1), GraspCommand(0.04, 0.1, -1.0), GraspCommand(0.04, 0.1, 10.0, -0.001),
    GraspCommand(0.1, 0.1, 10.0),
])
def test_impossible_goals_fail_at_once_and_leave_the_running_goal_alone(command):
    hand = HandSim()
    running = hand.send(MoveCommand(0.02, 0.05), 0.0)
    advance(hand, 0.1)
    bad = hand.send(command, hand.now_s)
    assert bad.status == GoalStatus.ABORTED and not bad.success
    assert bad.error == COMMAND_FAILED and bad.detail
    assert running.status == GoalStatus.ACTIVE
    until_done(hand, running)
    assert running.success


def test_move_blocked_by_an_object_presses_with_the_motor_force_then_fails():
    hand = hand_with("block", move_stall_timeout_s=0.5)
    record = hand.send(MoveCommand(0.01, 0.1), 0.0)
    advance(hand, 0.6)  # 0.3 s until the housing is on the block (0.05 m), then stalled
    assert record.status == GoalStatus.ACTIVE
    assert hand.width_m == pytest.approx(0.05, abs=1e-4)  # the housing on the block
    assert hand.grip_force_n == pytest.approx(MAX_FORCE_N)
    until_done(hand, record)
    assert record.status == GoalStatus.ABORTED and record.error == COMMAND_FAILED
    assert record.finished_s == pytest.approx((0.08 - 0.05) / 0.1 + 0.5, abs=0.005)
    advance(hand, 0.2)
    assert hand.width_m == pytest.approx(0.05, abs=1e-4)  # it holds where it stalled


def test_move_blocked_within_its_tolerance_succeeds():
    hand = hand_with("block")
    record = hand.send(MoveCommand(0.0495, 0.1), 0.0)  # the block stops it at 0.04999 m
    until_done(hand, record)
    assert record.success


def test_the_default_stall_timeout_is_the_real_hands():
    assert HandParams().move_stall_timeout_s == 100.0


# --------------------------------------------------------------------------- grasp


def test_grasp_succeeds_inside_epsilon_and_keeps_the_force():
    hand = hand_with("block")
    record = hand.send(GraspCommand(0.05, 0.1, 30.0, 0.005, 0.005), 0.0)
    until_done(hand, record)
    assert record.status == GoalStatus.SUCCEEDED and record.success
    assert record.grasp_width_m == pytest.approx(0.05, abs=1e-4)
    assert hand.is_grasped
    advance(hand, 1.0)
    assert hand.grip_force_n == pytest.approx(30.0)
    assert hand.active_goal is None and hand.is_grasped


@pytest.mark.parametrize("width_m, inner, outer, success", [
    (0.052, 0.005, 0.005, True),
    (0.048, 0.005, 0.005, True),
    (0.058, 0.005, 0.005, False),  # the block is 8 mm smaller than asked, inner epsilon 5 mm
    (0.058, 0.010, 0.005, True),
    (0.042, 0.005, 0.005, False),  # 8 mm larger, outer epsilon 5 mm
    (0.042, 0.005, 0.010, True),
    (0.05, 0.0, 0.0, False),  # strict inequalities: a zero window never holds
])
def test_grasp_epsilon_window(width_m, inner, outer, success):
    hand = hand_with("block")
    hand.send(MoveCommand(0.07, 0.1), 0.0)
    advance(hand, 0.2)
    record = hand.send(GraspCommand(width_m, 0.1, 20.0, inner, outer), hand.now_s)
    until_done(hand, record)
    d = record.grasp_width_m
    assert d == pytest.approx(0.05, abs=1e-4)
    assert record.success is success
    assert (width_m - inner < d < width_m + outer) is success
    # franka_gripper_node: an unsuccessful grasp still ends SUCCEEDED, with success False.
    assert record.status == GoalStatus.SUCCEEDED
    if not success:
        assert "nothing grasped" in record.detail
        advance(hand, 0.1)
        assert hand.grip_force_n == 0.0 and not hand.is_grasped  # it let go


def test_grasp_on_nothing_closes_fully_and_fails():
    hand = HandSim()
    record = hand.send(GraspCommand(0.03, 0.1, 20.0), 0.0)
    until_done(hand, record)
    assert not record.success and record.grasp_width_m == 0.0


def test_grasp_force_above_the_hand_is_clipped_to_70_n():
    hand = hand_with("block")
    record = hand.send(GraspCommand(0.05, 0.5, 140.0), 0.0)
    until_done(hand, record)
    assert record.success and "force 140.0 N clipped" in record.detail and "speed 0.5 m/s clipped" in record.detail
    assert hand.grip_force_n == pytest.approx(MAX_FORCE_N)


def test_sponge_is_squeezed_to_where_its_force_equals_the_grasp_force():
    sponge = OBJECTS["sponge"]
    hand = hand_with("sponge")
    record = hand.send(GraspCommand(0.04, 0.05, 10.0, 0.02, 0.02), 0.0)
    until_done(hand, record)
    expected = sponge.width_m - 10.0 / sponge.stiffness_n_per_m  # piston bottomed out at 1.77 N
    assert record.grasp_width_m == pytest.approx(expected)
    assert record.success


# --------------------------------------------------------------------------- homing, stop, preemption


def test_homing_closes_then_opens_fully():
    hand = HandSim(HandParams(initial_width_m=0.03))
    record = hand.send(HomingCommand(), 0.0)
    widths = []
    start = hand.now_s
    k = 0
    while not record.done:
        k += 1
        hand.step(start + k * DT)
        widths.append(hand.width_m)
    assert min(widths) == 0.0
    assert record.success and hand.width_m == 0.08


def test_homing_with_an_egg_in_the_way_touches_it_without_crushing():
    hand = hand_with("egg")
    record = hand.send(HomingCommand(), 0.0)
    until_done(hand, record, limit_s=10.0)
    assert record.success and not hand.object_crushed and hand.width_m == 0.08


def test_stop_aborts_the_running_goal_and_releases_the_grip():
    hand = hand_with("block")
    grasp = hand.send(GraspCommand(0.05, 0.1, 30.0), 0.0)
    until_done(hand, grasp)
    hand.pop_finished()
    assert hand.grip_force_n == pytest.approx(30.0)
    moving = hand.send(MoveCommand(0.0, 0.1), hand.now_s)  # presses on: blocked
    advance(hand, 0.1)
    stop = hand.send(StopCommand(), hand.now_s)
    assert stop.status == GoalStatus.SUCCEEDED and stop.success and stop.action == "stop"
    assert moving.status == GoalStatus.ABORTED and moving.error == COMMAND_ABORTED
    assert hand.pop_finished() == [moving, stop]
    advance(hand, 0.1)
    assert hand.grip_force_n == 0.0  # the fingers were pushed back to contact
    assert hand.width_m == pytest.approx(0.05 + TRAVEL)


def test_stop_with_nothing_running_succeeds():
    hand = HandSim()
    assert hand.send(StopCommand(), 0.0).success


def test_a_newer_goal_preempts_the_running_one():
    hand = HandSim()
    first = hand.send(MoveCommand(0.0, 0.05), 0.0)
    advance(hand, 0.2)
    second = hand.send(GraspCommand(0.0, 0.05, 10.0), hand.now_s)
    assert first.status == GoalStatus.PREEMPTED and not first.success and "goal 2" in first.detail
    third = hand.send(MoveCommand(0.08, 0.1), hand.now_s)
    assert second.status == GoalStatus.PREEMPTED
    until_done(hand, third)
    assert third.success and hand.width_m == 0.08
    assert [r.goal_id for r in hand.pop_finished()] == [1, 2, 3]
    assert hand.pop_finished() == []


def test_cancel_preempts_and_the_fingers_hold_where_they_are():
    hand = HandSim()
    record = hand.send(MoveCommand(0.0, 0.1), 0.0)
    advance(hand, 0.2)
    width = hand.width_m
    hand.cancel(record, hand.now_s)
    assert record.status == GoalStatus.PREEMPTED
    advance(hand, 0.2)
    assert hand.width_m == width == pytest.approx(0.06)


# --------------------------------------------------------------------------- limits at every step (property)

widths = st.floats(min_value=-0.01, max_value=0.09, allow_nan=False)
speeds = st.floats(min_value=-0.05, max_value=0.3, allow_nan=False)
forces = st.floats(min_value=-5.0, max_value=100.0, allow_nan=False)
epsilons = st.floats(min_value=0.0, max_value=0.02)
commands = st.one_of(
    st.builds(MoveCommand, widths, speeds),
    st.builds(GraspCommand, widths, speeds, forces, epsilons, epsilons),
    st.just(HomingCommand()),
    st.just(StopCommand()),
)
timeline = st.lists(st.tuples(st.integers(min_value=1, max_value=400), commands), min_size=1, max_size=8)


@given(st.sampled_from([None] + sorted(OBJECTS)), timeline,
       st.floats(min_value=-0.1, max_value=0.1), st.sampled_from([0.001, 0.004]))
@SETTINGS
def test_width_speed_and_force_limits_hold_at_every_step(object_name, plan, vz, dt):
    hand = HandSim()
    if object_name is not None:
        hand.place_object(OBJECTS[object_name])
    records = []
    t = 0.0
    full_count = hand.attachment.full_travel_count
    for steps, command in plan:
        records.append(hand.send(command, t))
        speed = command.speed_m_per_s if isinstance(command, (MoveCommand, GraspCommand)) else None
        for _ in range(steps):
            w = hand.width_m
            t += dt
            hand.step(t, vz)
            change = abs(hand.width_m - w)
            assert 0.0 <= hand.width_m <= GRIPPER_MAX_WIDTH_M
            assert change <= MAX_SPEED_M_PER_S * dt * (1 + 1e-9) + 1e-15
            assert hand.grip_force_n <= MAX_FORCE_N * (1 + 1e-9)
            assert 0.0 <= hand.spring_force_n <= FULL_FORCE * (1 + 1e-12)
            assert 0 <= hand.fsr_count <= full_count
            assert hand.joint_positions_m == (hand.width_m / 2, hand.width_m / 2)
            if object_name is None and speed is not None and speed > 0 and hand.active_goal is records[-1]:
                assert change <= speed * dt * (1 + 1e-9) + 1e-15  # nothing pushes: the commanded speed
        vz = -vz  # up and down
    for record in records:
        assert record.status in tuple(GoalStatus)
        if record.done:
            assert record.finished_s is not None and record.finished_s >= record.accepted_s
    finished = hand.pop_finished()
    assert len({id(r) for r in finished}) == len(finished) == sum(r.done for r in records)
    assert sum(not r.done for r in records) <= 1  # at most one goal runs


# --------------------------------------------------------------------------- errors, purity, speed


def test_time_must_not_run_backwards():
    hand = HandSim()
    hand.step(1.0)
    with pytest.raises(HandSimError, match="backwards"):
        hand.step(0.5)
    with pytest.raises(HandSimError, match="backwards"):
        hand.send(MoveCommand(0.04), 0.9)
    with pytest.raises(HandSimError, match="finite"):
        hand.step(float("nan"))
    with pytest.raises(HandSimError, match="hand_vz_m_per_s"):
        hand.step(2.0, float("inf"))
    with pytest.raises(HandSimError, match="hand_az_m_per_s2"):
        hand.step(2.0, 0.0, "up")
    assert hand.now_s == 1.0  # a refused step changes nothing
    hand.step(1.0)  # the same time again is a no-op


@pytest.mark.parametrize("make, match", [
    (lambda: HandParams(max_speed_m_per_s=0.0), "max_speed_m_per_s"),
    (lambda: HandParams(initial_width_m=0.1), "initial_width_m"),
    (lambda: HandParams(move_force_n=100.0), "move_force_n"),
    (lambda: GraspObject("x", width_m=0.04, stiffness_n_per_m=0.0, mass_kg=0.1, friction_coefficient=0.4),
     "stiffness_n_per_m"),
    (lambda: GraspObject("x", width_m=0.04, stiffness_n_per_m=1e3, mass_kg=0.1, friction_coefficient=0.4,
                         breaking_force_n=-1.0), "breaking_force_n"),
    (lambda: MoveCommand("0.04"), "width_m"),
    (lambda: GraspCommand(0.04, force_n=True), "force_n"),
    (lambda: HandSim().send("open", 0.0), "MoveCommand"),
    (lambda: HandSim().place_object("egg"), "GraspObject"),
])
def test_bad_settings_raise_one_error_class_that_names_the_field(make, match):
    with pytest.raises(HandSimError, match=match):
        make()


def test_a_bad_attachment_setting_names_the_field():
    with pytest.raises(AttachmentError, match="piston_travel_m"):
        Attachment(piston_travel_m=-0.001)


@pytest.mark.parametrize("module", [hand_module, hand_params, grasp_objects, gripper_goals, attachment])
def test_the_hand_model_is_pure(module):
    tree = ast.parse(Path(module.__file__).read_text())
    imported = {alias.name.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.Import)
                for alias in node.names}
    imported |= {node.module.split(".")[0] for node in ast.walk(tree)
                 if isinstance(node, ast.ImportFrom) and node.module}
    assert not imported & {"rospy", "time", "datetime", "os", "io", "random", "threading"}, imported


def test_same_inputs_same_outputs():
    def run():
        hand = hand_with("egg")
        hand.send(GraspCommand(0.044, 0.05, 8.0), 0.0)
        out = []
        advance(hand, 1.5, vz=0.03, on_step=lambda h: out.append((h.width_m, h.grip_force_n, h.object_height_m)))
        return out

    assert run() == run()


def test_one_second_at_1_khz_takes_less_than_20_ms():
    def one_second() -> float:
        hand = hand_with("sponge")
        hand.send(MoveCommand(0.0, 0.1), 0.0)
        begin = time.perf_counter()
        for k in range(1, 1001):
            hand.step(k * DT, 0.01)
            _ = hand.fsr_count, hand.joint_positions_m
        return time.perf_counter() - begin

    best = min(one_second() for _ in range(5))
    assert best < 0.020, f"1000 steps took {best * 1e3:.1f} ms"
    assert math.isfinite(best)


# --------------------------------------------------------------------------- the lab's loop


def operate(tap: bool, stop_at_count: int, seconds: float = 8.0) -> HandSim:
    """The lab's chain on an egg: cross closes by k_gripper/rate = 0.8 mm per 50 Hz tick,
    gripper_manager's GoalThrottle turns targets into move goals, the operator lets go of
    the button once the FSR count (the rumble) reaches ``stop_at_count``, then lifts."""
    hand = HandSim(HandParams(initial_width_m=0.052))  # already closed near the egg
    hand.place_object(OBJECTS["egg"])
    throttle = GoalThrottle()
    target, pressing = 0.052, True
    for ms in range(1, round(seconds * 1000) + 1):
        now = ms * DT
        if ms % 20 == 0:
            tick = ms // 20
            if pressing and hand.fsr_count >= stop_at_count:
                pressing = False
            if pressing and (not tap or tick % 15 == 0):  # tapping: one tick every 0.3 s
                target = max(0.0, target - 0.0008)
            if throttle.should_send(target, now):
                throttle.sent(target, now)
                hand.send(MoveCommand(target, 0.1), now)
        hand.step(now)
    advance(hand, 1.0, vz=0.05)
    return hand


def test_lab_loop_tapping_until_the_rumble_is_strong_lifts_the_egg():
    hand = operate(tap=True, stop_at_count=600)
    assert not hand.object_crushed
    assert hand.object_height_m == pytest.approx(0.05, abs=0.001)


def test_lab_loop_stopping_at_a_weak_rumble_lets_the_egg_slip():
    hand = operate(tap=True, stop_at_count=400)
    assert not hand.object_crushed and hand.object_height_m == 0.0


def test_lab_loop_holding_the_button_crushes_the_egg():
    # Goals go out at most 5 per second, so a held button moves the target 8 mm per goal:
    # far more than the piston's 3 mm, and the housing then crushes the egg.
    hand = operate(tap=False, stop_at_count=600)
    assert hand.object_crushed and hand.object_height_m == 0.0
