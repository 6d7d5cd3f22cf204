"""A simulated Franka Panda under a Cartesian velocity controller: moves and judges like the robot.

It takes the lab controller's twist, runs the robot's 1 kHz cycle on it (judge the twist with
:func:`hri_teleop.core.limits.limit_violations`' arithmetic, move the seven joints with the robot's
inverse kinematics and judge them too, reflex or integrate), refuses a command with libfranka's
error names, ramps to zero on a command timeout and clamps at the workspace box. Deterministic;
the model and its sources: docs/simulation.md.
"""

from __future__ import annotations

import ctypes
import math
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from hri_teleop.core.checks import is_finite_number
from hri_teleop.core.joints import JointVector
from hri_teleop.core.limits import ROBOT_PERIOD_S, CartesianLimits, Twist, TwistLimiter, Vec3
from hri_teleop.sim.arm_config import (
    ACCELERATION_DISCONTINUITY,
    AXES,
    EVENT_IGNORED,
    EVENT_RECOVERED,
    EVENT_REFLEX,
    EVENT_TIMEOUT,
    EVENT_WORKSPACE,
    LIBFRANKA_ERROR_FOR,
    NON_FINITE_COMMAND,
    STATE_IDLE,
    STATE_MOVING,
    STATE_REFLEX,
    STATE_TIMEOUT,
    VELOCITY_DISCONTINUITY,
    VELOCITY_LIMITS_VIOLATION,
    ArmEvent,
    ArmPose,
    LimitViolation,
    SimArmConfig,
    SimArmError,
)
from hri_teleop.sim.arm_kernel import STATE_SIZE, TRACE_WIDTH, doubles, kernel
from hri_teleop.sim.joint_motion import JointMotion, start_joints
from hri_teleop.sim.kinematics import KinematicsError

__all__ = [
    "SimArmError", "SimArmConfig", "SimArm", "LimitViolation", "ArmEvent", "ArmPose", "VELOCITY_LIMITS_VIOLATION",
    "VELOCITY_DISCONTINUITY", "ACCELERATION_DISCONTINUITY", "NON_FINITE_COMMAND", "LIBFRANKA_ERROR_FOR",
    "STATE_IDLE", "STATE_MOVING", "STATE_TIMEOUT", "STATE_REFLEX", "EVENT_REFLEX", "EVENT_TIMEOUT", "EVENT_WORKSPACE",
    "EVENT_RECOVERED", "EVENT_IGNORED",
]

_ZERO6: Twist = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
_RUN = "run"  # internal mode: following commands; the state read-out says idle or moving
_GROUPS = ("translation", "rotation")


def _rotation_matrix(q: Sequence[float]) -> np.ndarray:
    """The rotation of a unit quaternion (x, y, z, w)."""
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


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
        self._interpolate = config.controller == "interpolate"
        self._ramp_from: Twist = _ZERO6       # the controller's output when the held command arrived
        self._ramp_start_s = float(start_time_s)
        self._ramp_s = config.command_period_s
        self._arrived_s: Optional[float] = None  # the last command's arrival (its interval is the next ramp)
        self._reflex_violations: Tuple[LimitViolation, ...] = ()
        self._joints: Optional[JointMotion] = None
        if config.joints:
            try:
                start = start_joints(config.start_position_m, config.start_orientation_xyzw, config.joint_limits,
                                     config.model)
                self._joints = JointMotion(start, config.joint_limits, config.rel_tol, config.model)
            except KinematicsError as exc:
                raise SimArmError(f"start_position_m: {exc}") from None
        self._kernel = kernel()
        self._k_state = (ctypes.c_double * STATE_SIZE)()
        self._k_trace = (ctypes.c_double * (TRACE_WIDTH * 64))()
        self._k_params = doubles([self._dt, self._timeout_s, float(self._interpolate), *self._bounds, *self._lo,
                                  *self._hi, float(self._joints is not None)])
        self._k_joints: Optional[ctypes._Pointer[ctypes.c_double]] = None
        self._k_consts: Optional[ctypes._Pointer[ctypes.c_double]] = None
        if self._joints is not None:
            if self._joints.consts is None:
                self._kernel = None  # an arm the C does not know: every cycle in Python
            else:
                as_doubles = ctypes.POINTER(ctypes.c_double)
                self._k_joints = self._joints.state.ctypes.data_as(as_doubles)
                self._k_consts = self._joints.consts.ctypes.data_as(as_doubles)

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
        if self._interpolate:
            # The controller moves from where its output is now to the new command over the
            # interval since the last one (the first after rest: command_period_s).
            since = now_s - self._arrived_s if self._arrived_s is not None else self._config.command_period_s
            self._ramp_from = self._commanded
            under_way_end_s = self._ramp_start_s + self._ramp_s
            # from the next cycle on: a caller that commands first and runs the cycles up to now
            # after (a lock-step loop) gets them ramped, as a held command would reach them all
            self._ramp_start_s = min(now_s, self._time_s)
            # never shorter than the node's period: a message that comes late and the next on time
            # (a busy machine) must not turn into a ramp of a few ms; nor ending before the ramp under
            # way: commands a stalled subscriber hands over at once keep the first one's pace
            period = self._config.command_period_s
            ramp_s = min(max(since, period), 0.1) if since <= self._timeout_s else period
            self._ramp_s = max(ramp_s, under_way_end_s - self._ramp_start_s)
            self._arrived_s = now_s
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
        self._reflex_violations = ()
        self._arrived_s = None
        self._ramp_from = _ZERO6
        if self._joints is not None:
            self._joints.stop()
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
        n = int(math.floor((float(now_s) - self._time_s) / self._dt + 1e-6))
        self.run_cycles(n)
        return max(n, 0)

    def run_cycles(self, count: int, trace: Optional[List[float]] = None) -> None:
        """Run the next ``count`` cycles; with ``trace``, append the position (m) and velocity
        (m/s, rad/s) after each, 9 numbers per cycle (what the world's hand needs of the arm).

        The compiled cycle (:mod:`hri_teleop.sim.arm_kernel`) runs the cycles without an event;
        the Python cycle runs the others, and all of them where the C is not built.
        """
        t0 = self._time_s
        dt = self._dt
        k = 1
        run = self._kernel.run if self._kernel is not None else None
        while k <= count:
            if run is not None and self._mode == _RUN and self._held_finite:
                self._pack()
                buffer = self._trace_buffer(count - k + 1) if trace is not None else None
                after = run(self._k_state, self._k_params, self._k_joints, self._k_consts, t0, k, count, buffer)
                if after > k:
                    self._unpack()
                    if buffer is not None and trace is not None:
                        trace.extend(buffer[0:TRACE_WIDTH * (after - k)])
                    k = after
                    if k > count:
                        break
            self._cycle(t0 + k * dt)
            if trace is not None:
                trace.extend(self._position)
                trace.extend(self._velocity)
            k += 1

    def _trace_buffer(self, cycles: int) -> "ctypes.Array[ctypes.c_double]":
        if len(self._k_trace) < TRACE_WIDTH * cycles:
            self._k_trace = (ctypes.c_double * (TRACE_WIDTH * cycles))()
        return self._k_trace

    def _pack(self) -> None:
        """The Cartesian state into the C's array (arm_cycle.c's layout)."""
        held_time = self._held_time_s
        self._k_state[0:STATE_SIZE] = [
            self._time_s, *self._position, *self._quat, *self._held, math.nan if held_time is None else held_time,
            *self._commanded, *self._accel, *self._velocity, *self._ramp_from, self._ramp_start_s, self._ramp_s,
            *(1.0 if w else 0.0 for w in self._wall)]

    def _unpack(self) -> None:
        """What the C's cycles changed (the joints' state it changed in place)."""
        v = self._k_state[0:STATE_SIZE]
        self._time_s = v[0]
        self._position = (v[1], v[2], v[3])
        self._quat = (v[4], v[5], v[6], v[7])
        self._commanded = (v[15], v[16], v[17], v[18], v[19], v[20])
        self._accel = (v[21], v[22], v[23], v[24], v[25], v[26])
        self._velocity = (v[27], v[28], v[29], v[30], v[31], v[32])
        self._wall[:] = [w != 0.0 for w in v[41:47]]

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
        elif self._interpolate and t - self._ramp_start_s < self._ramp_s:
            s = max(0.0, (t - self._ramp_start_s) / self._ramp_s)  # a cycle before the command: still "from"
            f = self._ramp_from
            h = self._held
            c = (f[0] + s * (h[0] - f[0]), f[1] + s * (h[1] - f[1]), f[2] + s * (h[2] - f[2]),
                 f[3] + s * (h[3] - f[3]), f[4] + s * (h[4] - f[4]), f[5] + s * (h[5] - f[5]))
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
        # integrate the orientation: q <- exp(w dt / 2) (x) q, w in the base frame
        quat = self._quat
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
            quat = (rx / n, ry / n, rz / n, rw / n)

        # the joints: the robot's IK of the command is judged, then they follow the new pose
        joints = self._joints
        if joints is not None and (c != _ZERO6 or not joints.at_rest()):
            broken = joints.step(c, (nx, ny, nz), _rotation_matrix(quat), dt)
            if broken:
                self._abort(t, [LimitViolation(t, error, f"joint {joint}", value, limit)
                                for error, joint, value, limit in broken])
                return
        self._commanded = c
        self._accel = (a0, a1, a2, a3, a4, a5)
        self._position = (nx, ny, nz)
        self._quat = quat
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
                    self._event(t, EVENT_WORKSPACE, f"workspace limit: {AXES[i]} at its {which} {bound:g} m; "
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
        self._reflex_violations = tuple(found)
        if self._joints is not None:
            self._joints.stop()
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
    def joint_positions(self) -> Optional[JointVector]:
        """The seven joint angles (rad), as franka_state_controller publishes them (None: ``joints`` off)."""
        return self._joints.positions if self._joints is not None else None

    @property
    def joint_velocities(self) -> Optional[JointVector]:
        """What the joints did in the last cycle (rad/s; None: ``joints`` off)."""
        if self._joints is None:
            return None
        v = self._joints.velocity
        return (float(v[0]), float(v[1]), float(v[2]), float(v[3]), float(v[4]), float(v[5]), float(v[6]))

    @property
    def reflex_violations(self) -> Tuple[LimitViolation, ...]:
        """The limits the current reflex broke, with their values (empty when there is none)."""
        return self._reflex_violations

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
