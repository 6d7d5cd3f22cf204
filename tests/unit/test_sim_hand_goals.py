"""The simulated Franka Hand (hri_teleop.sim.hand): its goals, limits and errors."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest
from hand_helpers import DT, FULL_FORCE, SETTINGS, TRAVEL, advance, hand_with, until_done
from hypothesis import given
from hypothesis import strategies as st

from hri_teleop.core import attachment
from hri_teleop.core.attachment import Attachment, AttachmentError
from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M
from hri_teleop.sim import grasp_objects, gripper_goals, hand_params
from hri_teleop.sim import hand as hand_module
from hri_teleop.sim.grasp_objects import OBJECTS, GraspObject
from hri_teleop.sim.gripper_goals import (
    GoalStatus,
    GraspCommand,
    HomingCommand,
    MoveCommand,
    StopCommand,
)
from hri_teleop.sim.hand import HandSim
from hri_teleop.sim.hand_params import (
    COMMAND_ABORTED,
    COMMAND_FAILED,
    MAX_FORCE_N,
    MAX_SPEED_M_PER_S,
    HandParams,
    HandSimError,
)

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


def test_one_second_at_1_khz_is_1000_steps_that_close_the_fingers_on_the_sponge():
    """The work of one simulated second (its CPU cost: make bench, "gripper hand per 1 kHz cycle")."""
    hand = hand_with("sponge")
    hand.send(MoveCommand(0.0, 0.1), 0.0)
    widths = []
    for k in range(1, 1001):
        hand.step(k * DT, 0.01)
        _ = hand.fsr_count, hand.joint_positions_m
        widths.append(hand.width_m)
    assert hand.now_s == pytest.approx(1.0, abs=1e-12)
    assert len(widths) == 1000 and all(b <= a for a, b in zip(widths, widths[1:])) and widths[-1] < widths[0]
    assert all(math.isfinite(w) for w in widths)
