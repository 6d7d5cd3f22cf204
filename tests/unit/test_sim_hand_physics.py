"""The simulated Franka Hand, object and FSR attachment (hri_teleop.sim.hand): the physics."""

from __future__ import annotations

import numpy as np
import pytest
from hand_helpers import DT, FULL_FORCE, SETTINGS, TRAVEL, advance, hand_with, until_done
from hypothesis import given, settings
from hypothesis import strategies as st

from hri_teleop.core import fsr
from hri_teleop.core.attachment import Attachment
from hri_teleop.core.gripper import GoalThrottle
from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M
from hri_teleop.sim.grasp_objects import OBJECTS, holding_force_n, is_held
from hri_teleop.sim.gripper_goals import (
    GraspCommand,
    MoveCommand,
    StopCommand,
)
from hri_teleop.sim.hand import HandSim
from hri_teleop.sim.hand_params import (
    GRAVITY_M_PER_S2,
    MAX_FORCE_N,
    MAX_SPEED_M_PER_S,
    HandParams,
    HandSimError,
)

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
