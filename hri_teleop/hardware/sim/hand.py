"""The Franka Hand, an object between its fingers and the lab's FSR attachment, simulated.

Why: at home there is no gripper, no object and no sensor board (issue 3, "The simulated
gripper, object and FSR attachment").  The simulation node serves franka_gripper's actions
and publishes ``/franka_gripper/joint_states``; the simulated sensor board publishes the
FSR count on ``/pub_force``.  Both need one physics underneath, and this module is it:
pure Python floats, no rospy, no I/O and no clock.  The caller passes the time to every
call and steps :class:`HandSim` at 1 kHz; the same inputs give the same outputs.

What is modelled, and the numbers (every one a field of a dataclass, so a node can make it
a parameter):

**The hand** (:class:`HandParams`).  Width = distance between the fingers, 0 ..
``GRIPPER_MAX_WIDTH_M`` (0.08 m, docs/lab-facts.md).  Speed of the width at most 0.1 m/s
(franka_gripper's ``default_speed`` is 0.1 m/s, ``franka_gripper_node.yaml``; frankx,
a libfranka wrapper, has ``Gripper::max_speed = 0.1``).  Force at most 70 N (handout: "can
apply forces up to 70 N"; the Franka Hand's continuous grasping force; its short-term peak
of 140 N is not modelled).  A ``move`` presses with the motor's limit, 70 N; a ``grasp``
with its commanded force (clipped to 70 N).  The motion is quasi-static: the width
follows the command at the commanded speed until the elastic force of whatever is between
the fingers reaches the force limit; there the fingers stall.  Fingers that are squeezed
harder than the current limit allows (a weaker new grasp, a ``stop``) are pushed open, at
most at the speed limit.

**The commands** follow franka_gripper and libfranka (``franka::Gripper``):

* ``move{width, speed}``: drives to ``width`` at ``speed``.  It succeeds when the width is
  reached, or when the fingers stall within ``move_width_tolerance_m`` (1 mm, franka_gazebo's
  ``kDefaultMoveWidthTolerance``) of it.  A move that an object blocks further away does
  what the real hand does: it keeps pressing and does not return (libfranka issue #18:
  "move: blocks until the desired location is reached"; franka_ros issue #281: an
  unreachable move "will stall for about 100s") and then fails with libfranka's
  ``"libfranka gripper: Command failed!"`` (``move_stall_timeout_s``, 100 s).  After a
  successful move the hand holds the width with the move force: this is how the lab's
  gripper_manager (move goals only) squeezes the piston.
* ``grasp{width, epsilon{inner, outer}, speed, force}``: closes (or opens, if ``width`` is
  above the current width, as franka_gazebo does) until the fingers stall at the commanded
  force; with ``d`` the width then, it is a success iff ``width - inner < d < width + outer``
  (libfranka ``Gripper::grasp``).  On success the hand keeps applying the force (franka_ros
  issue #130) until ``stop`` or a new goal.  On failure it lets go.  Like the real
  franka_gripper_node, an unsuccessful grasp ends with status SUCCEEDED and
  ``success=False`` (its ``handleErrors`` calls ``setSucceeded`` with whatever libfranka
  returned; only exceptions become ABORTED).
* ``homing{}``: closes (until the fingers stall at ``homing_force_n``, so an object in the
  way is touched, not crushed) and then opens fully, as franka_gazebo's simulation does
  (homing runs the fingers over their range to measure the maximum width); succeeds when
  fully open.
* ``stop{}``: succeeds at once; a running move, grasp or homing ends ABORTED with
  libfranka's ``"libfranka gripper: Command aborted!"``, and the hand stops pressing
  (libfranka issue #111: call stop after a grasp "to release the pressure onto the
  object"); squeezed fingers are then pushed back to where the force vanishes.
* A newer move/grasp/homing goal preempts the running one (status PREEMPTED), as in the
  franka_gazebo gripper simulation.  Note: the real franka_gripper_node runs each goal as a
  blocking libfranka call, so there a new goal waits until the running one returns.
* A goal the hand cannot execute (width outside 0 .. 0.08 m, speed <= 0, negative force or
  epsilon, NaN) is accepted and ends ABORTED with ``"libfranka gripper: Command failed!"``
  at once; it does not disturb the running goal.  A speed above 0.1 m/s or a force above
  70 N is clipped (the record's ``detail`` says so).

**The attachment** (:class:`Attachment`, handout Fig. 5).  One finger carries a housing
with a piston that sticks out by its travel (3 mm; the handout gives no figure) when
relaxed.  Closing on an object pushes the piston in against a spring (590 N/m) that
presses the FSR; the FSR force is the spring force.  At full travel the piston is level
with the housing and any further force goes into the rigid housing, so the FSR force
saturates at 590 N/m * 3 mm = 1.77 N, which ``hri_teleop.core.fsr`` reads as about 700 counts:
the handout's "maximum value when the piston is pressed in level with the housing".  The
reported width is measured from the housing face (what homing with the attachment
mounted measures), so the piston touches an object of width ``W`` when the width is
``W + travel``, and with no object it touches the other finger at ``width <= travel``.

**The object** (:class:`GraspObject`): width, stiffness, mass, friction coefficient and an
optional breaking force.  Object and piston spring are springs in series: with
``delta = W + travel - width`` the total squeeze, the force is ``delta / (1/k_spring +
1/k_object)`` until the piston bottoms out, then ``k_object * (delta - travel)``.  An
object whose force exceeds its breaking force is crushed: it no longer resists (the
fingers meet the other finger through the piston) and can no longer be held.  See
:data:`OBJECTS` for the predefined set.

**Lift** (:func:`holding_force_n`, :func:`is_held` and :meth:`HandSim.step`): two contact
faces with Coulomb friction hold ``2 * mu * F_grip``.  The object moves with the hand while
that covers ``m * (g + a)`` (``a`` the hand's upward acceleration); otherwise it slides,
with kinetic friction of the same coefficient, and falls back to its support (the table,
height 0).  The object counts as between the fingers while the fingers are within
``grip_zone_m`` (2 cm, about a Franka fingertip pad) of it vertically, provided it got
there with the fingers open wider than ``W + travel``: closed fingers arriving over an
object collide with it, which this model does not resolve (the object just stays outside).
The horizontal geometry is the caller's (place and remove the object).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Dict, List, Optional, Tuple, Union

import numpy as np

from hri_teleop.core import fsr
from hri_teleop.core.checks import is_finite_number, is_number
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.teleop import GRIPPER_MAX_WIDTH_M

__all__ = [
    "HandSimError",
    "MAX_SPEED_M_PER_S",
    "MAX_FORCE_N",
    "MOVE_WIDTH_TOLERANCE_M",
    "MOVE_STALL_TIMEOUT_S",
    "DEFAULT_EPSILON_M",
    "GRAVITY_M_PER_S2",
    "PISTON_TRAVEL_M",
    "SPRING_N_PER_M",
    "COMMAND_FAILED",
    "COMMAND_ABORTED",
    "HandParams",
    "Attachment",
    "GraspObject",
    "OBJECTS",
    "holding_force_n",
    "is_held",
    "MoveCommand",
    "GraspCommand",
    "HomingCommand",
    "StopCommand",
    "Command",
    "GoalStatus",
    "GoalRecord",
    "HandState",
    "HandSim",
]

#: Largest speed of the width (m/s): franka_gripper's default_speed, frankx's max_speed.
MAX_SPEED_M_PER_S = 0.1
#: Largest force between the fingers (N): the handout's 70 N, the hand's continuous force.
MAX_FORCE_N = 70.0
#: A move that stalls this close to its width succeeds (m): franka_gazebo's default.
MOVE_WIDTH_TOLERANCE_M = 0.001
#: A move blocked for this long fails (s): "stalls for about 100 s" (franka_ros #281).
MOVE_STALL_TIMEOUT_S = 100.0
#: libfranka's default grasp epsilon, inner and outer (m); franka_gripper's default too.
DEFAULT_EPSILON_M = 0.005
#: Standard gravity (m/s^2).
GRAVITY_M_PER_S2 = 9.81
#: How far the piston sticks out of the housing when relaxed (m).  Not given by the
#: handout; 3 mm is a small piston's travel and a window the operator can hit.
PISTON_TRAVEL_M = 0.003
#: Piston spring (N/m): full travel gives 1.77 N, which the FSR model reads as ~700 counts
#: (``fsr.count_to_force(700)`` is 1.76 N), the handout's value at full travel.
SPRING_N_PER_M = 590.0
#: libfranka's message for a command the gripper could not carry out.
COMMAND_FAILED = "libfranka gripper: Command failed!"
#: libfranka's message for a command ended by stop.
COMMAND_ABORTED = "libfranka gripper: Command aborted!"

# Vertical relative speeds below this count as sticking (m/s).
_STICK_M_PER_S = 1e-9
# Widths closer than this are equal (m): far below any physical resolution.
_SAME_M = 1e-12


class HandSimError(HriTeleopError, ValueError):
    """A hand, attachment, object or command setting is unusable, or time ran backwards."""


def _check(value: object, name: str, fix: str, *, lowest: str = "") -> float:
    """``value`` as a finite float; ``lowest`` ">0" or ">=0" bounds it (else HandSimError)."""
    if not is_finite_number(value, numpy=True):
        raise HandSimError(f"{name} must be a finite number, got {value!r}; {fix}")
    number = float(value)  # type: ignore[arg-type]
    if (lowest == ">0" and not number > 0.0) or (lowest == ">=0" and not number >= 0.0):
        raise HandSimError(f"{name} must be {lowest.replace('0', ' 0')}, got {value!r}; {fix}")
    return number


# --------------------------------------------------------------------------- hand


@dataclass(frozen=True)
class HandParams:
    """The Franka Hand's numbers (defaults: the real hand, see the module doc).

    ``homing_speed_m_per_s`` and ``homing_force_n`` are not published by Franka; they
    are chosen so that homing takes about 3 s and does not crush an object in the way.
    """

    max_width_m: float = GRIPPER_MAX_WIDTH_M
    max_speed_m_per_s: float = MAX_SPEED_M_PER_S
    max_force_n: float = MAX_FORCE_N
    move_force_n: float = MAX_FORCE_N
    move_width_tolerance_m: float = MOVE_WIDTH_TOLERANCE_M
    move_stall_timeout_s: float = MOVE_STALL_TIMEOUT_S
    homing_speed_m_per_s: float = 0.05
    homing_force_n: float = 10.0
    initial_width_m: float = GRIPPER_MAX_WIDTH_M
    grip_zone_m: float = 0.02

    def __post_init__(self) -> None:
        positive = (
            ("max_width_m", "the Franka Hand opens 0.08 m"),
            ("max_speed_m_per_s", "the Franka Hand's is 0.1"),
            ("max_force_n", "the Franka Hand's is 70.0"),
            ("move_force_n", "the Franka Hand's is 70.0"),
            ("move_stall_timeout_s", "the real hand gives up after about 100.0"),
            ("homing_speed_m_per_s", "e.g. 0.05"),
            ("homing_force_n", "e.g. 10.0"),
        )
        for name, fix in positive:
            object.__setattr__(self, name, _check(getattr(self, name), f"HandParams.{name}", fix,
                                                  lowest=">0"))
        for name, fix in (("move_width_tolerance_m", "e.g. 0.001"), ("grip_zone_m", "e.g. 0.02")):
            object.__setattr__(self, name, _check(getattr(self, name), f"HandParams.{name}", fix, lowest=">=0"))
        width = _check(self.initial_width_m, "HandParams.initial_width_m", "e.g. 0.08 (fully open)")
        if not 0.0 <= width <= self.max_width_m:
            raise HandSimError(
                f"HandParams.initial_width_m must lie in 0 .. {self.max_width_m} m, got {width!r}; e.g. 0.08 (fully open)"
            )
        object.__setattr__(self, "initial_width_m", width)
        if self.move_force_n > self.max_force_n or self.homing_force_n > self.max_force_n:
            raise HandSimError(
                f"HandParams.move_force_n ({self.move_force_n}) and homing_force_n ({self.homing_force_n}) must not "
                f"exceed max_force_n ({self.max_force_n}); lower them"
            )
        if self.homing_speed_m_per_s > self.max_speed_m_per_s:
            raise HandSimError(
                f"HandParams.homing_speed_m_per_s ({self.homing_speed_m_per_s}) exceeds max_speed_m_per_s "
                f"({self.max_speed_m_per_s}); lower it"
            )


# --------------------------------------------------------------------------- attachment


@dataclass(frozen=True)
class Attachment:
    """The FSR attachment of handout Fig. 5: piston, spring, FSR and the lab's divider.

    The FSR wiring arguments are those of :func:`hri_teleop.core.fsr.force_to_count`; the
    count is that function's, computed from a table of its thresholds
    (:func:`hri_teleop.core.fsr.count_to_force`) because one call of it costs about 35 us and
    the simulation steps at 1 kHz.  Forces within one part in a million of a threshold are
    handed to ``force_to_count`` itself, so the result is always exactly its result.
    """

    piston_travel_m: float = PISTON_TRAVEL_M
    spring_n_per_m: float = SPRING_N_PER_M
    law: fsr.PowerLaw = fsr.FSR402
    pulldown_ohm: float = fsr.PULLDOWN_OHM
    supply_v: float = fsr.SUPPLY_V
    adc_bits: int = fsr.ADC_BITS
    _thresholds_n: Optional[Tuple[float, ...]] = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "piston_travel_m", _check(
            self.piston_travel_m, "Attachment.piston_travel_m", "e.g. 0.003 (3 mm)", lowest=">0"))
        object.__setattr__(self, "spring_n_per_m", _check(
            self.spring_n_per_m, "Attachment.spring_n_per_m", "e.g. 590.0", lowest=">0"))
        # Checks the wiring (raises fsr.FsrError with its own fix) before the table is built.
        fsr.force_to_count(1.0, law=self.law, pulldown_ohm=self.pulldown_ohm, supply_v=self.supply_v,
                           adc_bits=self.adc_bits)
        if int(self.adc_bits) <= 16:
            counts = np.arange(2 ** int(self.adc_bits))
            table = fsr.count_to_force(counts, law=self.law, pulldown_ohm=self.pulldown_ohm,
                                       supply_v=self.supply_v, adc_bits=self.adc_bits)
            object.__setattr__(self, "_thresholds_n", tuple(float(f) for f in table))

    @property
    def full_travel_force_n(self) -> float:
        """The spring's force with the piston level with the housing (N): the FSR's maximum."""
        return self.spring_n_per_m * self.piston_travel_m

    @property
    def full_travel_count(self) -> int:
        """The count at full piston travel: what students record as ``/max_sensor_force``."""
        return self.count(self.full_travel_force_n)

    def spring_force_n(self, compression_m: float) -> float:
        """Spring (= FSR) force for a piston pushed in by ``compression_m``, clipped to the travel."""
        x = min(max(float(compression_m), 0.0), self.piston_travel_m)
        return self.spring_n_per_m * x

    def count(self, force_n: float) -> int:
        """The ADC count for an FSR force: exactly ``int(fsr.force_to_count(force_n, ...))``."""
        f = float(force_n)
        if not f > 0.0:  # no force (and NaN) is an open circuit: 0 V, count 0, as in hri_teleop.core.fsr
            return 0
        table = self._thresholds_n
        if table is None or math.isinf(f):
            return int(fsr.force_to_count(f, law=self.law, pulldown_ohm=self.pulldown_ohm,
                                          supply_v=self.supply_v, adc_bits=self.adc_bits))
        c = bisect.bisect_right(table, f) - 1
        low = table[c]
        high = table[c + 1] if c + 1 < len(table) else math.inf
        if f - low <= 1e-6 * low or high - f <= 1e-6 * high:
            return int(fsr.force_to_count(f, law=self.law, pulldown_ohm=self.pulldown_ohm,
                                          supply_v=self.supply_v, adc_bits=self.adc_bits))
        return c


# --------------------------------------------------------------------------- objects


@dataclass(frozen=True)
class GraspObject:
    """Something to put between the fingers (SI units; ``breaking_force_n`` None: unbreakable).

    ``stiffness_n_per_m`` is the object's stiffness across the grasp (both faces together),
    ``friction_coefficient`` the static and kinetic coefficient against the fingers.
    """

    name: str
    width_m: float
    stiffness_n_per_m: float
    mass_kg: float
    friction_coefficient: float
    breaking_force_n: Optional[float] = None
    note: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise HandSimError(f"GraspObject.name must be a non-empty string, got {self.name!r}; e.g. 'egg'")
        for name, fix in (
            ("width_m", "e.g. 0.045 for an egg"),
            ("stiffness_n_per_m", "e.g. 1e6 for a rigid block"),
            ("mass_kg", "e.g. 0.06 for an egg"),
            ("friction_coefficient", "e.g. 0.4"),
        ):
            object.__setattr__(self, name, _check(getattr(self, name), f"GraspObject.{name}", fix,
                                                  lowest=">0"))
        if self.breaking_force_n is not None:
            object.__setattr__(self, "breaking_force_n", _check(
                self.breaking_force_n, "GraspObject.breaking_force_n", "e.g. 30.0, or None for unbreakable",
                lowest=">0"))

    def min_grip_force_n(self, hand_accel_up_m_per_s2: float = 0.0) -> float:
        """The smallest grip force (N) that holds the object while the hand accelerates upwards."""
        return self.mass_kg * max(GRAVITY_M_PER_S2 + hand_accel_up_m_per_s2, 0.0) / (2.0 * self.friction_coefficient)


#: The predefined objects.  Masses are those of the real things; the lift column says what
#: grip force holds each one at rest (m g / 2 mu), against the 1.77 N of the piston spring:
#: light objects lift on the spring alone, the heavy block needs the housing to press.
OBJECTS: Dict[str, GraspObject] = {
    obj.name: obj
    for obj in (
        GraspObject(
            "block", width_m=0.05, stiffness_n_per_m=1e6, mass_kg=0.08, friction_coefficient=0.4,
            note="50 mm wooden cube (0.65 g/cm^3 -> 81 g), effectively rigid; holds from 0.98 N",
        ),
        GraspObject(
            "heavy_block", width_m=0.04, stiffness_n_per_m=1e7, mass_kg=0.17, friction_coefficient=0.3,
            note="40 mm aluminium cube (2.7 g/cm^3 -> 173 g), rigid and slippery; holds from 2.8 N, "
                 "i.e. only with the piston pressed in level with the housing",
        ),
        GraspObject(
            "sponge", width_m=0.05, stiffness_n_per_m=1500.0, mass_kg=0.015, friction_coefficient=0.8,
            note="kitchen sponge 50 mm thick, 10 N squeezes it by 7 mm; holds from 0.09 N",
        ),
        GraspObject(
            "egg", width_m=0.044, stiffness_n_per_m=1.2e5, mass_kg=0.06, friction_coefficient=0.35,
            breaking_force_n=30.0,
            note="a hen's egg across its short axis: 44 mm, 60 g, shell stiffness of the order of 100 N/mm, "
                 "cracks at 30 N (the low end of typical eggs); holds from 0.84 N, so a grip inside the "
                 "piston's travel lifts it and a squeeze past full travel crushes it within 0.25 mm",
        ),
    )
}


def holding_force_n(grip_force_n: float, friction_coefficient: float) -> float:
    """Largest vertical force (N) two friction faces carry: ``2 * mu * F_grip``."""
    return 2.0 * friction_coefficient * max(grip_force_n, 0.0)


def is_held(grip_force_n: float, obj: GraspObject, hand_accel_up_m_per_s2: float = 0.0) -> bool:
    """Whether friction carries the object while the hand accelerates upwards by ``a``.

    Held iff ``2 * mu * F_grip >= m * (g + a)``; a hand falling at ``g`` or faster needs no grip.
    """
    need_n = obj.mass_kg * max(GRAVITY_M_PER_S2 + hand_accel_up_m_per_s2, 0.0)
    return holding_force_n(grip_force_n, obj.friction_coefficient) >= need_n


# --------------------------------------------------------------------------- commands


def _field(value: object, name: str) -> float:
    """A command field as a float (NaN and inf kept: the hand, not the caller, rejects them)."""
    if not is_number(value, numpy=True):
        raise HandSimError(f"{name} must be a number, got {value!r}; pass metres, m/s or newtons as a float")
    return float(value)  # type: ignore[arg-type]


@dataclass(frozen=True)
class MoveCommand:
    """franka_gripper ``move`` goal: drive to ``width_m`` at ``speed_m_per_s``."""

    width_m: float
    speed_m_per_s: float = MAX_SPEED_M_PER_S

    def __post_init__(self) -> None:
        object.__setattr__(self, "width_m", _field(self.width_m, "MoveCommand.width_m"))
        object.__setattr__(self, "speed_m_per_s", _field(self.speed_m_per_s, "MoveCommand.speed_m_per_s"))


@dataclass(frozen=True)
class GraspCommand:
    """franka_gripper ``grasp`` goal: close to contact, press with ``force_n``, check the width."""

    width_m: float
    speed_m_per_s: float = MAX_SPEED_M_PER_S
    force_n: float = 20.0
    epsilon_inner_m: float = DEFAULT_EPSILON_M
    epsilon_outer_m: float = DEFAULT_EPSILON_M

    def __post_init__(self) -> None:
        for name in ("width_m", "speed_m_per_s", "force_n", "epsilon_inner_m", "epsilon_outer_m"):
            object.__setattr__(self, name, _field(getattr(self, name), f"GraspCommand.{name}"))


@dataclass(frozen=True)
class HomingCommand:
    """franka_gripper ``homing`` goal (no fields)."""


@dataclass(frozen=True)
class StopCommand:
    """franka_gripper ``stop`` goal (no fields)."""


Command = Union[MoveCommand, GraspCommand, HomingCommand, StopCommand]

_ACTION_NAMES = {MoveCommand: "move", GraspCommand: "grasp", HomingCommand: "homing", StopCommand: "stop"}


class GoalStatus(IntEnum):
    """A goal's state; the numbers are actionlib's ``GoalStatus`` constants."""

    ACTIVE = 1
    PREEMPTED = 2
    SUCCEEDED = 3
    ABORTED = 4


@dataclass
class GoalRecord:
    """One goal's life, as an action server reports it.

    ``success`` and ``error`` are the fields of franka_gripper's results; ``detail`` says
    in plain words why the goal ended as it did (not part of any message).
    ``grasp_width_m`` is the width ``d`` at which a grasp stalled.
    """

    goal_id: int
    command: Command
    accepted_s: float
    status: GoalStatus = GoalStatus.ACTIVE
    success: bool = False
    error: str = ""
    detail: str = ""
    finished_s: Optional[float] = None
    grasp_width_m: Optional[float] = None

    @property
    def action(self) -> str:
        """The action's name: "move", "grasp", "homing" or "stop"."""
        return _ACTION_NAMES[type(self.command)]

    @property
    def done(self) -> bool:
        """Whether the goal has reached a terminal state."""
        return self.status != GoalStatus.ACTIVE


def _note(record: GoalRecord, text: str) -> None:
    """Add ``text`` to the record's plain-words ``detail``."""
    if text:
        record.detail = f"{record.detail}; {text}" if record.detail else text


@dataclass(frozen=True)
class HandState:
    """A snapshot of :class:`HandSim` for logs, plots and tests."""

    time_s: float
    width_m: float
    width_rate_m_per_s: float
    grip_force_n: float
    spring_force_n: float
    piston_compression_m: float
    fsr_count: int
    in_contact: bool
    is_grasped: bool
    active_action: Optional[str]
    object_name: Optional[str]
    object_crushed: bool
    object_height_m: float
    object_moves_with_hand: bool
    finger_offset_m: float


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
        self._now = _check(start_s, "HandSim start_s", "pass the simulation's start time in seconds, e.g. 0.0")
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
        offset = _check(finger_offset_m, "finger_offset_m", "pass metres, 0.0 = fingers at the grasp height")
        height = _check(height_m, "height_m", "pass metres above the support, 0.0 = on the table", lowest=">=0")
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

        The hand models only the vertical; the caller (:class:`hri_teleop.hardware.sim.world.LabWorld`)
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
        now = float(now_s)  # type: ignore[arg-type]
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
        _note(record, detail)
        record.finished_s = now
        self._finished.append(record)
        if record is self._active:
            self._active = None

    def send(self, command: Command, now_s: float) -> GoalRecord:
        """Accept a goal at ``now_s`` and return its record (updated in place as it runs).

        move, grasp and homing preempt the running one; stop ends it and releases.
        Impossible goals end ABORTED at once and leave the running goal alone.
        """
        if type(command) not in _ACTION_NAMES:
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
        problem = self._problem(command)
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
                _note(record, f"force {command.force_n} N clipped to {p.max_force_n} N")
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

    def _problem(self, command: Command) -> str:
        """Why the hand cannot execute ``command`` ("" if it can)."""
        w_max = self._w_max
        if isinstance(command, (MoveCommand, GraspCommand)):
            if not (0.0 <= command.width_m <= w_max):
                return f"width {command.width_m!r} m outside 0 .. {w_max} m"
            if not (command.speed_m_per_s > 0.0):  # also NaN
                return f"speed {command.speed_m_per_s!r} m/s is not positive"
        if isinstance(command, GraspCommand):
            if not (command.force_n >= 0.0):
                return f"force {command.force_n!r} N is negative"
            if not (command.epsilon_inner_m >= 0.0 and command.epsilon_outer_m >= 0.0):
                return f"epsilon {command.epsilon_inner_m!r}/{command.epsilon_outer_m!r} m is negative"
        return ""

    def _clip_speed(self, speed: float, record: GoalRecord) -> float:
        if speed > self._v_max:
            _note(record, f"speed {speed} m/s clipped to {self._v_max} m/s")
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
        self._vertical(dt, float(hand_v), None if hand_a is None else float(hand_a))
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
