"""The simulated lab world: arm and hand share one physics; the board reads the FSR."""

from __future__ import annotations

import pytest

from hri_teleop.core import fsr
from hri_teleop.core.attachment import PISTON_TRAVEL_M
from hri_teleop.core.limits import DEFAULT_LIMITS, TwistLimiter
from hri_teleop.sim.board import BoardConfig
from hri_teleop.sim.grasp_objects import OBJECTS
from hri_teleop.sim.gripper_goals import MoveCommand
from hri_teleop.sim.world import LabWorld, WorldConfig, WorldError

QUIET = BoardConfig(noise_counts=0.0)


class Driver:
    """Sends a limited twist at 50 Hz, as the teleoperation node does, and advances the world."""

    def __init__(self, world: LabWorld) -> None:
        self.world = world
        self.limiter = TwistLimiter(DEFAULT_LIMITS)
        self.t = 0.0
        self.samples = []

    def run(self, target, seconds: float) -> None:
        for _ in range(int(round(seconds * 50))):
            self.world.command_twist(self.limiter.step(target, 0.02), self.t)
            self.t += 0.02
            self.samples += self.world.advance(self.t)

    def gripper(self, width_m: float) -> None:
        self.world.send_gripper(MoveCommand(width_m, 0.1), self.t)

    def down_to_the_table(self) -> None:
        self.run([0, 0, -0.1, 0, 0, 0], 5.5)
        self.run([0] * 6, 0.5)


def _world(name: str = "egg", **kwargs) -> LabWorld:
    return LabWorld(WorldConfig(object=OBJECTS[name] if name else None, board=QUIET, **kwargs))


def test_the_arm_stops_at_the_workspace_floor_above_the_table_with_the_object_between_the_fingers():
    d = Driver(_world())
    d.down_to_the_table()
    assert d.world.arm.position_m[2] == pytest.approx(0.015)
    status = d.world.object_status()
    assert status.between_fingers and not status.in_contact and status.grip_force_n == 0.0
    assert d.world.arm.violation_count == 0


def test_closing_into_the_piston_window_gives_the_count_the_fsr_model_predicts():
    d = Driver(_world())
    d.down_to_the_table()
    contact = OBJECTS["egg"].width_m + PISTON_TRAVEL_M
    d.gripper(contact - 0.0015)
    d.run([0] * 6, 1.0)
    hand = d.world.hand
    assert 0.5 < hand.spring_force_n < 1.77
    expected = int(fsr.force_to_count(hand.spring_force_n))
    assert d.samples[-1][1] == expected == hand.fsr_count
    assert d.world.object_status().grasped and not d.world.object_status().crushed


def test_a_grip_inside_the_window_lifts_the_egg_with_the_arm():
    d = Driver(_world())
    d.down_to_the_table()
    d.gripper(OBJECTS["egg"].width_m + PISTON_TRAVEL_M - 0.002)
    d.run([0] * 6, 0.5)
    z0 = d.world.arm.position_m[2]
    d.run([0, 0, 0.05, 0, 0, 0], 2.0)
    d.run([0] * 6, 1.0)
    lifted = d.world.arm.position_m[2] - z0
    status = d.world.object_status()
    assert lifted > 0.09 and status.height_m == pytest.approx(lifted, abs=1e-3)
    assert status.held and status.lifted and d.world.ever_lifted


def test_a_heavy_block_held_by_the_spring_alone_slips():
    d = Driver(_world("heavy_block"))
    d.down_to_the_table()
    d.gripper(OBJECTS["heavy_block"].width_m + PISTON_TRAVEL_M - 0.002)  # spring only: 1.2 N < 2.8 N
    d.run([0] * 6, 0.5)
    d.run([0, 0, 0.05, 0, 0, 0], 2.0)
    status = d.world.object_status()
    assert status.height_m == 0.0 and not status.lifted and not d.world.ever_lifted
    assert not status.between_fingers  # the fingers went up, the block stayed


def test_squeezing_past_full_travel_crushes_the_egg_and_records_the_breaking_force():
    d = Driver(_world())
    d.down_to_the_table()
    d.gripper(0.03)  # 14 mm inside the egg
    d.run([0] * 6, 1.0)
    status = d.world.object_status()
    assert status.crushed and not status.grasped
    assert d.world.peak_grip_force_n >= 30.0


def test_an_object_beside_the_fingers_is_not_touched():
    x, y, _ = WorldConfig().arm.start_position_m
    d = Driver(_world(object_xy_m=(x + 0.05, y)))
    d.down_to_the_table()
    d.gripper(0.02)
    d.run([0] * 6, 1.0)
    status = d.world.object_status()
    assert not status.between_fingers and status.grip_force_n == 0.0 and d.world.hand.fsr_count == 0


def test_a_held_object_moves_sideways_with_the_hand_and_a_free_one_stays():
    d = Driver(_world())
    d.down_to_the_table()
    d.gripper(OBJECTS["egg"].width_m + PISTON_TRAVEL_M - 0.002)
    d.run([0] * 6, 0.5)
    d.run([0, 0, 0.05, 0, 0, 0], 1.0)
    d.run([0.05, 0, 0, 0, 0, 0], 2.0)
    d.run([0] * 6, 1.0)
    status = d.world.object_status()
    assert status.position_m[0] == pytest.approx(d.world.arm.position_m[0], abs=1e-6)
    assert status.held


def test_the_board_sends_while_the_world_advances():
    d = Driver(_world())
    d.run([0] * 6, 1.0)
    assert 99 <= len(d.samples) <= 101 and {c for _, c in d.samples} == {0}


@pytest.mark.parametrize("kwargs, expected", [
    (dict(capture_radius_m=0), "capture_radius_m must be a positive distance"),
    (dict(object_xy_m=(1.0,)), "object_xy_m must be two numbers"),
    (dict(table_z_m=0.5), "above the workspace floor"),
    (dict(object="egg"), "must be a GraspObject"),
])
def test_bad_world_settings_are_one_line_errors(kwargs, expected):
    with pytest.raises(WorldError) as info:
        WorldConfig(**kwargs)
    assert expected in str(info.value) and "\n" not in str(info.value)
