"""The lab's hardware in one simulated world: arm, hand, object, FSR attachment, sensor board.

At home the arm and the hand share one physics: the object lifts only if the arm moves up while
the hand grips it hard enough, and the board's count comes from the hand's piston. So
:class:`LabWorld` steps them together at 1 kHz and keeps the horizontal geometry. Pure: no rospy,
no clock; ``lab_sim.py`` and :mod:`hri_teleop.sim.lab` pass the time. The geometry:
docs/simulation.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import List, Optional, Sequence, Tuple

from hri_teleop.core.attachment import Attachment
from hri_teleop.core.checks import is_finite_number
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.limits import ROBOT_PERIOD_S, AxisLimits, CartesianLimits
from hri_teleop.core.robot import LAB_ROBOT, RobotProfile
from hri_teleop.core.run_record import LIFTED_M
from hri_teleop.sim.arm import SimArm, SimArmConfig
from hri_teleop.sim.arm_config import ArmModel
from hri_teleop.sim.board import BoardConfig, SensorBoard
from hri_teleop.sim.grasp_objects import GraspObject, is_held
from hri_teleop.sim.gripper_goals import Command, GoalRecord
from hri_teleop.sim.hand import HandSim
from hri_teleop.sim.hand_params import HandParams

__all__ = ["WorldError", "WorldConfig", "ObjectStatus", "LabWorld", "LAB_ARM_CONFIG", "robot_arm", "robot_hand",
           "ROBOT_HAND_KEYS"]

#: The arm as the lab world uses it: SimArm's defaults, with the workspace box where the Panda
#: holds the hand down comfortably (x 0.3..0.55 m, y +-0.25 m, up to 0.55 m; beyond it the arm
#: stretches toward a singular pose and its joints, not the operator, set the pace: docs/simulation.md)
#: and its floor 15 mm above the table so that the fingers reach an object lying on it, and a
#: command timeout of 0.3 s (15 missed messages at 50 Hz) instead of 0.1 s: on a student's busy
#: laptop a Python node can stall for a tenth of a second, and a stall must not look like a dead
#: node (the ramp to zero would then make the next command a step).
#: It starts 40 cm in front of the base (the ready pose's hand is at 31 cm): from there the hand reaches
#: the table with every joint at least 0.35 rad from its limits; below the ready pose joint 4 would
#: come within 0.06 rad of its lower limit and the teleoperation node would warn through the grasp.
LAB_ARM_CONFIG = SimArmConfig(workspace_min_m=(0.3, -0.25, 0.015), workspace_max_m=(0.55, 0.25, 0.55),
                              start_position_m=(0.4, 0.0, 0.4867), timeout_s=0.3)


#: The hand's settings a robot profile gives (sim.yaml sets them only to override the profile).
ROBOT_HAND_KEYS = ("max_width_m", "max_speed_m_per_s", "max_force_n", "move_force_n", "initial_width_m")


def robot_arm(robot: RobotProfile, base: SimArmConfig = LAB_ARM_CONFIG) -> SimArmConfig:
    """``base`` judged with ``robot``'s Cartesian and joint limits; the gentle stop after a timeout
    stays inside them (each of its numbers at most the robot's)."""
    if robot == LAB_ROBOT:
        return base
    stop = base.effective_stop_limits
    hard = robot.cartesian_limits
    gentle = CartesianLimits(*(AxisLimits(*(min(getattr(getattr(stop, g), k), getattr(getattr(hard, g), k))
                                             for k in ("velocity", "acceleration", "jerk")))
                               for g in ("translation", "rotation")))
    return replace(base, limits=hard, joint_limits=robot.joint_limits, stop_limits=gentle, model=ArmModel.of(robot))


def robot_hand(robot: RobotProfile, **settings: float) -> HandParams:
    """The simulated hand with ``robot``'s gripper range (it starts fully open), then ``settings``."""
    grip = robot.gripper
    defaults = dict(zip(ROBOT_HAND_KEYS, (grip.max_width_m, grip.max_speed_m_per_s, grip.max_force_n,
                                          grip.max_force_n, grip.max_width_m)))
    return HandParams(**{**defaults, **settings})


class WorldError(HriTeleopError, ValueError):
    """A world setting or input is unusable (the message names the fix)."""


@dataclass(frozen=True)
class WorldConfig:
    """Everything the simulated lab is made of; ``object`` None: nothing to grasp."""

    arm: SimArmConfig = LAB_ARM_CONFIG
    hand: HandParams = field(default_factory=HandParams)
    attachment: Attachment = field(default_factory=Attachment)
    object: Optional[GraspObject] = None
    object_xy_m: Optional[Tuple[float, float]] = None  # None: right below the start pose
    table_z_m: float = 0.0
    capture_radius_m: float = 0.01
    board: BoardConfig = field(default_factory=BoardConfig)
    robot: RobotProfile = LAB_ROBOT  # what ``arm`` and ``hand`` were made from (robot_world)

    def __post_init__(self) -> None:
        for name, kind in (("arm", SimArmConfig), ("hand", HandParams), ("attachment", Attachment),
                           ("board", BoardConfig), ("robot", RobotProfile)):
            if not isinstance(getattr(self, name), kind):
                raise WorldError(f"WorldConfig.{name} must be a {kind.__name__}, got {type(getattr(self, name)).__name__}")
        if self.object is not None and not isinstance(self.object, GraspObject):
            raise WorldError(f"WorldConfig.object must be a GraspObject or None, got {self.object!r}; "
                             "e.g. hri_teleop.sim.grasp_objects.OBJECTS['egg']")
        if not (is_finite_number(self.capture_radius_m) and self.capture_radius_m > 0):
            raise WorldError(f"capture_radius_m must be a positive distance in m, got {self.capture_radius_m!r}; e.g. 0.01")
        if not is_finite_number(self.table_z_m):
            raise WorldError(f"table_z_m must be a finite height in m, got {self.table_z_m!r}; e.g. 0.0")
        if self.object_xy_m is not None:
            xy = tuple(self.object_xy_m)
            if len(xy) != 2 or not all(is_finite_number(c) for c in xy):
                raise WorldError(f"object_xy_m must be two numbers (x, y) in m, got {self.object_xy_m!r}")
            object.__setattr__(self, "object_xy_m", (float(xy[0]), float(xy[1])))
        if self.table_z_m > self.arm.workspace_min_m[2]:
            raise WorldError(f"the table top ({self.table_z_m} m) is above the workspace floor "
                             f"({self.arm.workspace_min_m[2]} m); raise the floor or lower the table")


@dataclass(frozen=True)
class ObjectStatus:
    """The object as an observer sees it (None fields: there is no object)."""

    name: str
    position_m: Tuple[float, float, float]  # its bottom centre
    height_m: float  # above the table
    between_fingers: bool
    in_contact: bool
    held: bool  # friction carries it with the hand now
    grasped: bool  # squeezed hard enough to be lifted at rest
    lifted: bool  # height above LIFTED_M
    crushed: bool
    grip_force_n: float


class LabWorld:
    """Arm + hand + object + board, stepped together at 1 kHz (the geometry: docs/simulation.md)."""

    def __init__(self, config: Optional[WorldConfig] = None, start_s: float = 0.0) -> None:
        self.config = config if config is not None else WorldConfig()
        if not isinstance(self.config, WorldConfig):
            raise WorldError("LabWorld takes a WorldConfig; build one with WorldConfig(object=OBJECTS['egg'])")
        if not is_finite_number(start_s):
            raise WorldError(f"start_s must be a finite time in seconds, got {start_s!r}")
        cfg = self.config
        self.arm = SimArm(cfg.arm, start_time_s=float(start_s))
        self.hand = HandSim(cfg.hand, cfg.attachment, start_s=float(start_s))
        self.board = SensorBoard(cfg.board, start_s=float(start_s))
        start = cfg.arm.start_position_m
        self._obj_xy: List[float] = list(cfg.object_xy_m if cfg.object_xy_m is not None else start[:2])
        self._peak_grip_n = 0.0
        self._ever_grasped = False
        self._ever_lifted = False
        self._max_height_m = 0.0
        if cfg.object is not None:
            grasp_z = cfg.table_z_m + 0.5 * cfg.object.width_m
            self.hand.set_in_reach(self._in_reach(start))
            self.hand.place_object(cfg.object, finger_offset_m=start[2] - grasp_z, height_m=0.0)

    # -- inputs ---------------------------------------------------------------------

    @property
    def time_s(self) -> float:
        return self.arm.time_s

    def command_twist(self, twist: Sequence[float], now_s: float) -> bool:
        """A velocity command arrives (see :meth:`SimArm.command`); never in the world's past."""
        return self.arm.command(twist, max(float(now_s), self.arm.time_s))

    def send_gripper(self, command: Command, now_s: float) -> GoalRecord:
        """A gripper goal arrives (see :meth:`HandSim.send`); never in the world's past."""
        return self.hand.send(command, max(float(now_s), self.hand.now_s))

    def cancel_gripper(self, record: GoalRecord, now_s: float) -> None:
        self.hand.cancel(record, max(float(now_s), self.hand.now_s))

    # -- time -----------------------------------------------------------------------

    def advance(self, now_s: float) -> List[Tuple[float, int]]:
        """Run every 1 ms cycle up to ``now_s``; returns the board samples (time, count) sent meanwhile."""
        if not is_finite_number(now_s):
            raise WorldError(f"now_s must be a finite time in seconds, got {now_s!r}")
        arm, hand, board = self.arm, self.hand, self.board
        t0 = arm.time_s
        n = int(math.floor((float(now_s) - t0) / ROBOT_PERIOD_S + 1e-6))
        samples: List[Tuple[float, int]] = []
        # the arm reads nothing of the rest: its cycles first (mostly compiled), then the hand along them
        trace: List[float] = []
        arm.run_cycles(n, trace)
        has_object = hand.object is not None
        due_s, slack_s = board.next_sample_s, board.DUE_SLACK_S
        for k in range(1, n + 1):
            t = t0 + k * ROBOT_PERIOD_S
            row = 9 * (k - 1)
            if has_object:
                self._horizontal(trace[row], trace[row + 1], trace[row + 3], trace[row + 4])
            hand.advance(t, trace[row + 5])
            if t + slack_s >= due_s:  # board.due(t), without a call per millisecond
                samples.append((t, board.sample(hand.fsr_count, t)))
                due_s = board.next_sample_s
            self._track()
        return samples

    def _in_reach(self, position: Sequence[float]) -> bool:
        dx = position[0] - self._obj_xy[0]
        dy = position[1] - self._obj_xy[1]
        return dx * dx + dy * dy <= self.config.capture_radius_m ** 2

    def _horizontal(self, x_m: float, y_m: float, vx_m_per_s: float, vy_m_per_s: float) -> None:
        hand = self.hand
        if hand.object_between_fingers and hand.grip_force_n > 0.0:
            # Squeezed: it goes where the hand goes (sideways; up and down is the hand's business).
            self._obj_xy[0] += vx_m_per_s * ROBOT_PERIOD_S
            self._obj_xy[1] += vy_m_per_s * ROBOT_PERIOD_S
        hand.set_in_reach(self._in_reach((x_m, y_m)))

    def _track(self) -> None:
        hand = self.hand
        force = hand.grip_force_n
        if force > self._peak_grip_n:
            self._peak_grip_n = force
        obj = hand.object
        if obj is None:
            return
        if hand.object_crushed and obj.breaking_force_n is not None and obj.breaking_force_n > self._peak_grip_n:
            self._peak_grip_n = obj.breaking_force_n  # it broke under this force, within the step
        if hand.object_between_fingers and is_held(force, obj):
            self._ever_grasped = True
        height = hand.object_height_m
        if height > self._max_height_m:
            self._max_height_m = height
        if height > LIFTED_M:
            self._ever_lifted = True

    # -- read-outs ------------------------------------------------------------------

    @property
    def peak_grip_force_n(self) -> float:
        """The largest force between the fingers so far (N), object or not."""
        return self._peak_grip_n

    @property
    def ever_grasped(self) -> bool:
        """Whether the object was ever squeezed hard enough to be held at rest."""
        return self._ever_grasped

    @property
    def ever_lifted(self) -> bool:
        return self._ever_lifted

    @property
    def max_object_height_m(self) -> float:
        return self._max_height_m

    def object_status(self) -> Optional[ObjectStatus]:
        """Where the object is and what the hand does to it (None without an object)."""
        hand = self.hand
        obj = hand.object
        if obj is None:
            return None
        height = hand.object_height_m
        between = hand.object_between_fingers
        force = hand.grip_force_n if between else 0.0
        return ObjectStatus(
            name=obj.name,
            position_m=(self._obj_xy[0], self._obj_xy[1], self.config.table_z_m + height),
            height_m=height,
            between_fingers=between,
            in_contact=hand.in_contact,
            held=hand.object_moves_with_hand and height > 0.0,
            grasped=between and is_held(force, obj),
            lifted=height > LIFTED_M,
            crushed=hand.object_crushed,
            grip_force_n=force,
        )
