"""A simulated Franka Panda under a Cartesian velocity controller: moves and judges like the robot.

It takes the lab controller's twist, runs the robot's 1 kHz cycle on it (hold, judge with
:func:`hri_teleop.core.limits.limit_violations`' arithmetic, reflex or integrate), refuses a
command with libfranka's error names, ramps to zero on a command timeout and clamps at the
workspace box. Pure and deterministic; the model and its sources: docs/simulation.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Iterable, List, Optional, Sequence, Tuple

from hri_teleop.core.checks import is_finite_number, is_positive_number
from hri_teleop.core.errors import HriTeleopError
from hri_teleop.core.limits import (
    PANDA_LIMITS,
    ROBOT_PERIOD_S,
    CartesianLimits,
    LimitsError,
    Twist,
    TwistLimiter,
    Vec3,
)

__all__ = [
    "SimArmError",
    "SimArmConfig",
    "SimArm",
    "LimitViolation",
    "ArmEvent",
    "ArmPose",
    "VELOCITY_LIMITS_VIOLATION",
    "VELOCITY_DISCONTINUITY",
    "ACCELERATION_DISCONTINUITY",
    "NON_FINITE_COMMAND",
    "LIBFRANKA_ERROR_FOR",
    "STATE_IDLE",
    "STATE_MOVING",
    "STATE_TIMEOUT",
    "STATE_REFLEX",
    "EVENT_REFLEX",
    "EVENT_TIMEOUT",
    "EVENT_WORKSPACE",
    "EVENT_RECOVERED",
    "EVENT_IGNORED",
]

#: ``|v|`` above the velocity limit (franka::Errors field).
VELOCITY_LIMITS_VIOLATION = "cartesian_motion_generator_velocity_limits_violation"
#: ``|dv/dt|`` above the acceleration limit: "commanded velocity ... is discontinuous".
VELOCITY_DISCONTINUITY = "cartesian_motion_generator_velocity_discontinuity"
#: ``|da/dt|`` above the jerk limit: "commanded acceleration ... is discontinuous".
ACCELERATION_DISCONTINUITY = "cartesian_motion_generator_acceleration_discontinuity"
#: Not a franka::Errors flag: libfranka's std::invalid_argument "Commanding value is infinite or NaN.".
NON_FINITE_COMMAND = "commanding_value_is_infinite_or_nan"

#: Which libfranka error a violated limit raises, keyed by the limit's name in AxisLimits.
LIBFRANKA_ERROR_FOR: Dict[str, str] = {
    "velocity": VELOCITY_LIMITS_VIOLATION,
    "acceleration": VELOCITY_DISCONTINUITY,
    "jerk": ACCELERATION_DISCONTINUITY,
}

STATE_IDLE = "idle"
STATE_MOVING = "moving"
STATE_TIMEOUT = "timeout"
STATE_REFLEX = "reflex"

EVENT_REFLEX = "reflex"
EVENT_TIMEOUT = "command timeout"
EVENT_WORKSPACE = "workspace limit"
EVENT_RECOVERED = "recovered"
EVENT_IGNORED = "command ignored"

_ZERO6: Twist = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
_RUN = "run"  # internal mode: following commands; the state read-out says idle or moving
_AXES = "xyz"
_GROUPS = ("translation", "rotation")


class SimArmError(HriTeleopError, ValueError):
    """A configuration value, a command or a time the simulated arm cannot take; the message names the fix."""


@dataclass(frozen=True)
class LimitViolation:
    """One broken limit in one 1 ms cycle; ``value`` and ``limit`` in m/s^k (translation) or rad/s^k (rotation)."""

    time_s: float
    error: str
    group: str
    value: float
    limit: float


@dataclass(frozen=True)
class ArmEvent:
    """Something the arm reports once when it happens (kind is one of the ``EVENT_*`` strings)."""

    time_s: float
    kind: str
    message: str


@dataclass(frozen=True)
class ArmPose:
    """End-effector pose in the base frame: position in m, orientation as a unit quaternion (x, y, z, w)."""

    position_m: Vec3
    orientation_xyzw: Tuple[float, float, float, float]


def _vector(name: str, value: object, length: int) -> Tuple[float, ...]:
    try:
        items: Tuple[object, ...] = tuple(value) if isinstance(value, Iterable) else ()
    except TypeError:
        items = ()
    numbers = tuple(float(c) for c in items if is_finite_number(c, numpy=True))
    if len(items) != length or len(numbers) != length:
        raise SimArmError(f"{name} must be {length} finite numbers, got {value!r}")
    return numbers


@dataclass(frozen=True)
class SimArmConfig:
    """What the simulated arm judges against and where it starts; every number has a reason.

    * ``limits``: the robot's Cartesian limits (docs/lab-facts.md), judged every 1 ms.
    * ``timeout_s`` 0.1 s: the teleoperation node publishes at 50 Hz, so this is five
      missed messages -- long enough for a busy laptop, short enough that a dead node
      stops the arm within a tenth of a second.
    * ``workspace_min_m`` / ``workspace_max_m``: a box in the base frame in front of the
      Panda, inside its reach (about 0.855 m) and above the table, with room for a
      gripper at the ready pose.
    * ``start_position_m`` / ``start_orientation_xyzw``: the Panda's "ready" pose
      (joints 0, -pi/4, 0, -3pi/4, 0, pi/2, pi/4), the end effector pointing down:
      a rotation of pi about x, quaternion (1, 0, 0, 0).
    * ``stop_limits``: the ramp to zero after a timeout; ``None`` means ``limits``.
    * ``rel_tol``: relative tolerance of the judge, as ``limit_violations``'s.
    """

    limits: CartesianLimits = PANDA_LIMITS
    timeout_s: float = 0.1
    workspace_min_m: Vec3 = (0.2, -0.5, 0.05)
    workspace_max_m: Vec3 = (0.8, 0.5, 0.8)
    start_position_m: Vec3 = (0.3069, 0.0, 0.4867)
    start_orientation_xyzw: Tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    stop_limits: Optional[CartesianLimits] = None
    rel_tol: float = 1e-9

    def __post_init__(self) -> None:
        if not isinstance(self.limits, CartesianLimits):
            raise SimArmError(f"limits must be a CartesianLimits, got {type(self.limits).__name__}; "
                              "use hri_teleop.core.limits.PANDA_LIMITS")
        if self.stop_limits is not None and not isinstance(self.stop_limits, CartesianLimits):
            raise SimArmError(f"stop_limits must be a CartesianLimits or None, got {type(self.stop_limits).__name__}")
        if not is_positive_number(self.timeout_s):
            raise SimArmError(f"timeout_s must be a positive number of seconds, got {self.timeout_s!r}; e.g. 0.1")
        if not (is_finite_number(self.rel_tol) and 0.0 <= self.rel_tol < 1e-3):
            raise SimArmError(f"rel_tol must be in [0, 1e-3), got {self.rel_tol!r}; the default 1e-9 absorbs rounding")
        lo = _vector("workspace_min_m", self.workspace_min_m, 3)
        hi = _vector("workspace_max_m", self.workspace_max_m, 3)
        start = _vector("start_position_m", self.start_position_m, 3)
        quat = _vector("start_orientation_xyzw", self.start_orientation_xyzw, 4)
        for i, axis in enumerate(_AXES):
            if not lo[i] < hi[i]:
                raise SimArmError(f"workspace {axis}: min {lo[i]:g} m must be below max {hi[i]:g} m; "
                                  "swap or widen them")
            if not lo[i] <= start[i] <= hi[i]:
                raise SimArmError(f"start_position_m {axis} = {start[i]:g} m is outside the workspace "
                                  f"[{lo[i]:g}, {hi[i]:g}] m; move the start pose or widen the box")
        norm = math.sqrt(sum(c * c for c in quat))
        if abs(norm - 1.0) > 1e-6:
            raise SimArmError(f"start_orientation_xyzw must be a unit quaternion (x, y, z, w), got norm {norm:.9g}; "
                              "e.g. (1, 0, 0, 0) for the end effector pointing down")
        object.__setattr__(self, "workspace_min_m", lo)
        object.__setattr__(self, "workspace_max_m", hi)
        object.__setattr__(self, "start_position_m", start)
        object.__setattr__(self, "start_orientation_xyzw", tuple(c / norm for c in quat))
        object.__setattr__(self, "timeout_s", float(self.timeout_s))
        object.__setattr__(self, "rel_tol", float(self.rel_tol))
        try:  # the stop ramp must itself pass the judge
            TwistLimiter(self.effective_stop_limits, hard_limits=self.limits)
        except LimitsError as exc:
            raise SimArmError(f"stop_limits: {exc}") from None

    @property
    def effective_stop_limits(self) -> CartesianLimits:
        """The limits of the ramp to zero after a timeout."""
        return self.limits if self.stop_limits is None else self.stop_limits


def _stop_ramp(limits: CartesianLimits, hard: CartesianLimits, velocity: Sequence[float],
               acceleration: Sequence[float]) -> TwistLimiter:
    """A TwistLimiter that continues from ``velocity`` and ``acceleration`` (6 values each)."""
    limiter = TwistLimiter(limits, hard_limits=hard)
    limiter.reset(velocity, acceleration)
    return limiter


class SimArm:
    """The simulated arm: :meth:`command` it, :meth:`run_until` (or :meth:`step`) it, read it out.

    Times are seconds on the caller's clock; the arm never reads a clock.  The first
    cycle runs one ``ROBOT_PERIOD_S`` after ``start_time_s``.
    """

    def __init__(self, config: Optional[SimArmConfig] = None, *, start_time_s: float = 0.0) -> None:
        if config is None:
            config = SimArmConfig()
        if not isinstance(config, SimArmConfig):
            raise SimArmError(f"config must be a SimArmConfig, got {type(config).__name__}")
        if not is_finite_number(start_time_s):
            raise SimArmError(f"start_time_s must be a finite number of seconds, got {start_time_s!r}")
        self._config = config
        self._dt = ROBOT_PERIOD_S
        lim = config.limits
        tol = 1.0 + config.rel_tol
        # bound * (1 + rel_tol), computed as limit_violations computes it
        self._bounds = (
            lim.translation.velocity * tol, lim.translation.acceleration * tol, lim.translation.jerk * tol,
            lim.rotation.velocity * tol, lim.rotation.acceleration * tol, lim.rotation.jerk * tol,
        )
        self._lo = config.workspace_min_m
        self._hi = config.workspace_max_m
        self._time_s = float(start_time_s)
        self._position: Vec3 = config.start_position_m
        self._quat: Tuple[float, float, float, float] = config.start_orientation_xyzw
        self._held: Twist = _ZERO6           # the controller's command (zero-order hold)
        self._held_finite = True
        self._held_time_s: Optional[float] = None  # None: nothing received since start / recovery
        self._commanded: Twist = _ZERO6       # v_{k-1}: last command the robot accepted
        self._accel: Twist = _ZERO6           # a_{k-1}: its backward-Euler acceleration
        self._velocity: Twist = _ZERO6        # what the end effector did in the last cycle
        self._mode = _RUN                     # _RUN, STATE_TIMEOUT or STATE_REFLEX
        self._stopper: Optional[TwistLimiter] = None
        self._reflex_errors: Tuple[str, ...] = ()
        self._violations: List[LimitViolation] = []
        self._violation_counts: Dict[str, int] = {}
        self._events: List[ArmEvent] = []
        self._events_read = 0
        self._ignored = 0
        self._ignored_in_reflex = 0
        self._timeout_s = config.timeout_s
        self._wall = [False] * 6  # (x min, x max, y min, ...) in contact in the last cycle

    # --- inputs -----------------------------------------------------------------------

    @property
    def config(self) -> SimArmConfig:
        return self._config

    def command(self, twist: Sequence[float], now_s: float) -> bool:
        """Receive a velocity command ``(vx, vy, vz, wx, wy, wz)`` (m/s, rad/s, base frame) at ``now_s``.

        It is held until the next one and judged in every cycle.  Returns False if the
        arm is in a reflex and ignored it (counted, reported once per reflex).  A command
        with NaN or inf is accepted here and stops the arm in the next cycle, as libfranka
        refuses it only when the control loop hands it over.
        """
        if not is_finite_number(now_s, numpy=True):
            raise SimArmError(f"now_s must be a finite time in seconds, got {now_s!r}")
        try:
            values = tuple(float(c) for c in twist)
        except (TypeError, ValueError):
            raise SimArmError(f"twist must be 6 numbers (vx vy vz wx wy wz), got {twist!r}") from None
        if len(values) != 6:
            raise SimArmError(f"twist must have 6 values (vx vy vz in m/s, wx wy wz in rad/s), got {len(values)}")
        now_s = float(now_s)
        if self._mode == STATE_REFLEX:
            self._ignored += 1
            if self._ignored_in_reflex == 0:
                self._event(now_s, EVENT_IGNORED, "command ignored: the arm is in a reflex; call recover() "
                            "(franka_control's error_recovery action) before commanding again")
            self._ignored_in_reflex += 1
            return False
        self._held = values
        self._held_finite = all(math.isfinite(c) for c in values)
        self._held_time_s = now_s
        if self._mode == STATE_TIMEOUT:
            self._mode = _RUN
            self._stopper = None
        return True

    def recover(self, now_s: float) -> bool:
        """Clear a reflex (like franka's ErrorRecoveryAction); the arm starts again from rest.

        The held command is dropped: the next command is judged from rest.  Returns False
        (and does nothing) if there was no reflex.
        """
        if not is_finite_number(now_s, numpy=True):
            raise SimArmError(f"now_s must be a finite time in seconds, got {now_s!r}")
        if self._mode != STATE_REFLEX:
            return False
        errors = ", ".join(self._reflex_errors)
        self._mode = _RUN
        self._reflex_errors = ()
        self._ignored_in_reflex = 0
        self._event(float(now_s), EVENT_RECOVERED, f"recovered from reflex [{errors}]; the arm accepts commands again")
        return True

    # --- time -------------------------------------------------------------------------

    def step(self, now_s: float) -> None:
        """Run one 1 ms robot cycle stamped ``now_s`` (must be later than the last cycle)."""
        if not is_finite_number(now_s, numpy=True):
            raise SimArmError(f"now_s must be a finite time in seconds, got {now_s!r}")
        if not now_s > self._time_s:
            raise SimArmError(f"time must move forward: now_s {now_s!r} is not after the last cycle at "
                              f"{self._time_s!r} s; pass the simulation clock")
        self._cycle(float(now_s))

    def run_until(self, now_s: float) -> int:
        """Run every 1 ms cycle due up to and including ``now_s``; returns how many ran.

        Cycle ``k`` runs at ``t0 + k * ROBOT_PERIOD_S`` with ``t0`` the last cycle's time,
        so a caller with its own clock (a ROS node on sim time) just calls this with the
        current time.  A time at or before the last cycle runs nothing.
        """
        if not is_finite_number(now_s, numpy=True):
            raise SimArmError(f"now_s must be a finite time in seconds, got {now_s!r}")
        t0 = self._time_s
        dt = self._dt
        n = int(math.floor((float(now_s) - t0) / dt + 1e-6))
        cycle = self._cycle
        for k in range(1, n + 1):
            cycle(t0 + k * dt)
        return max(n, 0)

    # --- the 1 kHz cycle (plain floats: this runs 1000 times per simulated second) ------

    def _cycle(self, t: float) -> None:
        self._time_s = t
        mode = self._mode
        if mode == STATE_REFLEX:
            return
        dt = self._dt
        if mode != STATE_TIMEOUT and self._held_time_s is not None and t - self._held_time_s > self._timeout_s:
            self._begin_timeout(t)
            mode = STATE_TIMEOUT
        if mode == STATE_TIMEOUT:
            stopper = self._stopper
            if stopper is None:
                c = _ZERO6
            else:
                c = stopper.step(_ZERO6, dt)
                if not any(c):
                    self._stopper = None
        elif not self._held_finite:
            self._refuse_non_finite(t)
            return
        else:
            c = self._held

        # judge: backward Euler, as Control does (same operations as limit_violations)
        c0, c1, c2, c3, c4, c5 = c
        p0, p1, p2, p3, p4, p5 = self._commanded
        b0, b1, b2, b3, b4, b5 = self._accel
        a0 = (c0 - p0) / dt
        a1 = (c1 - p1) / dt
        a2 = (c2 - p2) / dt
        a3 = (c3 - p3) / dt
        a4 = (c4 - p4) / dt
        a5 = (c5 - p5) / dt
        j0 = (a0 - b0) / dt
        j1 = (a1 - b1) / dt
        j2 = (a2 - b2) / dt
        j3 = (a3 - b3) / dt
        j4 = (a4 - b4) / dt
        j5 = (a5 - b5) / dt
        sqrt = math.sqrt
        vt_max, at_max, jt_max, vr_max, ar_max, jr_max = self._bounds
        if (
            not sqrt(c0 * c0 + c1 * c1 + c2 * c2) <= vt_max
            or not sqrt(a0 * a0 + a1 * a1 + a2 * a2) <= at_max
            or not sqrt(j0 * j0 + j1 * j1 + j2 * j2) <= jt_max
            or not sqrt(c3 * c3 + c4 * c4 + c5 * c5) <= vr_max
            or not sqrt(a3 * a3 + a4 * a4 + a5 * a5) <= ar_max
            or not sqrt(j3 * j3 + j4 * j4 + j5 * j5) <= jr_max
        ):
            self._reflex(t, c, (a0, a1, a2, a3, a4, a5), (j0, j1, j2, j3, j4, j5))
            return
        self._commanded = c
        self._accel = (a0, a1, a2, a3, a4, a5)

        # integrate the position, inside the workspace box
        x, y, z = self._position
        lo, hi = self._lo, self._hi
        nx = x + c0 * dt
        ny = y + c1 * dt
        nz = z + c2 * dt
        v0, v1, v2 = c0, c1, c2
        wall = self._wall
        if nx < lo[0] or nx > hi[0] or ny < lo[1] or ny > hi[1] or nz < lo[2] or nz > hi[2] or any(wall):
            nx, v0 = self._clamp(t, 0, x, nx, c0)
            ny, v1 = self._clamp(t, 1, y, ny, c1)
            nz, v2 = self._clamp(t, 2, z, nz, c2)
        self._position = (nx, ny, nz)

        # integrate the orientation: q <- exp(w dt / 2) (x) q, w in the base frame
        w = sqrt(c3 * c3 + c4 * c4 + c5 * c5)
        if w > 0.0:  # (a tiny w can square to 0: then the rotation is below rounding anyway)
            half = 0.5 * w * dt
            s = math.sin(half) / w
            cw = math.cos(half)
            dx, dy, dz = c3 * s, c4 * s, c5 * s
            qx, qy, qz, qw = self._quat
            rx = cw * qx + qw * dx + (dy * qz - dz * qy)
            ry = cw * qy + qw * dy + (dz * qx - dx * qz)
            rz = cw * qz + qw * dz + (dx * qy - dy * qx)
            rw = cw * qw - (dx * qx + dy * qy + dz * qz)
            n = sqrt(rx * rx + ry * ry + rz * rz + rw * rw)
            self._quat = (rx / n, ry / n, rz / n, rw / n)
        self._velocity = (v0, v1, v2, c3, c4, c5)

    def _clamp(self, t: float, i: int, old: float, new: float, v: float) -> Tuple[float, float]:
        """Keep axis ``i`` inside the box; returns the new coordinate and the velocity applied."""
        lo, hi = self._lo[i], self._hi[i]
        for side, hit, bound in ((0, new < lo, lo), (1, new > hi, hi)):
            k = 2 * i + side
            if hit:
                if not self._wall[k]:
                    self._wall[k] = True
                    which = "min" if side == 0 else "max"
                    self._event(t, EVENT_WORKSPACE, f"workspace limit: {_AXES[i]} at its {which} {bound:g} m; "
                                f"the velocity out of the box ({v:+.3g} m/s) is not applied")
                return bound, (bound - old) / self._dt
            self._wall[k] = False
        return new, v

    def _begin_timeout(self, t: float) -> None:
        self._mode = STATE_TIMEOUT
        age = t - (self._held_time_s or 0.0)
        self._held = _ZERO6
        self._held_time_s = None
        moving = any(self._commanded) or any(self._accel)
        self._stopper = (
            _stop_ramp(self._config.effective_stop_limits, self._config.limits, self._commanded, self._accel)
            if moving else None
        )
        self._event(t, EVENT_TIMEOUT, f"command timeout: no velocity command for {age:.3f} s "
                    f"(> timeout_s {self._config.timeout_s:g} s); "
                    + ("ramping the velocity to zero inside the limits" if moving else "the arm was at rest"))

    def _reflex(self, t: float, v: Sequence[float], a: Sequence[float], j: Sequence[float]) -> None:
        found: List[LimitViolation] = []
        for g, group in enumerate(_GROUPS):
            lim = getattr(self._config.limits, group)
            bounds = self._bounds[3 * g: 3 * g + 3]
            for (what, vec), bound in zip((("velocity", v), ("acceleration", a), ("jerk", j)), bounds):
                n = math.sqrt(sum(c * c for c in vec[3 * g: 3 * g + 3]))
                if not n <= bound:
                    found.append(LimitViolation(t, LIBFRANKA_ERROR_FOR[what], group, n, getattr(lim, what)))
        self._abort(t, found)

    def _refuse_non_finite(self, t: float) -> None:
        bad = next(i for i, c in enumerate(self._held) if not math.isfinite(c))
        self._abort(t, [LimitViolation(t, NON_FINITE_COMMAND, _GROUPS[bad // 3], self._held[bad], math.inf)])

    def _abort(self, t: float, found: List[LimitViolation]) -> None:
        """The robot's reaction: motion aborted, velocity zero, errors reported, commands ignored."""
        self._violations.extend(found)
        names: List[str] = []
        for v in found:
            self._violation_counts[v.error] = self._violation_counts.get(v.error, 0) + 1
            if v.error not in names:
                names.append(v.error)
        self._reflex_errors = tuple(names)
        self._mode = STATE_REFLEX
        self._ignored_in_reflex = 0
        self._held = _ZERO6
        self._held_finite = True
        self._held_time_s = None
        self._commanded = self._accel = self._velocity = _ZERO6
        self._stopper = None
        details = "; ".join(f"{v.group} {v.value:.6g} > {v.limit:g}" for v in found)
        self._event(t, EVENT_REFLEX, f"{self.reflex_message} ({details})")

    def _event(self, t: float, kind: str, message: str) -> None:
        self._events.append(ArmEvent(t, kind, message))

    # --- read-outs ----------------------------------------------------------------------

    @property
    def time_s(self) -> float:
        """Time of the last cycle (``start_time_s`` before the first)."""
        return self._time_s

    @property
    def pose(self) -> ArmPose:
        """End-effector pose in the base frame (m, unit quaternion xyzw)."""
        return ArmPose(self._position, self._quat)

    @property
    def position_m(self) -> Vec3:
        return self._position

    @property
    def orientation_xyzw(self) -> Tuple[float, float, float, float]:
        return self._quat

    @property
    def velocity(self) -> Twist:
        """The end effector's velocity in the last cycle (m/s, rad/s): the command, less what a wall stopped."""
        return self._velocity

    @property
    def commanded_velocity(self) -> Twist:
        """The last command the robot accepted (m/s, rad/s), as the judge saw it."""
        return self._commanded

    @property
    def state(self) -> str:
        """``"reflex"``, ``"timeout"``, ``"moving"`` (a nonzero command) or ``"idle"``."""
        if self._mode in (STATE_REFLEX, STATE_TIMEOUT):
            return self._mode
        return STATE_MOVING if any(self._commanded) else STATE_IDLE

    @property
    def reflex_errors(self) -> Tuple[str, ...]:
        """The libfranka error names of the current reflex (empty when there is none)."""
        return self._reflex_errors

    @property
    def reflex_message(self) -> str:
        """The current reflex as libfranka words it ("" when there is none)."""
        if not self._reflex_errors:
            return ""
        names = ", ".join(f'"{name}"' for name in self._reflex_errors)
        return f"libfranka: Move command aborted: motion aborted by reflex! [{names}]"

    @property
    def violations(self) -> Tuple[LimitViolation, ...]:
        """Every limit violation so far, in order."""
        return tuple(self._violations)

    @property
    def violation_count(self) -> int:
        return len(self._violations)

    @property
    def violation_counts(self) -> Dict[str, int]:
        """Violations so far per libfranka error name."""
        return dict(self._violation_counts)

    @property
    def ignored_command_count(self) -> int:
        """Commands that arrived during a reflex and were ignored."""
        return self._ignored

    @property
    def events(self) -> Tuple[ArmEvent, ...]:
        """Every event so far, in order."""
        return tuple(self._events)

    def new_events(self) -> List[ArmEvent]:
        """The events since the last call (for a node that logs each one once)."""
        fresh = self._events[self._events_read:]
        self._events_read = len(self._events)
        return fresh

    @property
    def status(self) -> str:
        """One line for a status topic or a log: the state and what to do about it."""
        state = self.state
        if state == STATE_REFLEX:
            return f"reflex: {self.reflex_message}; call recover() (error recovery) to move again"
        if state == STATE_TIMEOUT:
            return (f"timeout: no velocity command for more than {self._config.timeout_s:g} s, the arm stopped; "
                    "send a command to move again")
        v = self._commanded
        return (f"{state}: |v| {math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2):.3f} m/s, "
                f"|w| {math.sqrt(v[3] ** 2 + v[4] ** 2 + v[5] ** 2):.3f} rad/s, "
                f"position ({self._position[0]:.4f}, {self._position[1]:.4f}, {self._position[2]:.4f}) m, "
                f"{len(self._violations)} limit violations")
