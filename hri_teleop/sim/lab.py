"""The whole teleoperation lab in one process, in lock step, much faster than real time.

:func:`run_lab` wires the same core objects the nodes wrap (world, mapping, controller, gripper
throttle), in the order the messages flow, with no ROS in between: for the grader's reference
traces, property tests with hundreds of random operators, and benchmarks. Deterministic: same
inputs, same record. Which node each part stands for, and what it leaves out: docs/simulation.md.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional, Sequence, Tuple, Union

from hri_teleop.core.config import lab_max_sensor_force
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.gamepad import GamepadError, RumbleRequests
from hri_teleop.core.gripper import GoalThrottle
from hri_teleop.core.joints import JointLimitWatch, JointStateWarning
from hri_teleop.core.limits import DEFAULT_LIMITS, CartesianLimits, Watchdog
from hri_teleop.core.mapping import map_force
from hri_teleop.core.reflex import explain_reflex
from hri_teleop.core.run_record import LIFTED_M, LabRecord
from hri_teleop.core.teleop import TeleopController, TeleopParams, motor_rumble
from hri_teleop.sim.gripper_goals import GoalRecord, MoveCommand
from hri_teleop.sim.virtual_pad import ScriptedPad, ScriptStep, load_script
from hri_teleop.sim.world import LabWorld, WorldConfig

__all__ = ["LabRunError", "ManagerParams", "run_lab"]

#: gripper_manager's timer that lets the settle rule fire when targets stop changing (s).
MANAGER_TIMER_S = 0.05


class LabRunError(HriTeleopError, ValueError):
    """The run cannot start (a setting is unusable); the message names the fix."""


@dataclass(frozen=True)
class ManagerParams:
    """gripper_manager.py's parameters, with its defaults (docs/ros-nodes.md)."""

    speed_m_per_s: float = 0.1
    min_step_m: float = 0.002
    max_goal_rate_hz: float = 5.0
    settle_s: float = 0.2


@dataclass
class _Gripper:
    """gripper_manager's rule: throttle targets, cancel the older goal, send a move."""

    world: LabWorld
    params: ManagerParams
    throttle: GoalThrottle = field(init=False)
    goal: Optional[GoalRecord] = None
    target: Optional[float] = None

    def __post_init__(self) -> None:
        p = self.params
        self.throttle = GoalThrottle(p.min_step_m, p.max_goal_rate_hz, p.settle_s)

    def on_target(self, width_m: float, now_s: float) -> None:
        self.target = width_m
        self.maybe_send(now_s)

    def maybe_send(self, now_s: float) -> None:
        if self.target is None or not self.throttle.should_send(self.target, now_s):
            return
        if self.goal is not None and not self.goal.done:
            self.world.cancel_gripper(self.goal, now_s)
        self.goal = self.world.send_gripper(MoveCommand(self.target, self.params.speed_m_per_s), now_s)
        self.throttle.sent(self.target, now_s)


def run_lab(
    steps: Union[Sequence[ScriptStep], str, Path],
    world: Optional[WorldConfig] = None,
    params: Optional[TeleopParams] = None,
    limits: CartesianLimits = DEFAULT_LIMITS,
    *,
    max_sensor_force: Optional[float] = None,
    manager: ManagerParams = ManagerParams(),
    max_duration_s: float = 120.0,
    record_every_s: float = 0.01,
    progress: Optional[Callable[[float], None]] = None,
) -> LabRecord:
    """Run a scripted operator through the lab until it quits (or ``max_duration_s``).

    ``steps``: a pad script (ScriptStep list or YAML path); its time runs on the
    teleoperation ticks, as in the node.  Returns the :class:`LabRecord`; ``wall_s`` says
    how long it took (the speed-up is ``duration_s() / wall_s``).
    """
    wall0 = time.perf_counter()
    if max_sensor_force is None:  # the lab's calibration (hri_lab/config/calibration.yaml)
        max_sensor_force = float(lab_max_sensor_force())
    params = params if params is not None else TeleopParams()
    if not (max_duration_s > 0 and math.isfinite(max_duration_s)):
        raise LabRunError(f"max_duration_s must be a positive number of seconds, got {max_duration_s!r}")
    if isinstance(steps, (str, Path)):
        steps = load_script(steps)
    world = world if world is not None else WorldConfig()
    controller = TeleopController(params, limits, world.robot.cartesian_limits)
    dt = 1.0 / params.rate_hz
    ticks = [0]
    pad = ScriptedPad(steps, clock=lambda: ticks[0] * dt)
    lab = LabWorld(world, start_s=0.0)
    gripper = _Gripper(lab, manager)
    rumble_requests = RumbleRequests()
    joint_warning = JointStateWarning(JointLimitWatch())  # the node's warning, fed the arm's joints each tick
    watchdog = Watchdog(params.input_timeout_s)
    rec = LabRecord(object_name=lab.hand.object.name if lab.hand.object is not None else "")
    force: Optional[Tuple[float, float]] = None  # (mapped, arrival time)
    stopping = True  # the last tick's: the node's rumble between ticks is silent before its first tick and while stopping
    next_timer = MANAGER_TIMER_S
    next_record = 0.0
    ended_by = "max_duration"
    k = 0
    while True:
        now = k * dt
        if now > max_duration_s + 1e-9:
            break
        # The world up to this tick: board samples -> mapping_node -> the pad's rumble at
        # once, as the node answers a force between its ticks (before this tick's poll).
        for t_sample, count in lab.advance(now):
            value = float(map_force(count, max_sensor_force))
            rec.count.append((t_sample, float(count)))
            rec.mapped.append((t_sample, value))
            force = (value, t_sample)
            between = motor_rumble(controller.rumble_between_ticks(value, 0.0), joint_warning.rumble(t_sample),
                                   stopping, params.feedback, params.rumble_motors)
            request = rumble_requests.update_motors(*between, t_sample)
            if request is not None:
                pad.rumble_motors(*request)
        while next_timer <= now + 1e-9:
            gripper.maybe_send(next_timer if next_timer > lab.time_s else lab.time_s)
            next_timer += MANAGER_TIMER_S
        # teleoperation: one tick.
        try:
            state = pad.poll()
        except GamepadError:
            state = None
        if state is not None and state.connected:
            watchdog.feed(now)
            if watchdog.is_stale(now):
                state = None
        mapped, age = (force[0], now - force[1]) if force is not None else (None, math.inf)
        cmd = controller.step(state, mapped, age, dt)
        stopping = cmd.stopping
        joints = lab.arm.joint_positions
        if joints is not None:
            joint_warning.update(joints, now)
        motors = motor_rumble(cmd.rumble, joint_warning.rumble(now), cmd.stopping, params.feedback,
                              params.rumble_motors)  # as the node: force and warning on their own motors
        rumble = max(motors)
        request = rumble_requests.update_motors(*motors, now)
        if request is not None:
            pad.rumble_motors(*request)
        ticks[0] += 1
        lab.command_twist(cmd.twist, now)
        gripper.on_target(cmd.gripper_width_m, now)
        rec.rumble.append((now, rumble))
        rec.width_target.append((now, cmd.gripper_width_m))
        if now + 1e-9 >= next_record:
            _sample_world(rec, lab, now)
            next_record += record_every_s
        if progress is not None and k % int(round(params.rate_hz)) == 0:
            progress(now)
        if controller.finished:
            ended_by = "quit"
            break
        k += 1
    _sample_world(rec, lab, lab.time_s)
    status = lab.object_status()
    rec.grasped = lab.ever_grasped
    rec.lifted = status is not None and status.height_m > LIFTED_M
    rec.crushed = status is not None and status.crushed
    rec.violations = lab.arm.violation_count
    rec.violation_counts = lab.arm.violation_counts
    if lab.arm.violations:
        rec.reflex_explanation = explain_reflex([v.cause() for v in lab.arm.violations])
    rec.peak_grip_force_n = lab.peak_grip_force_n
    rec.ended_by = ended_by
    rec.wall_s = time.perf_counter() - wall0
    return rec


def _sample_world(rec: LabRecord, lab: LabWorld, now: float) -> None:
    v = lab.arm.velocity
    rec.width.append((now, lab.hand.width_m))
    rec.speed.append((now, math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])))
    rec.grip_force.append((now, lab.hand.grip_force_n))
    rec.object_height.append((now, lab.hand.object_height_m if lab.hand.object is not None else 0.0))
