"""The Franka Hand with the FSR attachment and an object between its fingers, stepped at 1 kHz.

Pure and deterministic (no rospy, no I/O, no clock: the caller passes the time); the model of
the hand, its goals, the attachment and the object, with the source of every number, is in
docs/simulation.md.
"""

from __future__ import annotations

import math
from typing import List, Optional, Tuple

from hri_teleop.core.attachment import Attachment
from hri_teleop.core.checks import is_finite_number
from hri_teleop.sim.grasp_objects import GraspObject, holding_force_n
from hri_teleop.sim.gripper_goals import (
    ACTION_NAMES,
    Command,
    GoalRecord,
    GoalStatus,
    GraspCommand,
    HandState,
    MoveCommand,
    StopCommand,
    add_note,
    goal_problem,
)
from hri_teleop.sim.hand_params import (
    COMMAND_ABORTED,
    COMMAND_FAILED,
    GRAVITY_M_PER_S2,
    HandParams,
    HandSimError,
    checked_param,
)

__all__ = ["HandSim"]

# Vertical relative speeds below this count as sticking (m/s).
_STICK_M_PER_S = 1e-9
# Widths closer than this are equal (m): far below any physical resolution.
_SAME_M = 1e-12

# --------------------------------------------------------------------------- simulation

# What the motor does between and during goals.
_RELEASED = 0  # no force: the fingers stay, unless squeezed (then they are pushed open)
_HOLD = 1  # position hold at _target with force limit _cap (after move, homing, cancel)
_MOVE = 2
_GRASP = 3
_GRASP_HOLD = 4  # keeps pressing towards _target with the grasp force
_HOMING_CLOSE = 5
_HOMING_OPEN = 6


class HandSim:
    """The Franka Hand with the FSR attachment and (optionally) an object between its fingers.

    Use: :meth:`send` goals, :meth:`step` at 1 kHz with the time and the hand's vertical
    velocity, read the width, forces and FSR count, and collect finished goals with
    :meth:`pop_finished`.  All times are the caller's (seconds, never decreasing).
    """

    def __init__(self, params: Optional[HandParams] = None, attachment: Optional[Attachment] = None,
                 start_s: float = 0.0) -> None:
        self.params = params if params is not None else HandParams()
        self.attachment = attachment if attachment is not None else Attachment()
        if not isinstance(self.params, HandParams) or not isinstance(self.attachment, Attachment):
            raise HandSimError("HandSim takes a HandParams and an Attachment; build them with their defaults")
        self._now = checked_param(start_s, "HandSim start_s", "pass the simulation's start time in seconds, e.g. 0.0")
        p, a = self.params, self.attachment
        # Plain floats for the 1 kHz loop.
        self._w_max = p.max_width_m
        self._v_max = p.max_speed_m_per_s
        self._travel = a.piston_travel_m
        self._k_spring = a.spring_n_per_m
        self._f_spring_full = a.full_travel_force_n
        self._w = p.initial_width_m
        self._rate = 0.0
        self._mode = _RELEASED
        self._target = self._w
        self._speed = 0.0
        self._cap = 0.0
        self._active: Optional[GoalRecord] = None
        self._grasp: Optional[GraspCommand] = None
        self._stall_since: Optional[float] = None
        self._next_id = 1
        self._finished: List[GoalRecord] = []
        # The object and its vertical state.
        self._obj: Optional[GraspObject] = None
        self._inside = False
        self._crushed = False
        self._crushed_s: Optional[float] = None
        self._obj_z = 0.0
        self._obj_v = 0.0
        self._offset = 0.0
        self._moves_with_hand = False
        self._in_reach = True  # horizontally between the fingers (the caller's geometry)
        self._hand_v_prev: Optional[float] = None
        # Results of the last step.
        self._force = 0.0
        self._spring = 0.0
        self._update_forces()

    # ------------------------------------------------------------------ object

    def place_object(self, obj: GraspObject, finger_offset_m: float = 0.0, height_m: float = 0.0) -> None:
        """Put ``obj`` in the hand's reach (a fresh, unbroken one).

        ``finger_offset_m``: how far the fingers are above the object's grasp height (m);
        the object is between the fingers while ``|offset| <= grip_zone_m``.
        ``height_m``: the object's height above its support (0: on the table).
        """
        if not isinstance(obj, GraspObject):
            raise HandSimError(f"place_object takes a GraspObject, got {obj!r}; e.g. OBJECTS['egg']")
        offset = checked_param(finger_offset_m, "finger_offset_m", "pass metres, 0.0 = fingers at the grasp height")
        height = checked_param(height_m, "height_m", "pass metres above the support, 0.0 = on the table", lowest=">=0")
        if self._in_reach and abs(offset) <= self.params.grip_zone_m and self._w < obj.width_m + self._travel:
            raise HandSimError(
                f"place_object: the fingers are {self._w:.4f} m apart, too close for the {obj.name} "
                f"({obj.width_m} m + {self._travel} m piston); open them first, or place it with "
                f"|finger_offset_m| > {self.params.grip_zone_m} m (outside the fingers)"
            )
        self._obj = obj
        self._crushed = False
        self._crushed_s = None
        self._offset = offset
        self._obj_z = height
        self._obj_v = 0.0
        self._moves_with_hand = False
        self._inside = False
        self._update_inside()
        self._update_forces()

    def remove_object(self) -> None:
        """Take the object away (the fingers then close on nothing but the piston)."""
        self._obj = None
        self._inside = False
        self._crushed = False
        self._crushed_s = None
        self._moves_with_hand = False
        self._update_forces()

    @property
    def object(self) -> Optional[GraspObject]:
        """The object in reach, or None."""
        return self._obj

    @property
    def object_crushed(self) -> bool:
        """Whether the object broke (its breaking force was exceeded)."""
        return self._crushed

    @property
    def object_crushed_s(self) -> Optional[float]:
        """When the object broke (s), or None."""
        return self._crushed_s

    @property
    def object_height_m(self) -> float:
        """The object's height above its support (m); > 0 means lifted."""
        return self._obj_z

    @property
    def object_moves_with_hand(self) -> bool:
        """Whether, in the last step, friction carried the object along with the hand."""
        return self._moves_with_hand

    @property
    def finger_offset_m(self) -> float:
        """Fingers' height above the object's grasp height (m); grows as the object slips."""
        return self._offset

    def set_in_reach(self, in_reach: bool) -> None:
        """Tell the hand whether the object is horizontally between the fingers.

        The hand models only the vertical; the caller (:class:`hri_teleop.sim.world.LabWorld`)
        knows where the hand and the object are in the plane.  An object out of reach is
        not between the fingers whatever the height; coming back into reach follows the
        same rule as coming down onto it (the fingers must be open wide enough).
        """
        in_reach = bool(in_reach)
        if in_reach == self._in_reach:
            return
        self._in_reach = in_reach
        inside = self._inside
        self._update_inside()
        if self._inside != inside:
            self._update_forces()

    @property
    def object_between_fingers(self) -> bool:
        """Whether an unbroken object is between the fingers (in reach and in the grip zone)."""
        return self._between_fingers()

    def _between_fingers(self) -> bool:
        return self._inside and not self._crushed

    def _update_inside(self) -> None:
        """The object is between the fingers while in the grip zone, if it got in with room to spare.

        Fingers closer than the object's width (plus the piston) cannot take it in: moving
        them over it is a collision this model does not resolve, so the object stays outside
        (no force) until the fingers leave the zone and come back open enough.
        """
        obj = self._obj
        if obj is None or not self._in_reach or abs(self._offset) > self.params.grip_zone_m:
            self._inside = False
        elif not self._inside:
            self._inside = self._w >= obj.width_m + self._travel

    # ------------------------------------------------------------------ elastics

    def _contact(self) -> Tuple[float, float]:
        """(contact width, stiffness of what the piston meets): the object or the other finger."""
        if self._between_fingers():
            obj = self._obj
            assert obj is not None
            return obj.width_m + self._travel, obj.stiffness_n_per_m
        return self._travel, math.inf

    def _forces_at(self, width_m: float, contact_m: float, k_obj: float) -> Tuple[float, float]:
        """(grip force, spring force) in N at a width: spring and object in series."""
        squeeze = contact_m - width_m
        if squeeze <= 0.0:
            return 0.0, 0.0
        k_s = self._k_spring
        bottom_out = self._travel + self._f_spring_full / k_obj  # squeeze at which the piston is level
        if squeeze <= bottom_out:
            force = squeeze / (1.0 / k_s + 1.0 / k_obj)
            return force, force
        return k_obj * (squeeze - self._travel), self._f_spring_full

    def _width_at(self, force_n: float, contact_m: float, k_obj: float) -> float:
        """The width at which the grip force equals ``force_n`` (the fingers' stall width)."""
        if force_n <= 0.0:
            return contact_m
        if force_n <= self._f_spring_full:
            return contact_m - force_n * (1.0 / self._k_spring + 1.0 / k_obj)
        return contact_m - self._travel - force_n / k_obj

    def _update_forces(self) -> None:
        contact, k_obj = self._contact()
        self._force, self._spring = self._forces_at(self._w, contact, k_obj)

    # ------------------------------------------------------------------ read-outs

    @property
    def now_s(self) -> float:
        """The time of the last step (or of the start)."""
        return self._now

    @property
    def width_m(self) -> float:
        """The width between the fingers (m), as the hand reports it."""
        return self._w

    @property
    def width_rate_m_per_s(self) -> float:
        """The width's rate of change in the last step (m/s)."""
        return self._rate

    @property
    def joint_positions_m(self) -> Tuple[float, float]:
        """The two finger joints of ``/franka_gripper/joint_states``: width/2 each."""
        half = 0.5 * self._w
        return half, half

    @property
    def joint_velocities_m_per_s(self) -> Tuple[float, float]:
        """The finger joints' velocities: rate/2 each (the real node publishes zeros)."""
        half = 0.5 * self._rate
        return half, half

    @property
    def grip_force_n(self) -> float:
        """Force between the fingers and the object (or the other finger) (N)."""
        return self._force

    @property
    def spring_force_n(self) -> float:
        """Force of the piston spring on the FSR (N); at most the full-travel force."""
        return self._spring

    @property
    def piston_compression_m(self) -> float:
        """How far the piston is pushed in (m), 0 .. travel."""
        return self._spring / self._k_spring

    @property
    def fsr_count(self) -> int:
        """The ADC count the sensor board reads now: ``fsr.force_to_count(spring force)``."""
        return self.attachment.count(self._spring)

    @property
    def in_contact(self) -> bool:
        """Whether the piston or the fingers touch the object (width <= object width + travel)."""
        if not self._between_fingers():
            return False
        obj = self._obj
        assert obj is not None
        return self._w <= obj.width_m + self._travel

    @property
    def is_grasped(self) -> bool:
        """libfranka's ``GripperState.is_grasped``: a successful grasp holds within its epsilons."""
        g = self._grasp
        if self._mode != _GRASP_HOLD or g is None:
            return False
        return g.width_m - g.epsilon_inner_m < self._w < g.width_m + g.epsilon_outer_m

    @property
    def active_goal(self) -> Optional[GoalRecord]:
        """The running move, grasp or homing goal, or None."""
        return self._active

    def state(self) -> HandState:
        """A snapshot of everything above."""
        active = self._active
        return HandState(
            time_s=self._now,
            width_m=self._w,
            width_rate_m_per_s=self._rate,
            grip_force_n=self._force,
            spring_force_n=self._spring,
            piston_compression_m=self.piston_compression_m,
            fsr_count=self.fsr_count,
            in_contact=self.in_contact,
            is_grasped=self.is_grasped,
            active_action=active.action if active is not None else None,
            object_name=self._obj.name if self._obj is not None else None,
            object_crushed=self._crushed,
            object_height_m=self._obj_z,
            object_moves_with_hand=self._moves_with_hand,
            finger_offset_m=self._offset,
        )

    # ------------------------------------------------------------------ goals

    def _check_time(self, now_s: float, what: str) -> float:
        if not is_finite_number(now_s, numpy=True):
            raise HandSimError(f"{what}: now_s must be a finite time in seconds, got {now_s!r}")
        now = float(now_s)
        if now < self._now:
            raise HandSimError(
                f"{what}: time ran backwards ({now!r} s after {self._now!r} s); pass the simulation time, "
                "which never decreases"
            )
        return now

    def _finish(self, record: GoalRecord, now: float, status: GoalStatus, success: bool,
                error: str = "", detail: str = "") -> None:
        record.status = status
        record.success = success
        record.error = error
        add_note(record, detail)
        record.finished_s = now
        self._finished.append(record)
        if record is self._active:
            self._active = None

    def send(self, command: Command, now_s: float) -> GoalRecord:
        """Accept a goal at ``now_s`` and return its record (updated in place as it runs).

        move, grasp and homing preempt the running one; stop ends it and releases.
        Impossible goals end ABORTED at once and leave the running goal alone.
        """
        if type(command) not in ACTION_NAMES:
            raise HandSimError(
                f"send takes a MoveCommand, GraspCommand, HomingCommand or StopCommand, got {command!r}"
            )
        now = self._check_time(now_s, "send")
        record = GoalRecord(goal_id=self._next_id, command=command, accepted_s=now)
        self._next_id += 1
        p = self.params
        if isinstance(command, StopCommand):
            if self._active is not None:
                self._finish(self._active, now, GoalStatus.ABORTED, False, COMMAND_ABORTED,
                             f"stopped by goal {record.goal_id} (stop)")
            self._release()
            self._finish(record, now, GoalStatus.SUCCEEDED, True)
            return record
        problem = goal_problem(command, self._w_max)
        if problem:
            self._finish(record, now, GoalStatus.ABORTED, False, COMMAND_FAILED, problem)
            return record
        if self._active is not None:
            self._finish(self._active, now, GoalStatus.PREEMPTED, False, "",
                         f"preempted by goal {record.goal_id} ({record.action})")
        self._active = record
        self._stall_since = None
        self._grasp = None
        if isinstance(command, MoveCommand):
            self._mode, self._target, self._cap = _MOVE, command.width_m, p.move_force_n
            self._speed = self._clip_speed(command.speed_m_per_s, record)
        elif isinstance(command, GraspCommand):
            self._mode, self._cap = _GRASP, min(command.force_n, p.max_force_n)
            if command.force_n > p.max_force_n:
                add_note(record, f"force {command.force_n} N clipped to {p.max_force_n} N")
            self._target = 0.0 if command.width_m < self._w else self._w_max
            self._speed = self._clip_speed(command.speed_m_per_s, record)
            self._grasp = command
        else:
            self._mode, self._target, self._cap = _HOMING_CLOSE, 0.0, p.homing_force_n
            self._speed = p.homing_speed_m_per_s
        return record

    def cancel(self, record: GoalRecord, now_s: float) -> None:
        """actionlib cancel: a running goal ends PREEMPTED and the fingers hold where they are."""
        now = self._check_time(now_s, "cancel")
        if record is not self._active:
            return
        self._finish(record, now, GoalStatus.PREEMPTED, False, "", "cancelled")
        self._mode, self._target = _HOLD, self._w

    def pop_finished(self) -> List[GoalRecord]:
        """Goals that ended since the last call, in the order they ended."""
        done, self._finished = self._finished, []
        return done

    def _clip_speed(self, speed: float, record: GoalRecord) -> float:
        if speed > self._v_max:
            add_note(record, f"speed {speed} m/s clipped to {self._v_max} m/s")
            return self._v_max
        return speed

    def _release(self) -> None:
        self._mode, self._cap, self._target = _RELEASED, 0.0, self._w
        self._grasp = None

    # ------------------------------------------------------------------ stepping

    def step(self, now_s: float, hand_vz_m_per_s: float = 0.0,
             hand_az_m_per_s2: Optional[float] = None) -> bool:
        """Advance to ``now_s``: fingers, forces, goals, and the object's vertical motion.

        ``hand_vz_m_per_s`` is the hand's upward velocity, ``hand_az_m_per_s2`` its upward
        acceleration (None: the difference of successive velocities).  Returns whether the
        object moved with the hand in this step (False without an object).
        """
        now = self._check_time(now_s, "step")
        hand_v = hand_vz_m_per_s
        if not is_finite_number(hand_v, numpy=True):
            raise HandSimError(f"step: hand_vz_m_per_s must be a finite velocity in m/s, got {hand_v!r}")
        hand_a = hand_az_m_per_s2
        if hand_a is not None and not is_finite_number(hand_a, numpy=True):
            raise HandSimError(f"step: hand_az_m_per_s2 must be a finite acceleration in m/s^2 or None, got {hand_a!r}")
        return self.advance(now, float(hand_v), None if hand_a is None else float(hand_a))

    def advance(self, now: float, hand_v: float, hand_a: Optional[float] = None) -> bool:
        """:meth:`step` for a caller whose times and velocities come from the simulation itself
        (floats, finite, never back in time): the world's 1 kHz loop, which checks nothing twice."""
        dt = now - self._now
        if dt <= 0.0:
            return self._moves_with_hand
        self._now = now
        w = self._w
        contact, k_obj = self._contact()
        mode = self._mode
        # 1. Kinematics: towards the target at the commanded speed ...
        if mode == _RELEASED:
            w_next = w
        else:
            reach = self._speed * dt
            error = self._target - w
            if abs(error) <= reach + _SAME_M:  # arrives: exactly on the target, no rounding left
                w_next = self._target
            else:
                w_next = w + reach if error > 0 else w - reach
        # ... 2. but not past the width where the elastic force reaches the force limit
        # (there the fingers stall); a hand squeezed beyond its limit is pushed open, at
        # most at the speed limit, and stalls once it is back at that width.
        w_stall = self._width_at(self._cap, contact, k_obj)
        held_back = False
        if w_next < w_stall:
            if w_stall <= w + self._v_max * dt:
                w_next, held_back = w_stall, True
            else:
                w_next = w + self._v_max * dt
        if w_next < 0.0:
            w_next = 0.0
        elif w_next > self._w_max:
            w_next = self._w_max
        force, spring = self._forces_at(w_next, contact, k_obj)
        # 3. A fragile object breaks above its breaking force and stops resisting.
        obj = self._obj
        if obj is not None and obj.breaking_force_n is not None and force > obj.breaking_force_n \
                and self._between_fingers():
            self._crushed = True
            self._crushed_s = now
            contact, k_obj = self._contact()
            force, spring = self._forces_at(w_next, contact, k_obj)
        self._rate = (w_next - w) / dt
        self._w = w_next
        self._force = force
        self._spring = spring
        # 4. Goals.
        if mode >= _MOVE and mode != _GRASP_HOLD:
            self._advance_goal(mode, w_next, held_back, now)
        # 5. The object's vertical motion.
        self._vertical(dt, hand_v, hand_a)
        return self._moves_with_hand

    def _advance_goal(self, mode: int, w: float, held_back: bool, now: float) -> None:
        """Finish or advance the running goal after a step that ended at width ``w``.

        ``held_back``: the force limit stopped the fingers (they stall against the object);
        a stall is that, or having arrived at the target (a grasp's target is a width limit).
        """
        record = self._active
        assert record is not None
        p = self.params
        target = self._target
        gap = abs(w - target)
        arrived = gap <= _SAME_M
        if mode == _MOVE:
            if arrived or (held_back and gap <= p.move_width_tolerance_m):
                self._mode = _HOLD
                self._finish(record, now, GoalStatus.SUCCEEDED, True)
            elif not held_back:
                self._stall_since = None
            elif self._stall_since is None:
                self._stall_since = now
            elif now - self._stall_since >= p.move_stall_timeout_s:
                self._mode, self._target = _HOLD, w
                self._finish(record, now, GoalStatus.ABORTED, False, COMMAND_FAILED,
                             f"blocked at {w:.4f} m, short of {target:.4f} m, for {p.move_stall_timeout_s} s")
        elif mode == _GRASP:
            if not (held_back or arrived):
                return
            g = self._grasp
            assert g is not None
            record.grasp_width_m = w
            if g.width_m - g.epsilon_inner_m < w < g.width_m + g.epsilon_outer_m:
                self._mode = _GRASP_HOLD
                self._finish(record, now, GoalStatus.SUCCEEDED, True)
            else:
                self._release()
                self._finish(record, now, GoalStatus.SUCCEEDED, False, "",
                             f"stalled at {w:.4f} m, outside {g.width_m:.4f} m "
                             f"(-{g.epsilon_inner_m:.4f}/+{g.epsilon_outer_m:.4f} m): nothing grasped")
        elif mode == _HOMING_CLOSE:
            if held_back or arrived:
                self._mode, self._target = _HOMING_OPEN, self._w_max
        elif mode == _HOMING_OPEN and arrived:
            self._mode, self._target, self._cap = _HOLD, self._w_max, p.move_force_n
            self._finish(record, now, GoalStatus.SUCCEEDED, True)

    def _vertical(self, dt: float, hand_v: float, hand_a: Optional[float]) -> None:
        """Coulomb stick-slip of the object against the fingers, and its support."""
        if hand_a is None:
            hand_a = 0.0 if self._hand_v_prev is None else (hand_v - self._hand_v_prev) / dt
        self._hand_v_prev = hand_v
        obj = self._obj
        if obj is None:
            self._moves_with_hand = False
            return
        self._vertical_object(obj, dt, hand_v, float(hand_a))
        inside = self._inside
        self._update_inside()
        if self._inside != inside:  # it slid out of (or into) the fingers
            self._update_forces()

    def _vertical_object(self, obj: GraspObject, dt: float, hand_v: float, hand_a: float) -> None:
        g = GRAVITY_M_PER_S2
        m = obj.mass_kg
        friction = holding_force_n(self._force, obj.friction_coefficient) if self._between_fingers() else 0.0
        v = self._obj_v
        relative = v - hand_v
        stick = False
        if abs(relative) <= _STICK_M_PER_S:
            need = m * (hand_a + g)  # friction force that would carry it along
            if abs(need) <= friction and friction > 0.0:
                stick = True
                accel = hand_a
            else:
                accel = -g + math.copysign(friction, need) / m
        else:
            accel = -g - math.copysign(friction, relative) / m
        if stick:
            v_next = hand_v
        else:
            v_next = v + accel * dt
            # Kinetic friction stops the relative motion, it never reverses it.
            if friction > 0.0 and relative != 0.0 and (v_next - hand_v) * relative <= 0.0:
                v_next = hand_v
                stick = True
        z = self._obj_z + v_next * dt
        if z <= 0.0:  # the support carries it
            z = 0.0
            if v_next < 0.0:
                v_next = 0.0
                stick = stick and hand_v >= 0.0
        self._offset += (hand_v - v_next) * dt
        self._obj_z = z
        self._obj_v = v_next
        self._moves_with_hand = stick and friction > 0.0 and abs(v_next - hand_v) <= _STICK_M_PER_S
